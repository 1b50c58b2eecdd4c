// Model readers from an already parsed JSON document, so a file is parsed once and dispatched by its tag.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "popcut/design/face_design.h"
#include "popcut/io/voxel_json.h"
#include "popcut/model/face_model.h"
#include "popcut/pattern/pattern.h"

namespace popcut {

VoxelFile voxel_file_from_json(const nlohmann::json& root, const std::string& source);
VoxelModel voxel_model_from_json(const nlohmann::json& root, const std::string& source);
FaceModel face_model_from_json(const nlohmann::json& root, const std::string& source);
// popcut.design.v1 (design_json.cpp): a model file's readers parse it once and dispatch.
bool is_design_json(const nlohmann::json& root);
FaceDesign design_from_json(const nlohmann::json& root, const std::string& source);

namespace json_util {
class Reader;
}
// A card's "sheet": {"width", "back", "floor"} (mm, each > 0), as popcut.faces.v1 and
// popcut.design.v1 give it; and the same written back.
struct CardSheet {
  double width_mm = 0, back_mm = 0, floor_mm = 0;
};
CardSheet read_card_sheet(const json_util::Reader& in, const nlohmann::json& root);
std::string card_sheet_json(const Rect& sheet);

// One face object {"kind": "V"|"H", "t", "outer", "holes", "label"}, coordinates within ±limit_mm.
PatternFace read_face(const json_util::Reader& in, const nlohmann::json& face, const std::string& path,
                      double limit_mm);

}  // namespace popcut
