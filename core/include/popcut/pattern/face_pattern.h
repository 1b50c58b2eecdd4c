// Face model → pattern (polygon paper §3.4, §3.6) and voxel model → face model.
#pragma once

#include <string>

#include "popcut/model/face_model.h"
#include "popcut/model/voxel_model.h"
#include "popcut/pattern/pattern.h"

namespace popcut {

// Lines from the arrangement of all face boundaries (edges shared in part are split at each
// other's endpoints, Fig. 10); coplanar faces that touch are merged first, so every line
// separates two different planes. Throws popcut::Error when the faces do not tile the sheet.
Pattern make_pattern(const FaceModel& model, const std::string& source = "");

// The voxel model's faces as a face model: coplanar neighbouring cells merged into maximal polygons.
FaceModel to_face_model(const VoxelModel& model, const std::string& source = "");

}  // namespace popcut
