// The voxel paper's own cases: the simplest box (Fig. 1/3), a window (Fig. 4/5), Fig. 8's failures.
#include "popcut/pattern/voxel_pattern.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "pattern_oracle.h"
#include "popcut/pattern/popup_check.h"

namespace popcut {
namespace {

VoxelModel box(int w, int d, int h, int side = 1, int half = 6) {
  VoxelModel m = VoxelModel::empty(w, d, h, 1.0);
  for (int x = 0; x < w; ++x)
    for (int y = 0; y < d; ++y) m.h_at(x, y) = h;
  m.sheet = {half, half, side};
  return m;
}

bool has_line(const Pattern& p, LineKind kind, Point2 a, Point2 b) {
  return std::any_of(p.lines.begin(), p.lines.end(), [&](const Segment& s) {
    return s.kind == kind && ((s.a == a && s.b == b) || (s.a == b && s.b == a));
  });
}

int count_kind(const Pattern& p, FaceKind kind, double t) {
  return static_cast<int>(std::count_if(p.faces.begin(), p.faces.end(),
                                        [&](const PatternFace& f) { return f.kind == kind && f.t_mm == t; }));
}

TEST(VoxelPattern, SimplestBox) {
  // 3 wide, 2 deep, 3 high, one empty column each side: back wall, top, front, floor.
  const Pattern p = make_pattern(box(3, 2, 3));
  EXPECT_EQ(p.sheet, (Rect{{0, -6}, {5, 6}})) << "sheet: 5 columns, 6 voxels each half";
  EXPECT_EQ(p.faces.size(), 4u) << "back wall, floor, top HFace, front VFace";
  EXPECT_TRUE(has_line(p, LineKind::valley, {1, 3}, {4, 3})) << "back wall meets the top at 90°: valley (Table 1)";
  EXPECT_TRUE(has_line(p, LineKind::mountain, {1, 1}, {4, 1})) << "top meets the front at 270°: mountain";
  EXPECT_TRUE(has_line(p, LineKind::valley, {1, -2}, {4, -2})) << "front meets the floor at 90°: valley";
  EXPECT_TRUE(has_line(p, LineKind::valley, {0, 0}, {1, 0})) << "centre fold left of the box";
  EXPECT_TRUE(has_line(p, LineKind::valley, {4, 0}, {5, 0})) << "centre fold right of the box";
  EXPECT_TRUE(has_line(p, LineKind::cut, {1, -2}, {1, 3})) << "left side of the box is one maximal cut";
  EXPECT_TRUE(has_line(p, LineKind::cut, {4, -2}, {4, 3})) << "right side of the box is one maximal cut";
  EXPECT_EQ(p.lines.size(), 7u) << "no other lines: the centre fold inside the box is a 180° (no line)";
  EXPECT_TRUE(check_popup(p).pops_up()) << "a box always pops up";
}

TEST(VoxelPattern, WindowOpensTheFrontFaceAndAddsALedge) {
  VoxelModel m = box(3, 1, 3);
  m.set_window(1, 1, true);  // middle column, middle row
  const Pattern p = make_pattern(m);
  // The front VFace (depth 1) keeps the window cell as a hole; the cell becomes an HFace
  // at height 1 (h' = 0, the row below) lying at depth cell 0 (eq. in §2.3).
  const auto front = std::find_if(p.faces.begin(), p.faces.end(),
                                  [](const PatternFace& f) { return f.kind == FaceKind::vertical && f.t_mm == 1; });
  ASSERT_NE(front, p.faces.end()) << "the front face exists";
  EXPECT_EQ(front->holes.size(), 1u) << "the window is a hole in the front face";
  EXPECT_EQ(count_kind(p, FaceKind::horizontal, 1), 1) << "one ledge at height 1";
  EXPECT_TRUE(has_line(p, LineKind::mountain, {2, 0}, {3, 0})) << "ledge folds down into the front face below it";
  EXPECT_TRUE(has_line(p, LineKind::cut, {2, 1}, {3, 1})) << "top of the window is cut";
  EXPECT_TRUE(has_line(p, LineKind::cut, {2, 0}, {2, 1})) << "left side of the window is cut";
  EXPECT_TRUE(has_line(p, LineKind::cut, {3, 0}, {3, 1})) << "right side of the window is cut";
  EXPECT_TRUE(check_popup(p).pops_up()) << "a window framed by the front face pops up";
}

TEST(VoxelPattern, TallWindowFoldsBackOntoTheBackWall) {
  // Fig. 5 (b): rows 1 and 2 open on a 1-deep, 1-wide box; the ledge runs out of depth and
  // continues up the back wall, where it joins the wall beside the box.
  VoxelModel m = box(1, 1, 3);
  m.set_window(0, 1, true);
  m.set_window(0, 2, true);
  const CellGrid g = make_cell_grid(m);
  const int c = 1;  // model column 0
  EXPECT_EQ(g.at(c, 6 + 1), CellGrid::pack(FaceKind::vertical, 0)) << "v in [1,2] lies on the back wall";
  EXPECT_EQ(g.at(c, 6 + 0), CellGrid::pack(FaceKind::horizontal, 1)) << "v in [0,1] is the ledge at height 1";
  const Pattern p = make_pattern(g);
  EXPECT_TRUE(has_line(p, LineKind::valley, {1, 1}, {2, 1})) << "ledge meets the back wall: valley";
  const PopupReport r = check_popup(p);
  EXPECT_TRUE(r.pops_up()) << "the window pops up";
  ASSERT_EQ(r.flaps.size(), 1u) << "the roof is held only by its fold to the back wall";
  EXPECT_EQ(p.faces[static_cast<std::size_t>(r.flaps[0].face)].t_mm, 3) << "the flap is the top face";
}

TEST(VoxelPattern, TallWindowInsideABoxLeavesAPieceOnTheWall) {
  // The same window in the middle of a 3-wide box: the cell relocated onto the back wall is
  // framed by the front face, not the wall, so nothing pulls it from the back board.
  VoxelModel m = box(3, 1, 3);
  m.set_window(1, 1, true);
  m.set_window(1, 2, true);
  const Pattern p = make_pattern(m);
  const PopupReport r = check_popup(p);
  ASSERT_EQ(r.not_standing.size(), 1u) << "one VFace fails";
  const PatternFace& f = p.faces[static_cast<std::size_t>(r.not_standing[0].face)];
  EXPECT_EQ(f.t_mm, 0) << "it lies in the back wall's plane";
  EXPECT_EQ(bounds(f.outer), (Rect{{2, 1}, {3, 2}})) << "at the window's upper cell";
  EXPECT_FALSE(r.not_standing[0].from_back) << "not reached from the back board";
  EXPECT_TRUE(r.not_standing[0].from_floor) << "but pushed from the floor through the ledge";
}

TEST(VoxelPattern, WindowsOnADeeperFrontFollowThePaperFormula) {
  // A 2-deep, 4-high box: the front face belongs to voxel column j = 1. Window rows 1..3 move to
  // the tops of cell[x][j - (k - h) + 1][h] with h = 0: y' = 1, 0, then past the back wall.
  VoxelModel m = box(3, 2, 4);
  for (int z = 1; z <= 3; ++z) m.set_window(1, z, true);
  const CellGrid g = make_cell_grid(m);
  const auto f = [&](int v) { return g.at(2, v + 6); };  // model column 1
  EXPECT_EQ(f(-1), CellGrid::pack(FaceKind::horizontal, 1)) << "row 1 (v in [-1,0]) → ledge at height 1, depth cell 1";
  EXPECT_EQ(f(0), CellGrid::pack(FaceKind::horizontal, 1)) << "row 2 (v in [0,1]) → ledge at height 1, depth cell 0";
  EXPECT_EQ(f(1), CellGrid::pack(FaceKind::vertical, 0)) << "row 3 (v in [1,2]) → past the back wall, onto it";
  EXPECT_EQ(f(-2), CellGrid::pack(FaceKind::vertical, 2)) << "row 0 stays on the front face";
  EXPECT_EQ(to_card(FaceKind::horizontal, 1, {0, -0.5}).y_mm, 1.5) << "the row-1 cell lies 1-2 deep at height 1";
}

TEST(VoxelPattern, Fig8aFloatingPartIsCutFree) {
  // One column, windows on rows 0 and 2: the middle front cell and its ledge lose every fold to
  // the rest of the sheet.
  VoxelModel m = box(1, 1, 3);
  m.set_window(0, 0, true);
  m.set_window(0, 2, true);
  const Pattern p = make_pattern(m);
  const PopupReport r = check_popup(p);
  EXPECT_FALSE(r.pops_up()) << "a floating part cannot pop up";
  ASSERT_EQ(r.loose_pieces.size(), 1u) << "exactly one piece falls out";
  EXPECT_EQ(r.loose_pieces[0].faces.size(), 2u) << "the middle front cell and the ledge above it";
  EXPECT_DOUBLE_EQ(r.loose_pieces[0].area_mm2, 2.0) << "two unit cells";
  EXPECT_EQ(r.loose_pieces[0].bounds, (Rect{{1, 0}, {2, 2}})) << "located at the middle of the column";
  EXPECT_TRUE(r.not_standing.empty()) << "faces of the loose piece are reported with the piece";
}

TEST(VoxelPattern, Fig8bSplitPartsDoNotRise) {
  // One column, window on row 1: the upper front hangs from the top, the lower stands on the
  // floor, and nothing joins them.
  VoxelModel m = box(1, 1, 3);
  m.set_window(0, 1, true);
  const Pattern p = make_pattern(m);
  const PopupReport r = check_popup(p);
  EXPECT_FALSE(r.pops_up()) << "split parts are not raised when the card opens";
  EXPECT_TRUE(r.loose_pieces.empty()) << "nothing falls out: both parts hang on a fold";
  ASSERT_EQ(r.not_standing.size(), 2u) << "both parts of the front face fail";
  int only_back = 0, only_floor = 0;
  for (const FaceProblem& f : r.not_standing) {
    only_back += f.from_back && !f.from_floor;
    only_floor += !f.from_back && f.from_floor;
  }
  EXPECT_EQ(only_back, 1) << "the upper part is held only from the back board";
  EXPECT_EQ(only_floor, 1) << "the lower part is held only from the floor";
}

TEST(VoxelPattern, StaircaseFig7) {
  // Two steps: heights 2 then 1; faces a–l of Fig. 7 map one to one onto pattern cells.
  VoxelModel m = VoxelModel::empty(1, 2, 2, 1.0);
  m.h_at(0, 0) = 2;
  m.h_at(0, 1) = 1;
  m.sheet = {4, 4, 0};
  const CellGrid g = make_cell_grid(m);
  const auto f = [&](int v) { return g.at(0, v + 4); };
  EXPECT_EQ(f(3), CellGrid::pack(FaceKind::vertical, 0)) << "back wall above the top";
  EXPECT_EQ(f(1), CellGrid::pack(FaceKind::horizontal, 2)) << "top of the back step at v in [1,2]";
  EXPECT_EQ(f(0), CellGrid::pack(FaceKind::vertical, 1)) << "front of the back step";
  EXPECT_EQ(f(-1), CellGrid::pack(FaceKind::horizontal, 1)) << "top of the front step";
  EXPECT_EQ(f(-2), CellGrid::pack(FaceKind::vertical, 2)) << "front of the front step";
  EXPECT_EQ(f(-3), CellGrid::pack(FaceKind::horizontal, 0)) << "floor";
  EXPECT_TRUE(check_popup(make_pattern(g)).pops_up()) << "a staircase always pops up";
}

TEST(VoxelPattern, EmptyModelIsAFoldedSheet) {
  VoxelModel m = VoxelModel::empty(2, 0, 0, 2.0);
  const Pattern p = make_pattern(m);
  EXPECT_EQ(p.faces.size(), 2u) << "back board and floor";
  ASSERT_EQ(p.lines.size(), 1u) << "only the centre fold";
  EXPECT_EQ(p.lines[0].kind, LineKind::valley) << "the centre fold is a valley";
  EXPECT_TRUE(check_popup(p).pops_up()) << "a blank card is valid";
}

}  // namespace
}  // namespace popcut
