// Exact (CGAL) state of a FaceModel, shared by the Boolean edits and the arrangement that types the lines.
#pragma once

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include <cmath>
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

// Exact coordinates count nanometres. Input lengths in mm snap to the 1 nm grid, so the decimals
// people write (0.1, 1.1) and products like 3 × 0.3 = 0.8999999999999999 compare as intended
// (1.1 - 0.1 == 1 exactly, and a fold at v = 1 is found), and the count is an integer, exact as a
// double: the kernel's interval filter then decides comparisons of grid points alone, where in mm
// a decimal like 0.7 (no double) sends every equality test to rationals. 1 nm is far below any
// cutter's step; |count| <= 1e11 (kMaxFaceCoordinateMm) < 2^53.
inline constexpr double kNmPerMm = 1e6;

inline double nm_count(double value_mm) { return static_cast<double>(std::llround(value_mm * kNmPerMm)); }
inline FT exact_nm(double value_mm) { return FT(nm_count(value_mm)); }
// A point in mm on the grid: built from the two counts at once (one lazy node, not three).
inline ExactPoint exact_point_nm(Point2 p) { return ExactPoint(nm_count(p.x_mm), nm_count(p.v_mm)); }

// A length held in nm, in mm: the nearest double for a grid value (read from its interval), within
// an ulp of it otherwise (rounded once to a double, once in the division).
inline double to_mm(const FT& nm) {
  const auto& a = nm.approx();
  return (a.is_point() ? a.inf() : CGAL::to_double(nm)) / kNmPerMm;
}

struct ExactFace {
  FaceKind kind = FaceKind::vertical;
  FT t;
  ExactPolygonWithHoles polygon;
  CGAL::Bbox_2 bbox;           // for skipping Booleans that cannot touch
  bool opening_paper = false;  // the paper of an opening (a hole's face): falls out when nothing holds it
  bool drops_out = false;      // an opening's paper cut all round (FaceEdit::drop): no fold, no merge
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

// An exact point (nm) in doubles (mm), read from its interval where that is exact (no lazy
// coordinate is built), else rounded from the exact value.
inline Point2 to_point2(const ExactPoint& p) {
  const auto& a = p.approx();
  return {(a.x().is_point() ? a.x().inf() : CGAL::to_double(p.x())) / kNmPerMm,
          (a.y().is_point() ? a.y().inf() : CGAL::to_double(p.y())) / kNmPerMm};
}

}  // namespace popcut::detail
