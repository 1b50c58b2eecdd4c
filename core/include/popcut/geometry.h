// The geometry every layer shares: points in pattern (x, v) and card (x, y, z) coordinates, rings,
// rectangles, typed segments, and the two kinds of face plane (docs/architecture.md, "Geometry").
#pragma once

#include <vector>

#include "popcut/names.h"

namespace popcut {

enum class LineKind { cut, mountain, valley };
enum class FaceKind { vertical, horizontal };  // VFace (plane y = t) / HFace (plane z = t)

inline constexpr auto kLineKindNames =
    enum_names<LineKind>({{LineKind::cut, "cut"}, {LineKind::mountain, "mountain"}, {LineKind::valley, "valley"}});
inline constexpr auto kFaceKindNames =
    enum_names<FaceKind>({{FaceKind::vertical, "V"}, {FaceKind::horizontal, "H"}});  // as in the file formats
const char* to_string(LineKind kind);
const char* to_string(FaceKind kind);  // "V" / "H"

struct Point2 {
  double x_mm = 0;
  double v_mm = 0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

// x first, then v: the order that sorts equal points together.
inline bool lexicographic_less(Point2 a, Point2 b) { return a.x_mm < b.x_mm || (a.x_mm == b.x_mm && a.v_mm < b.v_mm); }

// Card coordinates at 90°: x across, y depth in front of the back wall, z height above the floor.
struct Point3 {
  double x_mm = 0;
  double y_mm = 0;
  double z_mm = 0;
  friend bool operator==(const Point3&, const Point3&) = default;
};

struct Rect {
  Point2 min;
  Point2 max;
  friend bool operator==(const Rect&, const Rect&) = default;
};

struct Segment {
  LineKind kind = LineKind::cut;
  Point2 a;
  Point2 b;
  friend bool operator==(const Segment&, const Segment&) = default;
};

using Ring = std::vector<Point2>;  // closed implicitly: the last point joins the first

// The 2D → 3D map of a face at 90° (docs/architecture.md, "Geometry"): VFace t: (x, t, v + t); HFace t: (x, t - v, t).
Point3 to_card(FaceKind kind, double t_mm, Point2 p);

double signed_area_mm2(const Ring& ring);

// Splits a ring that passes a vertex more than once (weakly simple: a region touching itself at
// a corner) into simple loops at each repeated vertex, so every ring handed on is simple.
std::vector<Ring> split_at_repeated_vertices(const Ring& ring);
Rect bounds(const Ring& ring);
// Whether p lies inside the ring (even-odd; a point on an edge may go either way).
bool inside_ring(Point2 p, const Ring& ring);

// A point inside a polygon with holes, for labels and reports: the middle of the widest inside
// stretch of a horizontal line halfway across the tallest band between vertex heights (never
// through a vertex). O(n log n), unlike a triangulation.
Point2 interior_point(const Ring& outer, const std::vector<Ring>& holes);

}  // namespace popcut
