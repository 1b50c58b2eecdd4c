// The two walks of polygon paper §3.6 on hand-built patterns, independent of the voxel generator.
#include "popcut/pattern/popup_check.h"

#include <gtest/gtest.h>

#include "popcut/error.h"

namespace popcut {
namespace {

PatternFace rect_face(FaceKind kind, double t, double x0, double v0, double x1, double v1) {
  return {kind, t, {{x0, v0}, {x1, v0}, {x1, v1}, {x0, v1}}, {}, {(x0 + x1) / 2, (v0 + v1) / 2}};
}

// Back wall (0), top H (1), front V (2), floor (3) of a box, joined as the folds say; the
// back wall also meets the floor at the centre fold beside the box.
Pattern box_pattern() {
  Pattern p;
  p.sheet = {{0, -6}, {4, 6}};
  p.faces = {rect_face(FaceKind::vertical, 0, 0, 3, 4, 6), rect_face(FaceKind::horizontal, 3, 0, 1, 4, 3),
             rect_face(FaceKind::vertical, 2, 0, -2, 4, 1), rect_face(FaceKind::horizontal, 0, 0, -6, 4, -2)};
  p.back_face = 0;
  p.floor_face = 3;
  p.folds = {{0, 1, LineKind::valley, 4},
             {1, 2, LineKind::mountain, 4},
             {2, 3, LineKind::valley, 4},
             {0, 3, LineKind::valley, 2}};
  return p;
}

TEST(PopupCheck, BoxStands) {
  EXPECT_TRUE(check_popup(box_pattern()).pops_up()) << "back→top (valley) →front (mountain); floor→front (valley)";
}

TEST(PopupCheck, FrontHangingFromTheTopOnlyFails) {
  Pattern p = box_pattern();
  p.folds.erase(p.folds.begin() + 2);  // the front no longer meets the floor
  const PopupReport r = check_popup(p);
  ASSERT_EQ(r.not_standing.size(), 1u) << "the front face is not pushed up by the floor";
  EXPECT_EQ(r.not_standing[0].face, 2) << "the front face is named";
  EXPECT_TRUE(r.not_standing[0].from_back) << "it is still reached from the back board";
  EXPECT_FALSE(r.not_standing[0].from_floor) << "but not from the floor";
  EXPECT_TRUE(r.loose_pieces.empty()) << "nothing falls out";
}

TEST(PopupCheck, WalksFollowFoldDirection) {
  // A face reached from the floor only by going down breaks walk (b)'s direction rule.
  Pattern p = box_pattern();
  p.faces.push_back(rect_face(FaceKind::vertical, 1, 5, -1, 6, 0));  // 4: a VFace hanging below the top
  p.folds.push_back({1, 4, LineKind::mountain, 1});
  const PopupReport r = check_popup(p);
  ASSERT_EQ(r.not_standing.size(), 1u) << "face 4 is reached from the back but never pushed from the floor";
  EXPECT_EQ(r.not_standing[0].face, 4) << "the hanging face is named";
}

TEST(PopupCheck, PiecesWithoutFoldsToTheCardFallOut) {
  Pattern p = box_pattern();
  p.faces.push_back(rect_face(FaceKind::vertical, 1, 5, -1, 6, 0));
  p.faces.push_back(rect_face(FaceKind::horizontal, 2, 5, 0, 6, 1));
  p.folds.push_back({5, 4, LineKind::mountain, 1});
  const PopupReport r = check_popup(p);
  ASSERT_EQ(r.loose_pieces.size(), 1u) << "faces 4 and 5 form one loose piece";
  EXPECT_EQ(r.loose_pieces[0].faces, (std::vector<int>{4, 5})) << "both faces are listed";
  EXPECT_EQ(r.loose_pieces[0].bounds, (Rect{{5, -1}, {6, 1}})) << "with their location";
  EXPECT_DOUBLE_EQ(r.loose_pieces[0].area_mm2, 2.0) << "and their area";
}

TEST(PopupCheck, BrokenPatternIsAnError) {
  Pattern p = box_pattern();
  p.folds.push_back({0, 9, LineKind::valley, 1});
  EXPECT_THROW(check_popup(p), Error) << "a fold naming a missing face is rejected, not followed";
}

}  // namespace
}  // namespace popcut
