// Fold gap as clearance: every scored fold piece stays fold_gap_mm (in the plane) from every cut and the outline.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>

#include "popcut/io/model_io.h"
#include "popcut/pattern/voxel_pattern.h"
#include "popcut/plan/plan.h"
#include "random_models.h"

namespace popcut {
namespace {

constexpr double kPi = 3.14159265358979323846;

double point_segment(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, l2 = dx * dx + dv * dv;
  const double t = l2 > 0 ? std::clamp(((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / l2, 0.0, 1.0) : 0;
  return std::hypot(a.x_mm + t * dx - p.x_mm, a.v_mm + t * dv - p.v_mm);
}

double cross(Point2 a, Point2 b, Point2 c) {
  return (b.x_mm - a.x_mm) * (c.v_mm - a.v_mm) - (b.v_mm - a.v_mm) * (c.x_mm - a.x_mm);
}

// Distance between two segments: 0 where they cross, else the nearest endpoint-to-segment.
double segment_segment(Point2 a, Point2 b, Point2 c, Point2 d) {
  const double o1 = cross(a, b, c), o2 = cross(a, b, d), o3 = cross(c, d, a), o4 = cross(c, d, b);
  if (((o1 > 0) != (o2 > 0)) && o1 != 0 && o2 != 0 && ((o3 > 0) != (o4 > 0)) && o3 != 0 && o4 != 0) return 0;
  return std::min({point_segment(a, c, d), point_segment(b, c, d), point_segment(c, a, b), point_segment(d, a, b)});
}

// The smallest distance from segment ab to any cut of the pattern or the sheet's edge.
double clearance(const Pattern& p, Point2 a, Point2 b) {
  const Rect& s = p.sheet;
  const Point2 c[4] = {s.min, {s.max.x_mm, s.min.v_mm}, s.max, {s.min.x_mm, s.max.v_mm}};
  double best = INFINITY;
  for (int i = 0; i < 4; ++i) best = std::min(best, segment_segment(a, b, c[i], c[(i + 1) % 4]));
  for (const Segment& l : p.lines) {
    if (l.kind == LineKind::cut) best = std::min(best, segment_segment(a, b, l.a, l.b));
  }
  return best;
}

// Checks every scored fold piece of `p` at `gap_mm`; returns how many pieces were checked. A
// piece must also be no shorter than it has to be: each of its ends is an end of the fold it
// came from or lies (within rounding) at exactly the gap from some cut.
int check_fold_pieces(const Pattern& p, double gap_mm, const std::string& what) {
  int pieces = 0;
  for (PlanKind kind : {PlanKind::valley, PlanKind::mountain}) {
    const LineKind fold = kind == PlanKind::valley ? LineKind::valley : LineKind::mountain;
    for (const Segment& s : kind_lines(p, kind, gap_mm)) {
      ++pieces;
      EXPECT_GE(clearance(p, s.a, s.b), gap_mm - 1e-6)
          << what << ": piece " << s.a.x_mm << "," << s.a.v_mm << " - " << s.b.x_mm << "," << s.b.v_mm;
      for (Point2 end : {s.a, s.b}) {
        bool fold_end = false;
        for (const Segment& l : p.lines) {
          if (l.kind == fold && (std::hypot(end.x_mm - l.a.x_mm, end.v_mm - l.a.v_mm) < 1e-9 ||
                                 std::hypot(end.x_mm - l.b.x_mm, end.v_mm - l.b.v_mm) < 1e-9)) {
            fold_end = true;
          }
        }
        if (!fold_end) {
          EXPECT_NEAR(clearance(p, end, end), gap_mm, 1e-6) << what << ": a trimmed end sits at the gap, not further";
        }
      }
    }
  }
  return pieces;
}

TEST(FoldGap, ASlantedCutKeepsTheGapAsADistance) {
  for (double angle_deg : {90.0, 56.3, 20.0, 5.0}) {
    Pattern p;
    p.sheet = {{-20, -20}, {40, 20}};
    const double a = angle_deg * kPi / 180;
    p.lines = {{LineKind::cut, {0, 0}, {10 * std::cos(a), 10 * std::sin(a)}}, {LineKind::valley, {0, 0}, {20, 0}}};
    const auto valleys = kind_lines(p, PlanKind::valley, 0.5);
    ASSERT_EQ(valleys.size(), 1u) << angle_deg << "°";
    EXPECT_NEAR(valleys[0].a.x_mm, 0.5 / std::sin(a), 1e-9) << angle_deg << "°: the fold gives up gap / sin(angle)";
    EXPECT_GE(clearance(p, valleys[0].a, valleys[0].b), 0.5 - 1e-9) << angle_deg << "°";
  }
}

TEST(FoldGap, ACutPassingTheFoldsMiddleSplitsIt) {
  Pattern p;
  p.sheet = {{-20, -20}, {40, 20}};
  p.lines = {{LineKind::valley, {0, 0}, {20, 0}}, {LineKind::cut, {10, 0.2}, {10, 5}}};  // ends 0.2 mm above the fold
  const auto valleys = kind_lines(p, PlanKind::valley, 0.5);
  ASSERT_EQ(valleys.size(), 2u) << "scored on both sides of the cut's end, not under it";
  const double half = std::sqrt(0.5 * 0.5 - 0.2 * 0.2);
  EXPECT_NEAR(valleys[0].b.x_mm, 10 - half, 1e-9);
  EXPECT_NEAR(valleys[1].a.x_mm, 10 + half, 1e-9);
  check_fold_pieces(p, 0.5, "split fold");
}

// examples/faces/pavilion.json: the valley at v = 18 from x = 25 to 75 meets slanted cuts at
// both ends (to (35, 33) and (65, 33)); scored 0.5 mm along it, its ends were 0.42 mm from them.
TEST(FoldGap, PavilionsSlantedWallsKeepTheGap) {
  const Pattern p = make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/faces/pavilion.json"));
  bool found = false;
  for (const Segment& s : kind_lines(p, PlanKind::valley, 0.5)) {
    if (std::abs(s.a.v_mm - 18) < 1e-9 && std::abs(s.b.v_mm - 18) < 1e-9 && std::min(s.a.x_mm, s.b.x_mm) < 30) {
      found = true;
      EXPECT_NEAR(std::min(s.a.x_mm, s.b.x_mm), 25 + 0.5 / std::sin(std::atan2(15, 10)), 1e-6)
          << "0.601 mm in from the corner";
      EXPECT_GE(clearance(p, s.a, s.b), 0.5 - 1e-6);
    }
  }
  EXPECT_TRUE(found) << "the valley at v = 18 is scored";
  EXPECT_GT(check_fold_pieces(p, 0.5, "pavilion"), 0);
}

// Many random face models with slanted cuts, and voxel models, at several gaps: every scored
// piece keeps its clearance, and no piece is shorter than its clearance requires.
TEST(FoldGap, RandomModelsKeepTheClearanceEverywhere) {
  std::mt19937_64 rng(16);
  int pieces = 0;
  for (int i = 0; i < 300; ++i) {
    testing::RandomFaceSpec spec;
    spec.edits = 4 + i % 10;
    const Pattern p = make_pattern(AnyModel(testing::random_face_model(rng, spec)));
    for (double gap : {0.5, 1.5}) pieces += check_fold_pieces(p, gap, "face model " + std::to_string(i));
  }
  testing::RandomModelSpec voxel;
  voxel.window_probability = 0.3;
  voxel.random_sheet = true;
  for (int i = 0; i < 100; ++i)
    pieces +=
        check_fold_pieces(make_pattern(testing::random_model(rng, voxel)), 0.5, "voxel model " + std::to_string(i));
  EXPECT_GT(pieces, 1000) << "the models have folds to check";
}

}  // namespace
}  // namespace popcut
