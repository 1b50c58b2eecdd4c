// Rigid folding of drawn sheets: a box dieline, FOLD's own diagonal fold, random strips, cycles and collisions.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "error_of.h"
#include "popcut/fold/sheet_fold.h"
#include "shared_testdata.h"

namespace popcut {
namespace {

using testing::error_of;

DrawnLine line(DrawnKind kind, std::vector<Point2> points, const std::string& where, bool closed = false) {
  return {kind, std::move(points), closed, where, "test", {}};
}

// An open box: base 40 × 30 at (20, 20), four walls 20 high, and a glue tab on each end of the
// front and back walls. Every crease is a score (`fold`), every other line a cut.
LineDrawing box() {
  LineDrawing d;
  d.source = "box";
  d.lines = {line(DrawnKind::cut,
                  {{20, 0},  {60, 0},  {60, 2},  {70, 4},  {70, 16}, {60, 18}, {60, 20}, {80, 20}, {80, 50}, {60, 50},
                   {60, 52}, {70, 54}, {70, 66}, {60, 68}, {60, 70}, {20, 70}, {20, 68}, {10, 66}, {10, 54}, {20, 52},
                   {20, 50}, {0, 50},  {0, 20},  {20, 20}, {20, 18}, {10, 16}, {10, 4},  {20, 2}},
                  "<path id=\"outline\">", true),
             line(DrawnKind::fold, {{20, 20}, {60, 20}}, "<line id=\"front\">"),
             line(DrawnKind::fold, {{20, 50}, {60, 50}}, "<line id=\"back\">"),
             line(DrawnKind::fold, {{20, 20}, {20, 50}}, "<line id=\"left\">"),
             line(DrawnKind::fold, {{60, 20}, {60, 50}}, "<line id=\"right\">"),
             line(DrawnKind::fold, {{20, 2}, {20, 18}}, "<line id=\"tab1\">"),
             line(DrawnKind::fold, {{60, 2}, {60, 18}}, "<line id=\"tab2\">"),
             line(DrawnKind::fold, {{20, 52}, {20, 68}}, "<line id=\"tab3\">"),
             line(DrawnKind::fold, {{60, 52}, {60, 68}}, "<line id=\"tab4\">")};
  return d;
}

FoldableSheet foldable(const LineDrawing& d, const SheetFoldOptions& o = {}) {
  return make_foldable_sheet(d, build_sheet_map(d), o);
}

int region_at(const FoldableSheet& s, Point2 p) {
  for (std::size_t r = 0; r < s.triangles.size(); ++r)
    for (const auto& t : s.triangles[r]) {
      const auto side = [&](Point2 a, Point2 b) {
        return (b.x_mm - a.x_mm) * (p.v_mm - a.v_mm) - (b.v_mm - a.v_mm) * (p.x_mm - a.x_mm);
      };
      if (side(t[0], t[1]) >= 0 && side(t[1], t[2]) >= 0 && side(t[2], t[0]) >= 0) return static_cast<int>(r);
    }
  return -1;
}

void expect_near(Point3 a, Point3 b, double tol, const std::string& what) {
  EXPECT_NEAR(a.x_mm, b.x_mm, tol) << what;
  EXPECT_NEAR(a.y_mm, b.y_mm, tol) << what;
  EXPECT_NEAR(a.z_mm, b.z_mm, tol) << what;
}

Point3 at(const FoldableSheet& s, const SheetState& st, Point2 p) {
  return apply(st.poses[static_cast<std::size_t>(region_at(s, p))], p);
}

TEST(SheetFold, TheBoxFoldsShutAndItsTabsLieOnTheSideWalls) {
  const FoldableSheet s = foldable(box());
  EXPECT_EQ(s.map.regions.size(), 9u);
  EXPECT_EQ(s.hinges.size(), 8u);
  ASSERT_EQ(s.piece_fixed.size(), 1u);
  EXPECT_EQ(s.piece_fixed[0], region_at(s, {40, 35}));  // the base, the largest region
  EXPECT_TRUE(s.problems.empty());
  const SheetState st = fold_sheet(s, 1);
  EXPECT_TRUE(st.open_cycles.empty());
  // The walls stand: the front wall's free corner rises straight above its foot.
  expect_near(at(s, st, {20, 0}), {20, 20, 20}, 1e-9, "front wall corner");
  expect_near(at(s, st, {0, 20}), {20, 20, 20}, 1e-9, "left wall corner");
  expect_near(at(s, st, {80, 50}), {60, 50, 20}, 1e-9, "right wall corner");
  // The tab turns inward onto the left wall: its tip lies inside the box, in the wall's plane.
  expect_near(at(s, st, {10, 4}), {20, 30, 16}, 1e-9, "front-left tab tip");
  expect_near(at(s, st, {70, 66}), {60, 40, 16}, 1e-9, "back-right tab tip");
}

// Folded all at once, each tab swings through the side wall it is glued to; walls first, then
// the tabs (stage 2), the box closes without a collision.
TEST(SheetFold, TabsFoldedWithTheWallsPassThroughThemAndAfterThemDoNot) {
  const FoldableSheet at_once = foldable(box());
  const SheetMotionReport r = check_sheet_motion(at_once, 13);
  EXPECT_TRUE(r.open_cycles.empty());
  ASSERT_EQ(r.collisions.size(), 4u);
  const int left_wall = region_at(at_once, {10, 35}), front_left_tab = region_at(at_once, {15, 10});
  EXPECT_EQ(r.collisions[0].problem.regions,
            (std::vector<int>{std::min(left_wall, front_left_tab), std::max(left_wall, front_left_tab)}));
  EXPECT_NE(r.collisions[0].problem.what.find("pass through each other at"), std::string::npos);
  SheetFoldOptions o;
  o.angles = {{"tab*", 90, 2}};
  const FoldableSheet staged = foldable(box(), o);
  EXPECT_EQ(stage_count(staged), 2);
  const SheetMotionReport ok = check_sheet_motion(staged, 25);
  EXPECT_TRUE(ok.ok());
  for (const auto& c : ok.collisions) ADD_FAILURE() << c.problem.what;
  // Halfway, the walls stand and the tabs are still flat with them.
  const SheetState half = fold_sheet(staged, 0.5);
  expect_near(at(staged, half, {10, 4}), {10, 20, 16}, 1e-9, "front-left tab tip at the stage change");
  expect_near(at(staged, fold_sheet(staged, 1), {10, 4}), {20, 30, 16}, 1e-9, "front-left tab tip");
}

TEST(SheetFold, FoldsAreRigidAtEveryFraction) {
  const FoldableSheet s = foldable(box());
  for (double f : {0.0, 0.25, 0.5, 0.77, 1.0}) {
    const SheetState st = fold_sheet(s, f);
    for (std::size_t r = 0; r < s.map.regions.size(); ++r) {
      const Ring& ring = s.map.regions[r].outer;
      for (std::size_t i = 0; i < ring.size(); ++i)
        for (std::size_t j = i + 1; j < ring.size(); ++j) {
          const Point3 a = apply(st.poses[r], ring[i]), b = apply(st.poses[r], ring[j]);
          const double d3 = std::hypot(a.x_mm - b.x_mm, a.y_mm - b.y_mm, a.z_mm - b.z_mm);
          const double d2 = std::hypot(ring[i].x_mm - ring[j].x_mm, ring[i].v_mm - ring[j].v_mm);
          EXPECT_NEAR(d3, d2, 1e-9);
        }
    }
  }
}

TEST(SheetFold, AMountainTurnsTheOtherWay) {
  SheetFoldOptions o;
  o.angles = {{"front", -90}};
  const FoldableSheet s = foldable(box(), o);
  const SheetState st = fold_sheet(s, 1);
  expect_near(at(s, st, {20, 0}), {20, 20, -20}, 1e-9, "front wall corner");
  o.angles = {{"fold", 45}};
  const FoldableSheet half = foldable(box(), o);
  const Point3 p = at(half, fold_sheet(half, 1), {40, 0});
  EXPECT_NEAR(p.z_mm, 20 * std::sin(M_PI / 4), 1e-9);
}

// Random strips: creases across a 200 mm strip, none crossing, with random angles. Every region
// keeps its shape, neighbours agree on their hinge, and no cycle exists to fail.
TEST(SheetFold, RandomStripsStayRigidAndJoined) {
  std::mt19937 rng(20);
  for (int trial = 0; trial < 150; ++trial) {
    std::uniform_real_distribution<double> v(1, 99), ang(-180, 180);
    const int n = 1 + static_cast<int>(rng() % 8);
    std::vector<double> left, right;
    for (int i = 0; i < n; ++i) left.push_back(v(rng)), right.push_back(v(rng));
    std::sort(left.begin(), left.end());
    std::sort(right.begin(), right.end());
    LineDrawing d;
    d.source = "strip";
    d.lines.push_back(line(DrawnKind::outline, {{0, 0}, {200, 0}, {200, 100}, {0, 100}}, "edge", true));
    SheetFoldOptions o;
    for (int i = 0; i < n; ++i) {
      const std::string id = "c" + std::to_string(i);
      d.lines.push_back(line(DrawnKind::fold,
                             {{0, left[static_cast<std::size_t>(i)]}, {200, right[static_cast<std::size_t>(i)]}},
                             "<line id=\"" + id + "\">"));
      o.angles.emplace_back(id, ang(rng));
    }
    const FoldableSheet s = foldable(d, o);
    ASSERT_EQ(s.hinges.size(), d.lines.size() - 1) << trial;
    const SheetState st = fold_sheet(s, std::uniform_real_distribution<double>(0, 1)(rng));
    EXPECT_TRUE(st.open_cycles.empty());
    for (const SheetHinge& h : s.hinges)
      for (Point2 p : {h.a, h.b})
        expect_near(apply(st.poses[static_cast<std::size_t>(h.left)], p),
                    apply(st.poses[static_cast<std::size_t>(h.right)], p), 1e-9,
                    "hinge end, trial " + std::to_string(trial));
  }
}

// Four regions around one crease vertex: the line through it may fold while the crossing line
// stays flat; two different angles on its halves cannot both hold, and the cycle is named.
LineDrawing cross() {
  LineDrawing d;
  d.source = "cross";
  d.lines = {line(DrawnKind::outline, {{0, 0}, {100, 0}, {100, 100}, {0, 100}}, "edge", true),
             line(DrawnKind::valley, {{0, 50}, {50, 50}}, "<line id=\"west\">"),
             line(DrawnKind::valley, {{50, 50}, {100, 50}}, "<line id=\"east\">"),
             line(DrawnKind::mountain, {{50, 0}, {50, 50}}, "<line id=\"south\">"),
             line(DrawnKind::valley, {{50, 50}, {50, 100}}, "<line id=\"north\">")};
  return d;
}

TEST(SheetFold, AConsistentCycleClosesAndAnInconsistentOneIsReported) {
  SheetFoldOptions o;
  o.angles = {{"west", 70}, {"east", 70}, {"south", 0}, {"north", 0}};
  EXPECT_TRUE(fold_sheet(foldable(cross(), o), 1).open_cycles.empty());
  o.angles = {{"west", 70}, {"east", 40}, {"south", 0}, {"north", 0}};
  const SheetState bad = fold_sheet(foldable(cross(), o), 1);
  ASSERT_EQ(bad.open_cycles.size(), 1u);
  EXPECT_EQ(bad.open_cycles[0].hinges.size(), 4u);
  EXPECT_EQ(bad.open_cycles[0].regions.size(), 4u);
  EXPECT_NE(bad.open_cycles[0].what.find("cannot all hold"), std::string::npos) << bad.open_cycles[0].what;
  // Folded in quarters, as a square of paper is: closed at the end, open on the way.
  o.angles = {{"west", 180}, {"east", 180}, {"south", -180}, {"north", 180}};
  const FoldableSheet quarters = foldable(cross(), o);
  EXPECT_TRUE(fold_sheet(quarters, 1).open_cycles.empty());
  EXPECT_FALSE(fold_sheet(quarters, 0.5).open_cycles.empty());
  EXPECT_FALSE(check_sheet_motion(quarters, 5).open_cycles.empty());
}

// Three panels in a row with both outer ones folding over the middle: narrow flaps pass each
// other, wide ones collide near the end of the motion.
LineDrawing flaps(double width) {
  LineDrawing d;
  d.source = "flaps";
  d.lines = {line(DrawnKind::outline, {{0, 0}, {40 + 2 * width, 0}, {40 + 2 * width, 30}, {0, 30}}, "edge", true),
             line(DrawnKind::valley, {{width, 0}, {width, 30}}, "<line id=\"l\">"),
             line(DrawnKind::valley, {{width + 40, 0}, {width + 40, 30}}, "<line id=\"r\">")};
  return d;
}

TEST(SheetFold, FlapsThatMeetOverTheMiddleCollide) {
  SheetFoldOptions o;
  o.angle_deg = 180;
  EXPECT_TRUE(check_sheet_motion(foldable(flaps(15), o), 19).ok());
  const FoldableSheet wide = foldable(flaps(30), o);
  const SheetMotionReport r = check_sheet_motion(wide, 19);
  ASSERT_EQ(r.collisions.size(), 1u);
  EXPECT_GT(r.collisions[0].fraction, 0.5);
  EXPECT_LT(r.collisions[0].fraction, 1.0);
  const int left = region_at(wide, {5, 5}), right = region_at(wide, {95, 5});
  EXPECT_EQ(r.collisions[0].problem.regions, (std::vector<int>{std::min(left, right), std::max(left, right)}));
  // Closed flat, the layers lie in one plane: stacked, not a collision.
  EXPECT_TRUE(find_collisions(wide, fold_sheet(wide, 1)).empty());
}

TEST(SheetFold, ACreaseEndingInsideARegionIsReported) {
  LineDrawing d = flaps(15);
  d.lines.push_back(line(DrawnKind::mountain, {{25, 10}, {45, 10}}, "<line id=\"stub\">"));
  const FoldableSheet s = foldable(d);
  ASSERT_EQ(s.problems.size(), 1u);
  EXPECT_NE(s.problems[0].what.find("stub"), std::string::npos) << s.problems[0].what;
  EXPECT_NE(s.problems[0].what.find("lies on both sides of the crease"), std::string::npos);
}

// A window cut in a flap: its inside falls out (no triangles, no collisions), the flap folds,
// and a hole drawn as the sheet's edge (FOLD's boundary around it) is cut all the same.
TEST(SheetFold, AWindowsInsideFallsOutAndItsEdgeIsCut) {
  for (DrawnKind edge : {DrawnKind::cut, DrawnKind::outline}) {
    LineDrawing d = flaps(15);
    d.lines.push_back(line(edge, {{20, 10}, {30, 10}, {30, 20}, {20, 20}}, "<rect id=\"window\">", true));
    const FoldableSheet s = foldable(d);
    int inside = -1;
    for (std::size_t r = 0; r < s.map.regions.size(); ++r)
      if (bounds(s.map.regions[r].outer) == Rect{{20, 10}, {30, 20}}) inside = static_cast<int>(r);
    ASSERT_GE(inside, 0);
    EXPECT_TRUE(s.cut_out[static_cast<std::size_t>(inside)]);
    EXPECT_EQ(region_at(s, {25, 15}), -1);  // no triangles: nothing is drawn there
    EXPECT_GE(region_at(s, {35, 15}), 0);
    ASSERT_FALSE(s.notes.empty());
    EXPECT_NE(s.notes[0].find("1 cut-out(s) fall out"), std::string::npos) << s.notes[0];
    const LineCounts c = count_lines(sheet_pattern(s));
    EXPECT_NEAR(c.cut_mm, 40, 1e-9) << to_string(edge);  // the window, and not the rectangular blank
  }
}

// Equal regions: the fixed one is the one with most hinges, whatever order the map lists them in.
TEST(SheetFold, TheBoxStandsOnItsBaseNotItsEqualLid) {
  LineDrawing d = box();
  d.lines.push_back(line(DrawnKind::fold, {{20, 70}, {60, 70}}, "<line id=\"lid\">"));
  d.lines[0].points[14] = {60, 100};  // the back wall's top edge becomes a lid 40 × 30, as large as the base
  d.lines[0].points[15] = {20, 100};
  const FoldableSheet s = foldable(d);
  EXPECT_EQ(s.piece_fixed[0], region_at(s, {40, 35}));
}

// A strip folded in half and in half again, as a person folds paper: the second fold goes
// through both layers, valley on the one facing up and mountain on the one turned over, and the
// stack's order is the paper's.
TEST(SheetFold, FoldingAlongALineFoldsEveryLayerItCrosses) {
  LineDrawing d;
  d.source = "strip";
  d.lines = {line(DrawnKind::outline, {{0, 0}, {100, 0}, {100, 20}, {0, 20}}, "edge", true)};
  const FoldableSheet flat = foldable(d);
  const SheetLineFold half = fold_along_line(d, flat, {{50, 0}, {50, 20}});
  ASSERT_EQ(half.sheet.hinges.size(), 1u);
  EXPECT_DOUBLE_EQ(half.sheet.hinges[0].angle_deg, 180);
  const SheetLineFold quarter = fold_along_line(half.drawing, half.sheet, {{75, 0}, {75, 20}});
  const FoldableSheet& s = quarter.sheet;
  ASSERT_EQ(s.map.regions.size(), 4u);
  ASSERT_EQ(s.hinges.size(), 3u);
  std::map<double, std::pair<double, int>> creases;  // x on the sheet → angle, stage
  for (const SheetHinge& h : s.hinges) creases[h.a.x_mm] = {h.angle_deg, h.stage};
  EXPECT_EQ(creases[50], std::pair(180.0, 1));
  EXPECT_EQ(creases[75], std::pair(180.0, 2));   // on the layer facing up: valley
  EXPECT_EQ(creases[25], std::pair(-180.0, 2));  // on the layer turned over: mountain
  // Everything lands on world [75, 100], rigidly, with the cycle-free motion closing.
  const SheetState st = fold_sheet(s, 1);
  EXPECT_TRUE(st.open_cycles.empty());
  const Point3 ref = at(s, st, {90, 10});
  for (double x : {60.0, 10.0, 40.0}) expect_near(at(s, st, {x, 10}), ref, 1e-9, "x " + std::to_string(x));
  // Bottom up: [75, 100] as it lay, [0, 25], [25, 50], and on top [50, 75].
  const auto layer = [&](double x) { return s.layer[static_cast<std::size_t>(region_at(s, {x, 10}))]; };
  EXPECT_LT(layer(90), layer(10));
  EXPECT_LT(layer(10), layer(40));
  EXPECT_LT(layer(40), layer(60));
  // The stack moves as one in stage 2: no layer passes through another.
  EXPECT_TRUE(check_sheet_motion(s, 25).ok());
  // Under instead of over: the folded half goes beneath, so its crease turns the other way.
  const SheetLineFold under = fold_along_line(d, flat, {{50, 0}, {50, 20}, true});
  EXPECT_DOUBLE_EQ(under.sheet.hinges[0].angle_deg, -180);
  // A line that misses the sheet, or a sheet that is not flat, is refused with the option named.
  EXPECT_EQ(error_of([&] { fold_along_line(d, flat, {{200, 0}, {200, 20}}); }).location(), "--fold-line");
  SheetFoldOptions o;
  o.angles = {{"front", 90}};
  const LineDrawing b = box();
  const Error e = error_of([&] { fold_along_line(b, foldable(b, o), {{0, 10}, {80, 10}}); });
  EXPECT_NE(e.message().find("needs the sheet folded flat"), std::string::npos) << e.message();
}

// A fold along a line through a stack of more layers than popcut folds is refused before the
// map is built again, naming the option and the limit.
TEST(SheetFold, AFoldLineThatWouldMakeTooManyRegionsIsRefused) {
  LineDrawing d;
  d.source = "fan";
  const int creases = 10001;
  d.lines = {line(DrawnKind::outline, {{0, 0}, {creases + 1.0, 0}, {creases + 1.0, 20}, {0, 20}}, "edge", true)};
  for (int i = 1; i <= creases; ++i) d.lines.push_back(line(DrawnKind::fold, {{i * 1.0, 0}, {i * 1.0, 20}}, "c"));
  SheetFoldOptions o;
  o.angle_deg = 0;  // every crease flat: a sheet of 10,002 regions lying in the plane
  const FoldableSheet flat = foldable(d, o);
  ASSERT_EQ(flat.map.regions.size(), 10002u);
  const Error e = error_of([&] { fold_along_line(d, flat, {{0, 10}, {creases + 1.0, 10}}); });
  EXPECT_EQ(e.location(), "--fold-line") << e.message();
  EXPECT_NE(e.message().find("20004 regions, more than the 20000 popcut folds"), std::string::npos) << e.message();
}

TEST(SheetFold, BadOptionsNameTheOption) {
  SheetFoldOptions o;
  o.angles = {{"nosuch", 30}};
  Error e = error_of([&] { foldable(box(), o); });
  EXPECT_EQ(e.location(), "--fold");
  EXPECT_NE(e.message().find("nosuch"), std::string::npos);
  o.angles = {{"front", 200}};
  EXPECT_EQ(error_of([&] { foldable(box(), o); }).location(), "--fold");
  o.angles = {{"front", 20, 0}};
  EXPECT_NE(error_of([&] { foldable(box(), o); }).message().find("stage must be from 1 to 100"), std::string::npos);
  o = {};
  o.fixed_region = 40;
  e = error_of([&] { foldable(box(), o); });
  EXPECT_EQ(e.location(), "--fixed");
  EXPECT_NE(e.message().find("0 to 8"), std::string::npos) << e.message();
  o = {};
  o.angle_deg = std::nan("");
  EXPECT_EQ(error_of([&] { foldable(box(), o); }).location(), "--crease-angle");
}

TEST(SheetFold, TheDielineCutsItsOutlineAndScoresItsCreases) {
  const Pattern p = sheet_pattern(foldable(box()));
  const LineCounts c = count_lines(p);
  EXPECT_EQ(c.valley, 8);  // each crease one maximal line
  EXPECT_NEAR(c.valley_mm, 40 + 40 + 30 + 30 + 4 * 16, 1e-9);
  EXPECT_NEAR(c.cut_mm, 2 * (40 + 30) + 4 * 20 + 8 * 2 + 8 * std::hypot(10, 2) + 4 * 12, 1e-9);
}

// The FOLD specification's diagonal fold: its crease pattern folded to its foldAngle lands where
// the specification's folded form (written by fold-convert) puts the vertices.
TEST(SheetFold, FoldSpecsDiagonalFoldsAsTheSpecFoldsIt) {
  const auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in) << "missing " << path;
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  POPCUT_NEEDS_SHARED_TESTDATA();
  const std::string dir = popcut::testing::shared_testdata("fold/");
  const LineDrawing d = read_fold_drawing(slurp(dir + "diagonal-cp.fold"), "diagonal-cp.fold");
  SheetFoldOptions o;
  const SheetMap map = build_sheet_map(d);
  FoldableSheet s = make_foldable_sheet(d, map, o);
  o.fixed_region = region_at(s, {0.1, 0.5});  // the face the folded form keeps in place
  s = make_foldable_sheet(d, map, o);
  ASSERT_EQ(s.hinges.size(), 1u);
  EXPECT_DOUBLE_EQ(std::abs(s.hinges[0].angle_deg), 180);
  const SheetState st = fold_sheet(s, 1);
  const double unit = map.bounds.max.x_mm - map.bounds.min.x_mm;
  expect_near(at(s, st, {unit * 0.999, unit * 0.999}), {0.001 * unit, 0.001 * unit, 0}, 1e-9, "vertex 2");
  // A valley lifts the moving face toward the viewer on the way.
  EXPECT_GT(at(s, fold_sheet(s, 0.5), {unit * 0.9, unit * 0.9}).z_mm, 0);
}

}  // namespace
}  // namespace popcut
