// Model readers from an already parsed JSON document, so a file is parsed once and dispatched by its tag.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "popcut/io/voxel_json.h"
#include "popcut/model/face_model.h"

namespace popcut {

VoxelFile voxel_file_from_json(const nlohmann::json& root, const std::string& source);
VoxelModel voxel_model_from_json(const nlohmann::json& root, const std::string& source);
FaceModel face_model_from_json(const nlohmann::json& root, const std::string& source);

}  // namespace popcut
