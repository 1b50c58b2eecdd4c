// popcut.pattern.v1 JSON (read and write) and SVG for people and cutter software (docs/formats.md).
#pragma once

#include <string>

#include "popcut/pattern/pattern.h"

namespace popcut {

inline constexpr const char* kPatternFormat = "popcut.pattern.v1";

std::string to_pattern_json(const Pattern& pattern);
Pattern parse_pattern(const std::string& text, const std::string& source);

struct SvgOptions {
  bool shade_faces = false;  // fill VFaces and HFaces in two light greys, for reading a design
};

// Millimetre-sized SVG (width/height in mm, viewBox in mm, y pointing down the sheet): one group
// per kind: cut solid black, mountain red dash-dot, valley blue dashed, sheet outline thin grey.
std::string to_pattern_svg(const Pattern& pattern, const SvgOptions& options = {});

}  // namespace popcut
