// Exact (CGAL) state of a FaceModel, shared by the Boolean edits and the arrangement that types the lines.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "popcut/model/face_model.h"

namespace popcut::detail {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = Kernel::FT;
using ExactPoint = Kernel::Point_2;
using ExactPolygon = CGAL::Polygon_2<Kernel>;
using ExactPolygonWithHoles = CGAL::Polygon_with_holes_2<Kernel>;

// Input lengths snap to a 1 nm grid and become exact rationals there, so the decimals people
// write (0.1, 1.1) and products like 3 × 0.3 = 0.8999999999999999 compare as intended
// (1.1 - 0.1 == 1 exactly, and a fold at v = 1 is found). 1 nm is far below any cutter's step.
inline FT exact_decimal(double value_mm) {
  // The rational itself (not a lazy quotient): to_double of it is then the nearest double, so
  // equal decimals give equal points downstream.
  static_assert(sizeof(long) >= 8, "nanometre counts need a 64-bit long");
  const long nm = std::lround(value_mm * 1e6);  // 1 nm = 1e-6 mm
  FT::ET q(nm, 1000000L);
  q.canonicalize();
  return FT(q);
}

struct ExactFace {
  FaceKind kind = FaceKind::vertical;
  FT t;
  ExactPolygonWithHoles polygon;
  CGAL::Bbox_2 bbox;  // for skipping Booleans that cannot touch
};

// Faces are shared between states: an edit copies pointers and replaces only the faces it
// touches, so undo history costs what the edits changed, not a copy of the card per edit.
struct FaceModelState {
  FT min_x, max_x, min_v, max_v;  // the sheet
  std::vector<std::shared_ptr<const ExactFace>> faces;
};

// A ring in doubles for output, without the vertices where an exact Boolean left three
// points collinear (they carry no shape, only the history of other faces' edges). A point the
// ring passes twice (a pinch) stays, or an edge would run through it.
inline Ring to_ring(const ExactPolygon& poly) {
  const auto& v = poly.container();
  const std::size_t n = v.size();
  std::map<ExactPoint, int> visits;
  for (const ExactPoint& p : v) ++visits[p];
  Ring r;
  r.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (n > 3 && visits[v[i]] == 1 && CGAL::collinear(v[(i + n - 1) % n], v[i], v[(i + 1) % n])) continue;
    r.push_back({CGAL::to_double(v[i].x()), CGAL::to_double(v[i].y())});
  }
  return r;
}

}  // namespace popcut::detail
