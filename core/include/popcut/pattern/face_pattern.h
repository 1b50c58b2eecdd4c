// Face model → pattern (polygon paper §3.4, §3.6) and voxel model → face model.
#pragma once

#include <string>

#include "popcut/model/face_model.h"
#include "popcut/model/voxel_model.h"
#include "popcut/pattern/pattern.h"
#include "popcut/pattern/popup_check.h"

namespace popcut {

// Lines from the arrangement of all face boundaries (edges shared in part are split at each
// other's endpoints, Fig. 10); coplanar faces that touch are merged first, so every line
// separates two different planes. Throws popcut::Error when the faces do not tile the sheet.
Pattern make_pattern(const FaceModel& model, const std::string& source = "");

// A face model whose faces include pieces cut free of the sheet is bad input, not a card that
// merely fails to pop up: an edit put paper where nothing holds it. Throws popcut::Error
// (invalid_input) naming the edit (or the given face) that drew the first loose piece and where
// the piece lies; does nothing when `report` has no loose pieces.
void require_attached(const FaceModel& model, const Pattern& pattern, const PopupReport& report,
                      const std::string& source = "");

// The voxel model's faces as a face model: coplanar neighbouring cells merged into maximal polygons.
FaceModel to_face_model(const VoxelModel& model, const std::string& source = "");

}  // namespace popcut
