// Staircase closure of a voxel occupancy and the greedy, check-guarded window marking of §3.2.
#include "popcut/model/repair.h"

#include <algorithm>
#include <vector>

#include "popcut/error.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
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

  const auto pops_up = [&](const VoxelModel& model) { return check_popup(make_pattern(model, source)).pops_up(); };
  std::int64_t candidates = 0;
  for (std::uint8_t f : filled_rows) candidates += f;
  const SheetVoxels sheet = resolve_sheet(m, source);
  const std::int64_t cells = (std::int64_t{m.width} + 2 * sheet.side) * (sheet.back + sheet.floor);
  if (candidates * cells > kMaxRepairWindowChecks) {
    throw Error(ErrorCode::limit, source, "--windows",
                "marking windows would re-check a card of " + std::to_string(cells) + " cells for each of " +
                    std::to_string(candidates) + " filled rows, over the limit of " + std::to_string(kMaxRepairWindowChecks) +
                    " cell checks; repair without --windows, or use fewer, larger voxels");
  }

  // Only a card that pops up before a window can judge the window; a card whose own windows
  // already fail is left as it is and reported by the caller's check.
  if (!pops_up(m)) return out;
  for (int x = 0; x < m.width; ++x) {
    for (int z = m.height - 1; z >= 0; --z) {
      if (!filled_rows[static_cast<std::size_t>(x) * static_cast<std::size_t>(m.height) + static_cast<std::size_t>(z)]) continue;
      if (m.is_window(x, z) || z >= m.h(x, 0)) continue;
      m.set_window(x, z, true);
      if (pops_up(m)) {
        ++out.windows_added;
      } else {
        m.set_window(x, z, false);
        ++out.windows_rejected;
      }
    }
  }
  return out;
}

}  // namespace popcut
