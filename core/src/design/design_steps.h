// The face edits each design item makes: how FaceDesign draws one item (its outline, mirror and tops, or its letters).
#pragma once

#include <string>
#include <vector>

#include "popcut/design/face_design.h"

namespace popcut::detail {

// One face edit an item makes; tops are named as such in errors.
struct Step {
  FaceEdit edit;
  bool top = false;
};

// The face edits `item` makes on `model`'s sheet, in the order they are drawn, its tops read off
// `behind` (the faces before it). Throws popcut::Error naming `where`.
std::vector<Step> steps_of(const DesignItem& item, const FaceModel& model, const std::string& where,
                           const std::vector<OAFace>& behind);

}  // namespace popcut::detail
