// Thin top faces found per step and joined across slices, each dropped as a whole, lowest first, under the incremental
// check.
#include "popcut/design/thin_tops.h"

#include <algorithm>
#include <tuple>
#include <vector>

#include "popcut/error.h"
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
  // A thin face goes as a whole or not at all: dropping part of it would leave a top narrower
  // than the face and the threshold meant. Faces are tried lowest first (then leftmost), so the
  // tallest of a run stays to hold the rest; within a face, slice by slice from the left, each
  // step judged by the incremental check, and undone in reverse when a later slice cannot go
  // (every undo returns to a state that popped up, so it cannot be refused).
  std::vector<std::vector<Step>> thin(face_width.size());
  for (const auto& slice : slices) {
    for (const Step& s : slice) {
      if (face_width[static_cast<std::size_t>(s.face)] <= max_width_voxels)
        thin[static_cast<std::size_t>(s.face)].push_back(s);
    }
  }
  std::vector<std::size_t> order;
  for (std::size_t f = 0; f < thin.size(); ++f) {
    if (!thin[f].empty()) order.push_back(f);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(thin[a].front().z, thin[a].front().x) < std::tie(thin[b].front().z, thin[b].front().x);
  });
  IncrementalPopup card(m, source);
  for (std::size_t f : order) {
    const std::vector<Step>& face = thin[f];
    std::size_t done = 0;
    while (done < face.size() && card.try_drop_top(face[done].x, face[done].z)) ++done;
    if (done == face.size()) {
      ++out.dropped;
      continue;
    }
    ++out.kept;
    while (done > 0) {
      --done;
      if (!card.try_drop_top(face[done].x, face[done].z, false)) {
        throw Error(ErrorCode::internal, source, "",
                    "thin tops: undoing a dropped top was refused by the pop-up check");
      }
    }
  }
  m = card.model();
  return out;
}

}  // namespace popcut
