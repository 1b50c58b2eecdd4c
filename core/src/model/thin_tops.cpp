// Thin top faces found per step and across slices, dropped lowest first under the incremental check.
#include "popcut/model/thin_tops.h"

#include <algorithm>
#include <tuple>
#include <vector>

#include "popcut/pattern/incremental_popup.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
namespace {

// One step of one slice: the columns [y_lo, y_hi) that are exactly z high.
struct Step {
  int x, z, y_lo, y_hi;
  int face = -1;  // the top face (steps joined across slices) it belongs to
};

std::vector<Step> steps_of(const VoxelModel& m, int x) {
  std::vector<Step> out;
  for (int y = 0; y < m.depth;) {
    const int z = m.h(x, y);
    if (z == 0) break;
    int end = y;
    while (end < m.depth && m.h(x, end) == z) ++end;
    out.push_back(Step{x, z, y, end});
    y = end;
  }
  return out;
}

}  // namespace

ThinTops drop_thin_tops(VoxelModel& m, int max_width_voxels, const std::string& source) {
  ThinTops out;
  if (max_width_voxels <= 0 || !check_popup(make_pattern(m, source)).pops_up()) return out;
  // Steps of neighbouring slices at one height with overlapping depths share their top face
  // (their cells meet side by side in the pattern); each face spans a run of slices.
  std::vector<std::vector<Step>> slices(static_cast<std::size_t>(m.width));
  std::vector<int> face_width;
  for (int x = 0; x < m.width; ++x) {
    slices[static_cast<std::size_t>(x)] = steps_of(m, x);
    for (Step& s : slices[static_cast<std::size_t>(x)]) {
      if (x > 0) {
        for (const Step& p : slices[static_cast<std::size_t>(x - 1)]) {
          if (p.z == s.z && p.y_lo < s.y_hi && s.y_lo < p.y_hi) s.face = p.face;
        }
      }
      if (s.face < 0) {
        s.face = static_cast<int>(face_width.size());
        face_width.push_back(0);
      }
      ++face_width[static_cast<std::size_t>(s.face)];
    }
  }
  std::vector<Step> thin;
  for (const auto& slice : slices) {
    for (const Step& s : slice) {
      if (face_width[static_cast<std::size_t>(s.face)] <= max_width_voxels) thin.push_back(s);
    }
  }
  std::sort(thin.begin(), thin.end(), [](const Step& a, const Step& b) { return std::tie(a.z, a.x) < std::tie(b.z, b.x); });
  IncrementalPopup card(m, source);
  for (const Step& s : thin) {
    if (card.try_drop_top(s.x, s.z)) {
      ++out.dropped;
    } else {
      ++out.kept;
    }
  }
  m = card.model();
  return out;
}

}  // namespace popcut
