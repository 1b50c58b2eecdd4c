// Exact (CGAL) state of a FaceModel, shared by the Boolean edits and the arrangement that types the lines.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <vector>

#include "popcut/model/face_model.h"

namespace popcut::detail {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = Kernel::FT;
using ExactPoint = Kernel::Point_2;
using ExactPolygon = CGAL::Polygon_2<Kernel>;
using ExactPolygonWithHoles = CGAL::Polygon_with_holes_2<Kernel>;

struct ExactFace {
  FaceKind kind = FaceKind::vertical;
  FT t;
  ExactPolygonWithHoles polygon;
  CGAL::Bbox_2 bbox;  // for skipping Booleans that cannot touch
};

struct FaceModelState {
  FT min_x, max_x, min_v, max_v;  // the sheet
  std::vector<ExactFace> faces;
};

// A ring in doubles for output, without the vertices where an exact Boolean left three
// points collinear (they carry no shape, only the history of other faces' edges).
inline Ring to_ring(const ExactPolygon& poly) {
  const auto& v = poly.container();
  const std::size_t n = v.size();
  Ring r;
  r.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (n > 3 && CGAL::collinear(v[(i + n - 1) % n], v[i], v[(i + 1) % n])) continue;
    r.push_back({CGAL::to_double(v[i].x()), CGAL::to_double(v[i].y())});
  }
  return r;
}

}  // namespace popcut::detail
