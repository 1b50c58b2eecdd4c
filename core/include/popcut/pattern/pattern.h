// The unfolded pattern: a planar map of the sheet in pattern coordinates (x, v = z - y), in mm.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "popcut/names.h"

namespace popcut {

enum class LineKind { cut, mountain, valley };
enum class FaceKind { vertical, horizontal };  // VFace (plane y = t) / HFace (plane z = t)

inline constexpr auto kLineKindNames =
    enum_names<LineKind>({{LineKind::cut, "cut"}, {LineKind::mountain, "mountain"}, {LineKind::valley, "valley"}});
inline constexpr auto kFaceKindNames = enum_names<FaceKind>({{FaceKind::vertical, "V"}, {FaceKind::horizontal, "H"}});  // as in the file formats
const char* to_string(LineKind kind);
const char* to_string(FaceKind kind);  // "V" / "H"

struct Point2 {
  double x_mm = 0;
  double v_mm = 0;
  friend bool operator==(const Point2&, const Point2&) = default;
};

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

// One region of the sheet and the face it becomes: outer ring counter-clockwise in (x, v),
// holes clockwise. `label` is a point inside the region, for reports.
struct PatternFace {
  FaceKind kind = FaceKind::vertical;
  double t_mm = 0;
  Ring outer;
  std::vector<Ring> holes;
  Point2 label;
  friend bool operator==(const PatternFace&, const PatternFace&) = default;
};

// Two faces joined by a fold: `upper` lies above `lower` in the pattern (larger v).
struct FoldLink {
  int upper = -1;
  int lower = -1;
  LineKind kind = LineKind::valley;
  double length_mm = 0;
  friend bool operator==(const FoldLink&, const FoldLink&) = default;
};

// Lines are maximal straight segments (collinear touching pieces of one kind merged); the sheet
// outline is `sheet`, never a line. `back_face`/`floor_face` hold the sheet's top/bottom edge.
struct Pattern {
  Rect sheet;
  std::vector<Segment> lines;
  std::vector<PatternFace> faces;
  std::vector<FoldLink> folds;
  int back_face = -1;
  int floor_face = -1;
  friend bool operator==(const Pattern&, const Pattern&) = default;
};

// The 2D → 3D map of a face at 90° (docs/architecture.md, "Geometry"): VFace t: (x, t, v + t); HFace t: (x, t - v, t).
Point3 to_card(FaceKind kind, double t_mm, Point2 p);

// Line kind of an x-parallel edge at height v between the face above it and the face below it
// (same face: no line, returned as false). Folds where the two faces meet in 3D: VFace above
// HFace → valley, HFace above VFace → mountain; anything else is a cut.
bool classify_x_edge(FaceKind upper_kind, double upper_t, FaceKind lower_kind, double lower_t, double v,
                     double tolerance, LineKind& out);

double signed_area_mm2(const Ring& ring);

// Splits a ring that passes a vertex more than once (weakly simple: a region touching itself at
// a corner) into simple loops at each repeated vertex, so every ring handed on is simple.
std::vector<Ring> split_at_repeated_vertices(const Ring& ring);
Rect bounds(const Ring& ring);

struct LineCounts {
  int cut = 0;
  int mountain = 0;
  int valley = 0;
  double cut_mm = 0;
  double mountain_mm = 0;
  double valley_mm = 0;
};
LineCounts count_lines(const Pattern& pattern);

}  // namespace popcut
