// Repair (voxel paper §3.2 b, c): fill any occupancy into a valid staircase, optionally opening windows.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

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

// Outcome of opening candidate windows one by one.
struct WindowMarking {
  int added = 0;
  int rejected = 0;              // candidates dropped because the card would not pop up with them
  std::int64_t full_checks = 0;  // decisions the incremental check handed to check_popup
  std::int64_t work = 0;         // IncrementalPopupStats::segments_visited over all decisions
};

// Voxel paper §3.2 c): tries isHole(x, z) for every candidate row (`rows[x * height + z]` != 0
// with a front face) slice by slice, from the bottom row up, keeping each only while the card
// still pops up. The paper goes from the top down; bottom-up, an opening taller than the card is
// deep keeps its solid row where the floor stops holding the window paper, at the same height in
// every slice, so its sills line up (examples/meshes/arch.off: 2 sills held from one side instead
// of 8 at 40 across and 18 at 80; see docs/import.md). Each decision is IncrementalPopup's, so
// the work follows what a window can reach rather than the whole card. A card that does not pop
// up to begin with is left as it is (nothing can be judged on it).
WindowMarking mark_windows(VoxelModel& model, const std::vector<std::uint8_t>& rows, const std::string& source = "");

// Fills every cell behind and below a filled one (eq. 4's closure, done as eq. 7 row by row):
// the least filling that satisfies the staircase. Windows are tried row by row from the bottom
// of each slice up (mark_windows).
// `source` names the file in errors.
RepairResult repair(const VoxelFile& file, const RepairOptions& options, const std::string& source = "");

}  // namespace popcut
