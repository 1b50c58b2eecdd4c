// The pop-up check's report as the CLI and the designer page show it: lines for people, popcut.validation.v1 JSON.
#pragma once

#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

#include "popcut/pattern/pattern.h"
#include "popcut/pattern/popup_check.h"

namespace popcut {

// popcut.validation.v1 (docs/formats.md) for the pattern `p` of the model named `source`.
nlohmann::json validation_json(const std::string& source, const Pattern& p, const PopupReport& report);

// "SOURCE: pops up (N faces; ...)" and a line per face that would not stand, flap or loose piece.
void print_validation(std::ostream& out, const std::string& source, const Pattern& p, const PopupReport& report);

}  // namespace popcut
