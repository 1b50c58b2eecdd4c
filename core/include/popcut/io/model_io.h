// Any model file (voxel or face), chosen by its "format" tag, and the face model's own format.
#pragma once

#include <string>
#include <variant>

#include "popcut/model/face_model.h"
#include "popcut/model/voxel_model.h"
#include "popcut/pattern/pattern.h"

namespace popcut {

inline constexpr const char* kFacesFormat = "popcut.faces.v1";

using AnyModel = std::variant<VoxelModel, FaceModel>;

// Parses a popcut.voxel.v1 or popcut.faces.v1 document; errors name `source` and the field.
AnyModel parse_model(const std::string& text, const std::string& source);
// Drawings (.svg, .dxf, .fold) read as OA cards; CardConflictError when no card folds from one.
AnyModel load_model(const std::string& path);

FaceModel parse_face_model(const std::string& text, const std::string& source);
// Writes the edit list when the model has one (so it replays identically), else the faces.
std::string to_face_json(const FaceModel& model, const std::string& name = "");

Pattern make_pattern(const AnyModel& model, const std::string& source = "");

}  // namespace popcut
