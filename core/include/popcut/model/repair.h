// Repair (voxel paper §3.2 b, c): fill any occupancy into a valid staircase, optionally opening windows.
#pragma once

#include <cstdint>

#include "popcut/io/voxel_json.h"
#include "popcut/model/voxel_model.h"

namespace popcut {

struct RepairOptions {
  // Mark rows where cells were filled as windows (eq. 5), keeping each only while the card
  // still pops up, so the filled bulk reads as openings rather than solid paper.
  bool windows = false;
};

struct RepairResult {
  VoxelModel model;
  std::int64_t cells_filled = 0;
  int windows_added = 0;
  int windows_rejected = 0;  // candidate windows dropped because the card would not pop up
};

// Work limit for window marking: candidate rows × pattern cells re-checked (about 10 s).
inline constexpr std::int64_t kMaxRepairWindowChecks = 100'000'000;

// Fills every cell behind and below a filled one (eq. 4's closure, done as eq. 7 row by row):
// the least filling that satisfies the staircase. Windows are tried row by row from the top of
// each slice down, as the paper does; each is checked with the full pop-up check, so the work
// grows as rows × cells and is refused (ErrorCode::limit) past kMaxRepairWindowChecks.
// `source` names the file in errors.
RepairResult repair(const VoxelFile& file, const RepairOptions& options, const std::string& source = "");

}  // namespace popcut
