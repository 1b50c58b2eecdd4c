// Voxel model rules (staircase eq. 4, windows eq. 5), sheet sizing and the editor operations of §2.7.
#include "popcut/model/voxel_model.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
namespace {

std::string format_mm(double mm) { return format_decimal(mm, 3); }

std::string cell_name(int x, int y) { return "heights[" + std::to_string(x) + "][" + std::to_string(y) + "]"; }

void require_in_grid(const VoxelModel& m, int x, int y, int z, const char* what) {
  if (x < 0 || x >= m.width || y < 0 || y >= m.depth || z < 0 || z >= m.height) {
    throw Error(ErrorCode::invalid_input, "", what,
                "voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) +
                    ") is outside the grid " + std::to_string(m.width) + " x " + std::to_string(m.depth) + " x " +
                    std::to_string(m.height));
  }
}

// Windows are only meaningful on rows that have a front face: z below the column's top at the back.
void clear_windows_above_top(VoxelModel& m, int x) {
  for (int z = std::max(0, m.h(x, 0)); z < m.height; ++z) m.set_window(x, z, false);
}

// A dropped top names a step of the slice; an edit that removes the step removes the mark.
void clear_missing_tops(VoxelModel& m, int x) {
  for (int z = 1; z <= m.height; ++z) {
    if (m.is_top_dropped(x, z) && !m.has_top(x, z)) m.set_top_dropped(x, z, false);
  }
}

}  // namespace

VoxelModel VoxelModel::empty(int width, int depth, int height, double voxel_mm) {
  VoxelModel m;
  m.width = width;
  m.depth = depth;
  m.height = height;
  m.voxel_mm = voxel_mm;
  m.heights.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(depth), 0);
  m.windows.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0);
  m.dropped_tops.assign(m.windows.size(), 0);
  return m;
}

bool VoxelModel::has_top(int x, int z) const {
  if (z < 1) return false;
  for (int y = 0; y < depth; ++y) {
    if (h(x, y) == z) return true;
    if (h(x, y) < z) return false;  // heights fall towards the front
  }
  return false;
}

int VoxelModel::window_count() const {
  return static_cast<int>(std::count(windows.begin(), windows.end(), std::uint8_t{1}));
}

std::optional<ModelViolation> find_violation(const VoxelModel& m) {
  if (!(m.voxel_mm >= kMinVoxelMm && m.voxel_mm <= kMaxVoxelMm)) {
    return ModelViolation{"voxel_mm", "must be a number from " + format_mm(kMinVoxelMm) + " to " +
                                          format_mm(kMaxVoxelMm) + " (millimetres per voxel)"};
  }
  for (int x = 0; x < m.width; ++x) {
    for (int y = 0; y < m.depth; ++y) {
      const int hy = m.h(x, y);
      if (hy < 0 || hy > m.height) {
        return ModelViolation{cell_name(x, y), "must be from 0 to the grid height " + std::to_string(m.height)};
      }
      if (y > 0 && hy > m.h(x, y - 1)) {
        return ModelViolation{
            cell_name(x, y),
            std::to_string(hy) + " is higher than " + cell_name(x, y - 1) + " = " + std::to_string(m.h(x, y - 1)) +
                ": a column may not be taller than the one behind it (the staircase rule, voxel paper "
                "eq. 4), or the card could not fold flat; 'popcut repair' fills the model to satisfy it"};
      }
    }
    for (int z = 0; z < m.height; ++z) {
      if (m.is_window(x, z) && z >= m.h(x, 0)) {
        return ModelViolation{
            "windows", "window [" + std::to_string(x) + ", " + std::to_string(z) +
                           "] is on row z=" + std::to_string(z) + " but column x=" + std::to_string(x) + " is only " +
                           std::to_string(m.h(x, 0)) + " high, so that row has no front face to open"};
      }
    }
    for (int z = 1; z <= m.height; ++z) {
      if (m.is_top_dropped(x, z) && !m.has_top(x, z)) {
        return ModelViolation{
            "dropped_tops", "top [" + std::to_string(x) + ", " + std::to_string(z) + "]: slice x=" + std::to_string(x) +
                                " has no column exactly " + std::to_string(z) +
                                " high, so there is no top face at z=" + std::to_string(z) + " to drop"};
      }
    }
  }
  return std::nullopt;
}

