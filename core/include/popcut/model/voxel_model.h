// Voxel origamic-architecture model (voxel paper §2): staircase column heights, windows, sheet size.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace popcut {

// Documented limits: a grid axis, a sheet dimension, and the cells of a pattern.
inline constexpr int kMaxVoxelAxis = 4096;
inline constexpr int kMaxSheetVoxels = 8192;
// 2^22 cells: three times the sheet of a full 800 × 400 × 400 box. Measured worst case at the
// limit (every cell its own face): 1.6 GB peak, 17 s for a 1.4 GB pattern JSON.
inline constexpr std::int64_t kMaxPatternCells = std::int64_t{1} << 22;
inline constexpr double kMinVoxelMm = 0.01;
inline constexpr double kMaxVoxelMm = 1000.0;
// Margin added to the smallest enclosing card when the file leaves the sheet size out.
inline constexpr int kDefaultSheetMarginVoxels = 2;
inline constexpr int kDefaultSideVoxels = 2;

// Sheet size in voxels as the file gives it; an absent field takes its default.
struct SheetSpec {
  std::optional<int> back;   // height of the back half above the centre fold
  std::optional<int> floor;  // depth of the front half in front of the centre fold
  std::optional<int> side;   // empty columns added on each side
  friend bool operator==(const SheetSpec&, const SheetSpec&) = default;
};

// The sheet actually used for a pattern, every field decided.
struct SheetVoxels {
  int back = 0;
  int floor = 0;
  int side = 0;
};

// Grid width (x) × depth (y) × height (z). Column heights h(x, y) count cells filled from the
// floor up; a valid model has h non-increasing in y (eq. 4). is_window(x, z) is isHole (eq. 5).
struct VoxelModel {
  int width = 0;
  int depth = 0;
  int height = 0;
  double voxel_mm = 1.0;
  SheetSpec sheet;
  std::string name;
  std::vector<int> heights;           // width × depth, index x * depth + y
  std::vector<std::uint8_t> windows;  // width × height, index x * height + z
  // width × height (or empty: none), index x * height + z - 1: the top face at height z
  // (1 ≤ z ≤ height) of slice x is left out (§3.3); its paper lies on the face behind it
  // instead, as a window's does (see slice_faces).
  std::vector<std::uint8_t> dropped_tops;

  static VoxelModel empty(int width, int depth, int height, double voxel_mm);

  int h(int x, int y) const {
    return (y < 0 || y >= depth)
               ? 0
               : heights[static_cast<std::size_t>(x) * static_cast<std::size_t>(depth) + static_cast<std::size_t>(y)];
  }
  int& h_at(int x, int y) {
    return heights[static_cast<std::size_t>(x) * static_cast<std::size_t>(depth) + static_cast<std::size_t>(y)];
  }
  bool is_window(int x, int z) const {
    return z >= 0 && z < height &&
           windows[static_cast<std::size_t>(x) * static_cast<std::size_t>(height) + static_cast<std::size_t>(z)] != 0;
  }
  void set_window(int x, int z, bool on) {
    windows[static_cast<std::size_t>(x) * static_cast<std::size_t>(height) + static_cast<std::size_t>(z)] = on ? 1 : 0;
  }
  int window_count() const;
  bool is_top_dropped(int x, int z) const {
    return !dropped_tops.empty() && z >= 1 && z <= height &&
           dropped_tops[static_cast<std::size_t>(x) * static_cast<std::size_t>(height) +
                        static_cast<std::size_t>(z - 1)] != 0;
  }
  void set_top_dropped(int x, int z, bool on) {
    dropped_tops.resize(windows.size(), 0);
    dropped_tops[static_cast<std::size_t>(x) * static_cast<std::size_t>(height) + static_cast<std::size_t>(z - 1)] =
        on ? 1 : 0;
  }
  // Does slice x have a top face at height z (a column exactly z high, z ≥ 1)?
  bool has_top(int x, int z) const;

  friend bool operator==(const VoxelModel&, const VoxelModel&) = default;
};

// The first place where a model breaks a rule of the voxel paper, or nothing when it is valid.
struct ModelViolation {
  std::string field;    // e.g. "heights[3][2]" or "windows[1]"
  std::string message;  // what is wrong and what is expected
};
std::optional<ModelViolation> find_violation(const VoxelModel& model);

// Throws popcut::Error (invalid_input) naming `source` and the field when the model is invalid.
void require_valid(const VoxelModel& model, const std::string& source);

// The smallest back/floor (in voxels) that encloses the model when the card is closed: a point
// (y, z) lies at y + z from the fold when flat, so this is max(y + h(x, y) + 1) over filled columns.
int min_sheet_half_voxels(const VoxelModel& model);

// The sheet the pattern uses: given fields checked against the minimum, absent ones defaulted.
// Throws popcut::Error naming sheet.back / sheet.floor / sheet.side and the minimum.
SheetVoxels resolve_sheet(const VoxelModel& model, const std::string& source);

// Editor operations (§2.7); each keeps a valid model valid. Coordinates outside the grid throw.
// add: fills the voxel and every cell behind and below it.
void add_voxel(VoxelModel& model, int x, int y, int z);
// remove: clears the voxel and every cell in front of and above it; windows left above the
// column's new top (where there is no front face any more) are cleared with it.
void remove_voxel(VoxelModel& model, int x, int y, int z);
// toggle: flips isHole(x, z); the row must have a front face (z below the column's top).
void toggle_window(VoxelModel& model, int x, int z);

}  // namespace popcut
