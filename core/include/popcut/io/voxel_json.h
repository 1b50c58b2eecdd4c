// popcut.voxel.v1: reading and writing voxel models as JSON (docs/formats.md).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "popcut/model/voxel_model.h"

namespace popcut {

inline constexpr const char* kVoxelFormat = "popcut.voxel.v1";

// A voxel file as written, before the staircase rule is enforced: `model.heights` holds each
// column's top (which may break eq. 4). A file that lists "voxels" may leave empty cells under a
// column's top; they are counted here so `repair` can fill them and mark their rows.
struct VoxelFile {
  VoxelModel model;
  std::vector<std::uint8_t> gap_rows;  // width × height: some column of slice x is empty at row z under its top
  std::int64_t gap_cells = 0;
  std::optional<std::array<int, 3>> first_gap;  // the first empty cell under a filled one, for messages
};

// Parses the text of a voxel file; `source` names it in errors. Syntax, types, ranges, unknown
// fields and grid bounds are checked here; the staircase rule is not (see load_voxel_model).
VoxelFile parse_voxel_file(const std::string& text, const std::string& source);

// A valid model or popcut::Error naming the file and the field: the strict reader for commands
// that need a card that can be made.
VoxelModel parse_voxel_model(const std::string& text, const std::string& source);
VoxelModel load_voxel_model(const std::string& path);

// Writes every field, including the grid size, so the model reads back identical.
std::string to_voxel_json(const VoxelModel& model);

}  // namespace popcut
