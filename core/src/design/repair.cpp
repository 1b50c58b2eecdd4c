// Staircase closure of a voxel occupancy and the greedy, check-guarded window marking of §3.2.
#include "popcut/design/repair.h"

#include <algorithm>
#include <vector>

#include "popcut/error.h"
#include "popcut/pattern/incremental_popup.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {

WindowMarking mark_windows(VoxelModel& m, const std::vector<std::uint8_t>& rows, const std::string& source) {
  WindowMarking out;
  // Only a card that pops up before a window can judge the window; a card whose own windows
  // already fail is left as it is and reported by the caller's check.
  if (!check_popup(make_pattern(m, source)).pops_up()) return out;
  IncrementalPopup card(m, source);
  for (int x = 0; x < m.width; ++x) {
    // Bottom row first: tall openings keep their solid rows at one height, so sills line up (repair.h).
    for (int z = 0; z < m.height; ++z) {
      if (!rows[static_cast<std::size_t>(x) * static_cast<std::size_t>(m.height) + static_cast<std::size_t>(z)])
        continue;
      if (card.model().is_window(x, z) || z >= m.h(x, 0)) continue;
      if (card.try_window(x, z)) {
        ++out.added;
      } else {
        ++out.rejected;
      }
    }
  }
  out.full_checks = card.stats().full_checks;
  out.work = card.stats().segments_visited;
  m = card.model();
  return out;
}

RepairResult repair(const VoxelFile& file, const RepairOptions& options, const std::string& source) {
  RepairResult out;
  out.model = file.model;
  VoxelModel& m = out.model;
  out.cells_filled = file.gap_cells;
  std::vector<std::uint8_t> filled_rows = file.gap_rows;
  filled_rows.resize(m.windows.size(), 0);
  for (int x = 0; x < m.width; ++x) {
    int running = 0;  // the tallest column at or in front of y
    for (int y = m.depth - 1; y >= 0; --y) {
      const int top = m.h(x, y);
      running = std::max(running, top);
      for (int z = top; z < running; ++z) {
        filled_rows[static_cast<std::size_t>(x) * static_cast<std::size_t>(m.height) + static_cast<std::size_t>(z)] = 1;
      }
      out.cells_filled += running - top;
      m.h_at(x, y) = running;
    }
  }
  if (!options.windows || out.cells_filled == 0) return out;

  const WindowMarking marked = mark_windows(m, filled_rows, source);
  out.windows_added = marked.added;
  out.windows_rejected = marked.rejected;
  return out;
}

}  // namespace popcut
