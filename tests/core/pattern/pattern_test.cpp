// The 2D↔3D face map (polygon paper eq. 1–3) and the line rule for x-parallel edges.
#include "popcut/pattern/pattern.h"

#include <gtest/gtest.h>

namespace popcut {
namespace {

TEST(Pattern, FaceMapMatchesEquations) {
  EXPECT_EQ(to_card(FaceKind::vertical, 4, {1, 3}), (Point3{1, 4, 7})) << "VFace t: (x, t, v + t)";
  EXPECT_EQ(to_card(FaceKind::horizontal, 5, {1, 3}), (Point3{1, 2, 5})) << "HFace t: (x, t - v, t)";
  for (double v : {-3.0, 0.0, 2.5}) {
    const Point3 a = to_card(FaceKind::vertical, 2, {0, v});
    const Point3 b = to_card(FaceKind::horizontal, 7, {0, v});
    EXPECT_DOUBLE_EQ(a.z_mm - a.y_mm, v) << "eq. 1 inverts eq. 2: v = z - y";
    EXPECT_DOUBLE_EQ(b.z_mm - b.y_mm, v) << "eq. 1 inverts eq. 3: v = z - y";
  }
}

TEST(Pattern, EdgeKindsFollowTable1) {
  LineKind k = LineKind::cut;
  EXPECT_FALSE(classify_x_edge(FaceKind::vertical, 2, FaceKind::vertical, 2, 1, 0, k)) << "one face: no line (180°)";
  ASSERT_TRUE(classify_x_edge(FaceKind::vertical, 0, FaceKind::horizontal, 3, 3, 0, k));
  EXPECT_EQ(k, LineKind::valley) << "back wall above a top at its height: 90°, valley";
  ASSERT_TRUE(classify_x_edge(FaceKind::horizontal, 3, FaceKind::vertical, 2, 1, 0, k));
  EXPECT_EQ(k, LineKind::mountain) << "a top above its front: 270°, mountain";
  ASSERT_TRUE(classify_x_edge(FaceKind::horizontal, 3, FaceKind::vertical, 2, 0, 0, k));
  EXPECT_EQ(k, LineKind::cut) << "t_h - t_v != v: the faces do not meet, cut";
  ASSERT_TRUE(classify_x_edge(FaceKind::vertical, 1, FaceKind::vertical, 2, 0, 0, k));
  EXPECT_EQ(k, LineKind::cut) << "two VFaces never fold into each other";
  ASSERT_TRUE(classify_x_edge(FaceKind::horizontal, 1, FaceKind::vertical, 0.5, 0.5 + 1e-9, 1e-6, k));
  EXPECT_EQ(k, LineKind::mountain) << "within tolerance the faces meet";
}

}  // namespace
}  // namespace popcut
