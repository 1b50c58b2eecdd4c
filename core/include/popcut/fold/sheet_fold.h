// A drawn sheet folded rigidly along its creases (cut-and-fold paper §2): hinges, poses, closure and collisions.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "popcut/fold/fold.h"
#include "popcut/io/drawing_io.h"
#include "popcut/pattern/sheet_map.h"

namespace popcut {

// One straight fold between two regions of the map: every map edge of one crease line that joins
// the same two regions. The angle is the target dihedral turn, FOLD's sign: + valley (both sides
// rise toward +z, the drawing's viewer), − mountain, ±180 folded flat.
struct SheetHinge {
  int left = -1;   // the region on the left walking a → b
  int right = -1;  // the region on its right
  Point2 a, b;     // the hinge's extent on the sheet
  DrawnKind kind = DrawnKind::fold;
  double angle_deg = 0;
  int stage = 1;           // the motion turns stage 1's hinges first, then stage 2's, ...
  std::vector<int> edges;  // indices into SheetMap::edges
  std::string where;       // the drawn element it comes from
};

// What keeps a sheet from folding as drawn: where, which regions and hinges.
struct SheetProblem {
  std::string what;
  Point2 at;
  std::vector<int> regions;
  std::vector<int> hinges;
};

// The regions joined by hinges form pieces; each piece folds about its fixed region, which stays
// in the drawing's plane. The sheet's frame is right-handed: (x, v) as drawn, z toward the
// drawing's viewer.
struct FoldableSheet {
  std::string source;
  SheetMap map;
  std::vector<SheetHinge> hinges;
  std::vector<int> piece_of;     // per region
  std::vector<int> piece_fixed;  // per piece: its fixed region
  std::vector<bool> cut_out;     // per region: the inside of a closed cut, which falls out (no triangles)
  std::vector<std::vector<std::array<Point2, 3>>> triangles;  // per region, counter-clockwise
  std::vector<int> layer;              // per region, bottom up, once folded flat along lines (empty: one layer)
  std::vector<SheetProblem> problems;  // creases that cannot fold (inside one region, two angles on one hinge)
  std::vector<std::string> notes;
};

// The angle (and stage) of the creases a selector names: a drawn line's id (SVG id, DXF handle,
// FOLD edge index "edges[7]"), ids by prefix ("tab-*"), or a kind (mountain, valley, fold). A
// mountain or valley line takes the angle's size, its kind the direction; an undirected fold
// takes the sign as given.
struct CreaseAngle {
  std::string selector;
  double angle_deg = 0;
  int stage = 1;
};

// "SELECTOR=DEGREES" or "SELECTOR=DEGREES@STAGE" (--fold, popcutd's fold field); nullopt unless
// the whole text reads so. The angle's range is checked where the sheet is made.
std::optional<CreaseAngle> parse_crease_angle(const std::string& text);
inline constexpr const char* kCreaseAngleSyntax =
    "LINE=DEGREES or LINE=DEGREES@STAGE (LINE a line's id, DXF handle or FOLD edge, ids by prefix such as tab-*, or "
    "mountain, valley or fold; degrees from -180 to 180)";

struct SheetFoldOptions {
  double angle_deg = 90;            // the turn of creases that give none (FOLD's edges_foldAngle gives one)
  std::vector<CreaseAngle> angles;  // in order, the last naming a crease winning
  int fixed_region = -1;            // -1: each piece's largest region
};

// The motion's stages (the largest hinge stage, at least 1), and the share of its angle hinge `h`
// has turned by at `fraction` of the motion (see fold_sheet).
int stage_count(const FoldableSheet& sheet);
double hinge_progress(const SheetHinge& h, int stages, double fraction);

// Groups the map's crease edges into hinges with their angles, finds the pieces and triangulates
// every region (CGAL's constrained Delaunay, holes kept). Throws popcut::Error (invalid_input,
// naming the option) for a selector no line answers, an angle outside ±180 or a bad fixed region.
FoldableSheet make_foldable_sheet(const LineDrawing& drawing, SheetMap map, const SheetFoldOptions& options = {});

// A rigid motion of the plane z = 0 into space: p ↦ R p + t.
struct Pose {
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  Point3 t;
};
Point3 apply(const Pose& pose, Point2 p);

// Every region's pose at `fraction` of the motion (0 flat, 1 as asked): with K stages, stage k's
// hinges turn from flat to their angle while the fraction runs from (k−1)/K to k/K. The walk goes
// breadth-first over the hinge graph from each piece's fixed region. A hinge the walk did not take
// closes a cycle of regions; where it would put its region elsewhere than the walk did (by
// more than `closure_tolerance_mm`), the cycle's hinges are reported: their angles cannot all hold.
struct SheetState {
  double fraction = 1;
  std::vector<Pose> poses;                // per region
  std::vector<SheetProblem> open_cycles;  // closure failures
};
SheetState fold_sheet(const FoldableSheet& sheet, double fraction, double closure_tolerance_mm = 0.01);

// The folded sheet as triangles (region index in triangle_face) in card coordinates, (x, −y, z)
// of the sheet's frame as a card at 0° lies, for the OBJ, glTF, SVG and PNG writers; the
// drawing's side is the printed side. With `layer_gap_mm`, each region of a stack folded flat
// along lines sits that far per layer above the one below (along its own normal, so it stays
// rigid): for pictures, where coincident layers would speckle.
CardMesh sheet_mesh(const FoldableSheet& sheet, const SheetState& state, double layer_gap_mm = 0);

// Two regions passing through each other: triangles of different regions, each shrunk by
// `inset_mm` from its edges (so regions meeting along a hinge or at a corner do not count),
// crossing. Regions lying in one plane touch and stack (folded flat); they are not collisions.
struct SheetCollision {
  int region_a = -1;
  int region_b = -1;
  Point3 at;  // a point of the crossing
};
std::vector<SheetCollision> find_collisions(const FoldableSheet& sheet, const SheetState& state,
                                            double inset_mm = 0.05);

// The whole motion from flat to folded in `frames` steps (fractions 0, 1/(frames−1), ..., 1;
// 2 to 10,000 of them): the first fraction at which each cycle fails to close and each pair of
// regions collides. A crossing that begins and ends between two steps is not seen.
struct SheetMotionReport {
  struct Timed {
    SheetProblem problem;
    double fraction = 0;
  };
  int frames = 0;
  std::vector<Timed> open_cycles;
  std::vector<Timed> collisions;
  bool ok() const { return open_cycles.empty() && collisions.empty(); }
};
SheetMotionReport check_sheet_motion(const FoldableSheet& sheet, int frames);

// One fold of a flat-folded sheet along a line of its plane (the sheet's frame at z = 0, where the
// fixed region lies as drawn): everything left of a → b turns over onto the rest, or beneath it
// with `under`, through every layer the line crosses, as the cut-and-fold paper's multi-layer fold.
struct LineFoldStep {
  Point2 a, b;
  bool under = false;
};

// The drawing with the new creases (valley on layers facing up, mountain on those turned over,
// each ±180° in the next stage of the motion) and its sheet, whose `layer` keeps the stack's
// order: the moving stack lands on top (or beneath), reversed. Throws popcut::Error
// (invalid_input, "--fold-line") unless the sheet lies folded flat and the line crosses it, and
// when the sheet would have more than kMaxLineFoldRegions regions after the fold.
inline constexpr std::size_t kMaxLineFoldRegions = 20000;
struct SheetLineFold {
  LineDrawing drawing;
  FoldableSheet sheet;
};
SheetLineFold fold_along_line(const LineDrawing& drawing, const FoldableSheet& sheet, const LineFoldStep& step,
                              const SheetMapOptions& map = {});

// The sheet's lines as a pattern for the planner: cuts (the outer contour too, a dieline's shape)
// and creases as mountain/valley scores. A drawn sheet edge (outline lines, FOLD's boundary) is
// cut unless it is an upright rectangle: the blank itself.
Pattern sheet_pattern(const FoldableSheet& sheet);

}  // namespace popcut
