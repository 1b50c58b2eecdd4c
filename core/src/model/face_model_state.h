// Exact (CGAL) state of a FaceModel, shared by the Boolean edits and the arrangement that types the lines.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

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
FT exact_decimal(double value_mm);

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
Ring to_ring(const ExactPolygon& poly);

// An exact point in doubles, read from its interval where that is exact (no lazy coordinate is
// built), else rounded from the exact value.
inline Point2 to_point2(const ExactPoint& p) {
  const auto& a = p.approx();
  return {a.x().is_point() ? a.x().inf() : CGAL::to_double(p.x()),
          a.y().is_point() ? a.y().inf() : CGAL::to_double(p.y())};
}

}  // namespace popcut::detail
