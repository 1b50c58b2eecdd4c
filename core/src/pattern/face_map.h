// Rules of the face map shared by the pattern and its test oracle: coplanar merging and line types.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <tuple>
#include <vector>

#include "model/face_model_state.h"
#include "popcut/pattern/pattern.h"

namespace popcut::detail {

class CoplanarGroups {
 public:
  explicit CoplanarGroups(const std::vector<std::shared_ptr<const ExactFace>>& faces)
      : faces_(faces), parent_(faces.size()) {
    for (std::size_t i = 0; i < parent_.size(); ++i) parent_[i] = static_cast<int>(i);
  }
  // Faces a and b meet along an edge (not just a corner): one face if they share a plane.
  void meet(int a, int b) {
    const ExactFace& l = *faces_[static_cast<std::size_t>(a)];
    const ExactFace& r = *faces_[static_cast<std::size_t>(b)];
    // Paper meant to drop out is cut from its plane's other paper, never joined to it.
    if (l.kind == r.kind && l.t == r.t && !l.drops_out && !r.drops_out)
      parent_[static_cast<std::size_t>(find(a))] = find(b);
  }
  // After every meet: the groups, numbered in order of their first face, with their faces.
  std::vector<std::vector<int>> members() {
    index_.assign(faces_.size(), -1);
    std::vector<std::vector<int>> out;
    for (std::size_t i = 0; i < faces_.size(); ++i) {
      int& index = index_[static_cast<std::size_t>(find(static_cast<int>(i)))];
      if (index < 0) {
        index = static_cast<int>(out.size());
        out.emplace_back();
      }
      out[static_cast<std::size_t>(index)].push_back(static_cast<int>(i));
    }
    return out;
  }
  // The group number of a face; valid after members().
  int group_of(int face) { return index_[static_cast<std::size_t>(find(face))]; }

 private:
  int find(int f) {
    while (parent_[static_cast<std::size_t>(f)] != f) {
      f = parent_[static_cast<std::size_t>(f)] =
          parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(f)])];
    }
    return f;
  }
  const std::vector<std::shared_ptr<const ExactFace>>& faces_;
  std::vector<int> parent_;
  std::vector<int> index_;
};

// The line between two different faces along an edge: `up` lies left of it (above, for an
// x-parallel edge at height v). Faces of two kinds meet in 3D on an x-parallel edge exactly when
// t_h - t_v = v (docs/architecture.md, "Geometry"): a fold, valley when the VFace is above, mountain when the HFace is.
// Anything else is a cut, as is every edge of paper meant to drop out.
inline LineKind line_between(const ExactFace& up, const ExactFace& lo, bool x_parallel, const FT& v) {
  if (!x_parallel || up.kind == lo.kind || up.drops_out || lo.drops_out) return LineKind::cut;
  const FT& tv = up.kind == FaceKind::vertical ? up.t : lo.t;
  const FT& th = up.kind == FaceKind::horizontal ? up.t : lo.t;
  if (th - tv != v) return LineKind::cut;
  return up.kind == FaceKind::vertical ? LineKind::valley : LineKind::mountain;
}

// The order make_pattern emits: x-parallel lines first, by v then x; the others by x, v; folds by faces.
inline void sort_lines_and_folds(Pattern& p) {
  std::sort(p.lines.begin(), p.lines.end(), [](const Segment& a, const Segment& b) {
    const bool ha = a.a.v_mm == a.b.v_mm, hb = b.a.v_mm == b.b.v_mm;
    if (ha != hb) return ha;
    return ha ? std::tie(a.a.v_mm, a.a.x_mm) < std::tie(b.a.v_mm, b.a.x_mm)
              : std::tie(a.a.x_mm, a.a.v_mm, a.b.x_mm) < std::tie(b.a.x_mm, b.a.v_mm, b.b.x_mm);
  });
  std::sort(p.folds.begin(), p.folds.end(), [](const FoldLink& a, const FoldLink& b) {
    return a.upper != b.upper ? a.upper < b.upper : a.lower < b.lower;
  });
}

}  // namespace popcut::detail
