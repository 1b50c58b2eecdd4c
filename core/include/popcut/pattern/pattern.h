// The unfolded pattern: a planar map of the sheet in pattern coordinates (x, v = z - y), in mm.
#pragma once

#include <vector>

#include "popcut/geometry.h"

namespace popcut {

// One region of the sheet and the face it becomes: outer ring counter-clockwise in (x, v),
// holes clockwise. `label` is a point inside the region, for reports.
struct PatternFace {
  FaceKind kind = FaceKind::vertical;
  double t_mm = 0;
  Ring outer;
  std::vector<Ring> holes;
  Point2 label;
  // The paper inside an opening (a hole drawn in a face): where nothing holds it, it falls out
  // as the opening is cut, which is no fault of the card.
  bool opening_paper = false;
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

// Line kind of an x-parallel edge at height v between the face above it and the face below it
// (same face: no line, returned as false). Folds where the two faces meet in 3D: VFace above
// HFace → valley, HFace above VFace → mountain; anything else is a cut.
bool classify_x_edge(FaceKind upper_kind, double upper_t, FaceKind lower_kind, double lower_t, double v,
                     double tolerance, LineKind& out);

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
