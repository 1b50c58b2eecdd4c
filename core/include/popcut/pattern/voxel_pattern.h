// Voxel model → unfolded pattern (voxel paper §2.3, §2.5): one unit cell per voxel face.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "popcut/model/voxel_model.h"
#include "popcut/pattern/pattern.h"

namespace popcut {

// The sheet as a grid of unit cells, each knowing its face, before regions and lines are drawn.
// Column c covers x in [c, c+1] voxels (model column c - side); row r covers v in [r - floor,
// r - floor + 1]. A face is packed as 2 t + (1 for HFace), t in voxels.
struct CellGrid {
  int columns = 0;
  int rows = 0;
  SheetVoxels sheet;
  double voxel_mm = 1;
  std::vector<std::uint32_t> faces;  // rows × columns, index r * columns + c

  std::uint32_t at(int c, int r) const {
    return faces[static_cast<std::size_t>(r) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(c)];
  }
  static std::uint32_t pack(FaceKind kind, int t) {
    return static_cast<std::uint32_t>(t) * 2u + (kind == FaceKind::horizontal ? 1u : 0u);
  }
  static FaceKind kind_of(std::uint32_t f) { return (f & 1u) ? FaceKind::horizontal : FaceKind::vertical; }
  static int t_of(std::uint32_t f) { return static_cast<int>(f >> 1); }
};

// The face of every cell of a valid model's sheet, with windows relocated (§2.3).
// Throws popcut::Error when the model is invalid or the sheet too small (`source` names the file).
CellGrid make_cell_grid(const VoxelModel& model, const std::string& source = "");

// The face of every cell in the strip of model slice x (outside 0..width-1: the bare boards),
// bottom row first: strip[r] covers v in [r - sheet.floor, r - sheet.floor + 1] voxels.
// The model must be valid; this is the column make_cell_grid writes, for incremental checks.
void slice_faces(const VoxelModel& model, const SheetVoxels& sheet, int x, std::vector<std::uint32_t>& strip);

// The region (pattern face index, as make_pattern numbers them) of every cell, index r * columns + c.
std::vector<int> cell_regions(const CellGrid& grid);

// Regions, typed lines and fold links of a cell grid, in millimetres.
Pattern make_pattern(const CellGrid& grid);

inline Pattern make_pattern(const VoxelModel& model, const std::string& source = "") {
  return make_pattern(make_cell_grid(model, source));
}

}  // namespace popcut
