// interior_point: strictly inside polygons with holes, concave outlines and teeth, never on an edge.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "popcut/geometry.h"

namespace {
using popcut::Point2;
using popcut::Ring;

// Even-odd test, and the distance to the nearest edge, to tell "inside" from "on the boundary".
bool inside(const Ring& r, Point2 p) {
  bool in = false;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
    if ((r[i].v_mm > p.v_mm) != (r[j].v_mm > p.v_mm) &&
        p.x_mm < r[i].x_mm + (p.v_mm - r[i].v_mm) * (r[j].x_mm - r[i].x_mm) / (r[j].v_mm - r[i].v_mm))
      in = !in;
  return in;
}

double edge_distance(const Ring& r, Point2 p) {
  double best = INFINITY;
  for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
    const double dx = r[i].x_mm - r[j].x_mm, dv = r[i].v_mm - r[j].v_mm;
    const double u =
        std::clamp(((p.x_mm - r[j].x_mm) * dx + (p.v_mm - r[j].v_mm) * dv) / (dx * dx + dv * dv), 0.0, 1.0);
    best = std::min(best, std::hypot(p.x_mm - r[j].x_mm - u * dx, p.v_mm - r[j].v_mm - u * dv));
  }
  return best;
}

void expect_inside(const Ring& outer, const std::vector<Ring>& holes, const std::string& what) {
  const Point2 p = popcut::interior_point(outer, holes);
  EXPECT_TRUE(inside(outer, p)) << what;
  EXPECT_GT(edge_distance(outer, p), 1e-6) << what;
  for (const Ring& h : holes) {
    EXPECT_FALSE(inside(h, p)) << what;
    EXPECT_GT(edge_distance(h, p), 1e-6) << what;
  }
}

TEST(InteriorPoint, LiesInsideConcaveOutlinesAndOutsideTheirHoles) {
  expect_inside({{0, 0}, {10, 0}, {10, 1}, {1, 1}, {1, 10}, {0, 10}}, {}, "an L");
  expect_inside({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {{{1, 1}, {1, 9}, {9, 9}, {9, 1}}}, "a frame");
  // A comb: the tallest band between vertex heights is the teeth's, where most of the line is gap.
  expect_inside({{0, 0}, {9, 0}, {9, 8}, {8, 8}, {8, 1}, {5, 1}, {5, 8}, {4, 8}, {4, 1}, {1, 1}, {1, 8}, {0, 8}}, {},
                "a comb");
  expect_inside({{0, 0}, {4, 3}, {0, 6}, {1, 3}}, {}, "an arrowhead");
}

TEST(InteriorPoint, LiesInsideRandomStarShapedRings) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> radius(0.2, 5), jitter(-0.3, 0.3);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 3 + trial % 40;
    Ring r;
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * (k + 0.5 + jitter(rng)) / n, d = radius(rng);
      r.push_back({10 + d * std::cos(a), 10 + d * std::sin(a)});
    }
    expect_inside(r, {}, "star " + std::to_string(trial));
  }
}

}  // namespace