void require_valid(const VoxelModel& model, const std::string& source) {
  if (auto v = find_violation(model)) throw Error(ErrorCode::invalid_input, source, v->field, v->message);
}

int min_sheet_half_voxels(const VoxelModel& m) {
  int need = 0;
  for (int x = 0; x < m.width; ++x) {
    for (int y = 0; y < m.depth; ++y) {
      const int hy = m.h(x, y);
      if (hy > 0) need = std::max(need, y + hy + 1);
    }
  }
  return need;
}

SheetVoxels resolve_sheet(const VoxelModel& m, const std::string& source) {
  const int need = min_sheet_half_voxels(m);
  // y + h + 1 is at most (kMaxVoxelAxis - 1) + kMaxVoxelAxis + 1, so every model fits a sheet half.
  static_assert(kMaxSheetVoxels >= 2 * kMaxVoxelAxis);
  // The margin never pushes a default past the limit the model itself fits in.
  const int fallback = std::min(std::max(need, 1) + kDefaultSheetMarginVoxels, kMaxSheetVoxels);
  SheetVoxels s;
  s.back = m.sheet.back.value_or(fallback);
  s.floor = m.sheet.floor.value_or(fallback);
  s.side = m.sheet.side.value_or(kDefaultSideVoxels);
  auto check_half = [&](const char* field, int value) {
    if (value < 1 || value > kMaxSheetVoxels) {
      throw Error(
          ErrorCode::invalid_input, source, field,
          std::to_string(value) + " is out of range: expected 1 to " + std::to_string(kMaxSheetVoxels) + " voxels");
    }
    if (value < need) {
      throw Error(ErrorCode::invalid_input, source, field,
                  std::to_string(value) + " voxels is too small for this model: the card must be at least " +
                      std::to_string(need) + " voxels (" + format_mm(need * m.voxel_mm) +
                      " mm) to enclose it when closed (the largest y + height + 1 over the columns)");
    }
  };
  check_half("sheet.back", s.back);
  check_half("sheet.floor", s.floor);
  if (s.side < 0 || s.side > kMaxVoxelAxis) {
    throw Error(ErrorCode::invalid_input, source, "sheet.side",
                std::to_string(s.side) + " is out of range: expected 0 to " + std::to_string(kMaxVoxelAxis));
  }
  const std::int64_t cells = (std::int64_t{m.width} + 2 * std::int64_t{s.side}) * (std::int64_t{s.back} + s.floor);
  if (cells > kMaxPatternCells) {
    throw Error(ErrorCode::limit, source, "sheet",
                "the pattern would have " + std::to_string(cells) + " cells; the limit is " +
                    std::to_string(kMaxPatternCells) + " (use fewer, larger voxels or a smaller sheet)");
  }
  return s;
}

void add_voxel(VoxelModel& m, int x, int y, int z) {
  require_in_grid(m, x, y, z, "add_voxel");
  for (int yy = 0; yy <= y; ++yy) m.h_at(x, yy) = std::max(m.h(x, yy), z + 1);
  clear_missing_tops(m, x);
}

void remove_voxel(VoxelModel& m, int x, int y, int z) {
  require_in_grid(m, x, y, z, "remove_voxel");
  for (int yy = y; yy < m.depth; ++yy) m.h_at(x, yy) = std::min(m.h(x, yy), z);
  clear_windows_above_top(m, x);
  clear_missing_tops(m, x);
}

void toggle_window(VoxelModel& m, int x, int z) {
  require_in_grid(m, x, 0, z, "toggle_window");
  if (z >= m.h(x, 0)) {
    throw Error(ErrorCode::invalid_input, "", "toggle_window",
                "row z=" + std::to_string(z) + " of column x=" + std::to_string(x) +
                    " has no front face (the column is " + std::to_string(m.h(x, 0)) + " high)");
  }
  m.set_window(x, z, !m.is_window(x, z));
}

}  // namespace popcut
