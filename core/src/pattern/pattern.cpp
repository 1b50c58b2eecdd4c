// What a pattern is made of beyond the shared geometry: the fold rule for x-parallel edges and line counts.
#include "popcut/pattern/pattern.h"

#include <cmath>

namespace popcut {

bool classify_x_edge(FaceKind upper_kind, double upper_t, FaceKind lower_kind, double lower_t, double v,
                     double tolerance, LineKind& out) {
  if (upper_kind == lower_kind && std::abs(upper_t - lower_t) <= tolerance) return false;
  // The edge is the 3D line through to_card(face, (0, v)) for each face; they meet when equal.
  const Point3 a = to_card(upper_kind, upper_t, {0, v});
  const Point3 b = to_card(lower_kind, lower_t, {0, v});
  const bool meet = std::abs(a.y_mm - b.y_mm) <= tolerance && std::abs(a.z_mm - b.z_mm) <= tolerance;
  if (!meet || upper_kind == lower_kind) {
    out = LineKind::cut;
  } else {
    out = upper_kind == FaceKind::vertical ? LineKind::valley : LineKind::mountain;
  }
  return true;
}

LineCounts count_lines(const Pattern& pattern) {
  LineCounts c;
  for (const Segment& s : pattern.lines) {
    const double len = std::hypot(s.b.x_mm - s.a.x_mm, s.b.v_mm - s.a.v_mm);
    switch (s.kind) {
      case LineKind::cut:
        ++c.cut;
        c.cut_mm += len;
        break;
      case LineKind::mountain:
        ++c.mountain;
        c.mountain_mm += len;
        break;
      case LineKind::valley:
        ++c.valley;
        c.valley_mm += len;
        break;
    }
  }
  return c;
}

}  // namespace popcut
