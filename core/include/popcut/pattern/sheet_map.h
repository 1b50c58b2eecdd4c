// A drawing as a planar map of the sheet (cut-and-fold paper §2): regions, and the typed edges between them.
#pragma once

#include <string>
#include <vector>

#include "popcut/geometry.h"
#include "popcut/io/drawing_io.h"

namespace popcut {

// One piece of the map's boundary between two regions (or a region and the outside, -1).
// `above`/`left` is the region on the left walking a → b; for an edge running +x that is the
// region above it. `drawn` indexes the drawing's line it lies on.
struct SheetEdge {
  DrawnKind kind = DrawnKind::cut;
  Point2 a;
  Point2 b;
  int left = -1;
  int right = -1;
  int drawn = -1;
};

// A region of the sheet bounded by lines: outer ring counter-clockwise, holes clockwise (slits
// that end inside the region are edges with the region on both sides, not part of any ring).
struct SheetRegion {
  Ring outer;
  std::vector<Ring> holes;
  double area_mm2 = 0;
  Point2 label;  // a point inside, for reports
};

struct SheetMap {
  Ring outline;  // the sheet's edge, counter-clockwise
  Rect bounds;
  std::vector<SheetRegion> regions;
  std::vector<SheetEdge> edges;
  int snapped_ends = 0;          // line ends moved onto a nearby end or line (within the tolerance)
  int overlaps_merged = 0;       // edges drawn more than once (a self-overlapping path, two layers)
  bool vertices_on_grid = true;  // every vertex exactly on the 1 nm grid (no crossing of slanted lines between)
  std::vector<std::string> notes;
};

struct SheetMapOptions {
  double snap_tolerance_mm = 0.01;  // ends this close to another end, or to a line, join it
};

// "(12.5, 40) mm": a place on the drawn sheet as every report about it writes one.
std::string describe_place(Point2 p);

// Builds the map with CGAL's arrangement (exact): snaps ends, splits at crossings and
// T-junctions, finds the regions with their holes. The sheet's edge is the `outline` lines,
// else the outer boundary of the cut lines, else the SVG page. Throws popcut::Error (naming the
// drawn element) for lines no convention classifies, lines outside the sheet, a fold on the
// sheet's edge, and lines of two kinds drawn over each other.
SheetMap build_sheet_map(const LineDrawing& drawing, const SheetMapOptions& options = {});

}  // namespace popcut
