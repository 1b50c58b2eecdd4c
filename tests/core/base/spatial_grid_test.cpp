// The spatial grid against brute force: k-nearest (ties, duplicates, groups, erased points, far
// queries, capped grids), box queries and segments near a point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>

#include "popcut/spatial_grid.h"

namespace popcut {
namespace {

struct PointSet {
  std::vector<Point2> at;
  std::vector<int> group;
  std::vector<char> erased;
};

// The same distance as the grid's, so equal distances tie the same way.
double distance(Point2 a, Point2 b) {
  const double dx = a.x_mm - b.x_mm, dv = a.v_mm - b.v_mm;
  return std::sqrt(dx * dx + dv * dv);
}

std::vector<std::pair<double, int>> brute_nearest(const PointSet& s, Point2 q, std::size_t k, int skip_group) {
  std::vector<std::pair<double, int>> all;
  for (std::size_t i = 0; i < s.at.size(); ++i) {
    if (!s.erased[i] && s.group[i] != skip_group) all.emplace_back(distance(q, s.at[i]), static_cast<int>(i));
  }
  std::sort(all.begin(), all.end());
  if (all.size() > k) all.resize(k);
  return all;
}

// Points of one of several shapes: a small lattice (many duplicates and equal distances), a wide
// uniform spread, or a line (a grid capped at 4096 cells a side).
PointSet random_points(std::mt19937_64& rng, int shape, std::size_t n) {
  PointSet s;
  std::uniform_real_distribution<double> u(-50, 150);
  const std::uint64_t span = 1 + rng() % 5;
  for (std::size_t i = 0; i < n; ++i) {
    Point2 p;
    if (shape == 0)
      p = {static_cast<double>(rng() % span), static_cast<double>(rng() % span)};
    else if (shape == 1)
      p = {u(rng), u(rng)};
    else
      p = {static_cast<double>(rng() % 100000) / 10, 3.0};
    s.at.push_back(p);
    s.group.push_back(static_cast<int>(rng() % 4) - 1);
    s.erased.push_back(0);
  }
  return s;
}

TEST(SpatialGrid, NearestMatchesBruteForceIncludingTiesAndDuplicates) {
  std::mt19937_64 rng(17);
  int checked = 0, ties = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int shape = trial % 3;
    const std::size_t n = shape == 2 && trial % 2 ? 8000 : 1 + rng() % 300;
    PointSet s = random_points(rng, shape, n);
    SpatialGrid grid(bounds(s.at), n);
    for (std::size_t i = 0; i < n; ++i) grid.insert(static_cast<int>(i), s.at[i], s.group[i]);
    for (std::size_t i = 0; i < n; ++i) {
      if (rng() % 4 == 0) {
        s.erased[i] = 1;
        grid.erase(static_cast<int>(i), s.at[i]);
      }
    }
    std::vector<std::pair<double, int>> found;
    for (int query = 0; query < 40; ++query) {
      // At a stored point, anywhere near the points, or far outside the grid's box.
      const Point2 q = query % 3 == 0 ? s.at[rng() % n]
                       : query % 3 == 1
                           ? Point2{static_cast<double>(rng() % 200) - 50, static_cast<double>(rng() % 200) - 50}
                           : Point2{static_cast<double>(rng() % 4000) - 2000, -1000.0 + static_cast<double>(rng() % 3)};
      const std::size_t k = std::vector<std::size_t>{1, 2, 3, 8, 40}[rng() % 5];
      const int skip = query % 2 ? SpatialGrid::kNoGroup : static_cast<int>(rng() % 4) - 1;
      grid.nearest(q, k, skip, found);
      const auto want = brute_nearest(s, q, k, skip);
      ASSERT_EQ(found, want) << "trial " << trial << " query " << query << " k " << k;
      for (std::size_t j = 1; j < want.size(); ++j) ties += want[j].first == want[j - 1].first;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 300 * 40);
  EXPECT_GT(ties, 1000) << "the point sets must exercise equal distances";
}

TEST(SpatialGrid, NearestOfNoneOrZeroIsEmpty) {
  SpatialGrid grid({{0, 0}, {10, 10}}, 2);
  std::vector<std::pair<double, int>> found{{1.0, 1}};
  grid.nearest({5, 5}, 3, SpatialGrid::kNoGroup, found);
  EXPECT_TRUE(found.empty()) << "an empty grid has no nearest point";
  grid.insert(0, Point2{1, 1}, 7);
  grid.insert(1, Point2{9, 9}, 8);
  grid.nearest({5, 5}, 0, SpatialGrid::kNoGroup, found);
  EXPECT_TRUE(found.empty()) << "k = 0 asks for nothing";
  grid.nearest({5, 5}, 5, 7, found);
  ASSERT_EQ(found.size(), 1u) << "the skipped group's point is not found";
  EXPECT_EQ(found[0].second, 1);
  grid.nearest({5, 5}, 5, SpatialGrid::kNoGroup, found);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].second, 0) << "equally far: the lower id first";
}

TEST(SpatialGrid, BoxQueriesFindEveryOverlappingBoxOnce) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 100), len(0, 30);
  for (int trial = 0; trial < 100; ++trial) {
    const std::size_t n = 1 + rng() % 200;
    std::vector<std::pair<Point2, Point2>> boxes;
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 lo{u(rng), u(rng)};
      boxes.push_back({lo, {lo.x_mm + len(rng) * (trial % 2), lo.v_mm + len(rng)}});
    }
    SpatialGrid grid({{0, 0}, {100, 100}}, n);  // some boxes reach past the grid's own box
    for (std::size_t i = 0; i < n; ++i) grid.insert(static_cast<int>(i), boxes[i].first, boxes[i].second);
    std::vector<int> ids;
    for (int query = 0; query < 30; ++query) {
      const Point2 lo{u(rng) - 20, u(rng) - 20}, hi{lo.x_mm + len(rng), lo.v_mm + len(rng)};
      grid.ids_in_box(lo, hi, ids);
      const std::set<int> got(ids.begin(), ids.end());
      ASSERT_EQ(got.size(), ids.size()) << "each id once";
      for (std::size_t i = 0; i < n; ++i) {
        const auto& [a, b] = boxes[i];
        const bool overlaps = a.x_mm <= hi.x_mm && lo.x_mm <= b.x_mm && a.v_mm <= hi.v_mm && lo.v_mm <= b.v_mm;
        if (overlaps) {
          ASSERT_TRUE(got.count(static_cast<int>(i))) << "trial " << trial << ": box " << i << " overlaps the query";
        }
      }
      for (const Point2 p : {lo, hi}) {
        const std::vector<int>& cell = grid.at(p);
        for (std::size_t i = 0; i < n; ++i) {
          const auto& [a, b] = boxes[i];
          const bool holds = a.x_mm <= p.x_mm && p.x_mm <= b.x_mm && a.v_mm <= p.v_mm && p.v_mm <= b.v_mm;
          if (holds) {
            ASSERT_NE(std::find(cell.begin(), cell.end(), static_cast<int>(i)), cell.end())
                << "box " << i << " holds the point";
          }
        }
      }
    }
  }
}

// A segment is in the cell of every point within its pad, for segments of every length and
// direction, points inside and outside the grid's box, and grids of few or many cells.
TEST(SpatialGrid, SegmentsAreInTheCellOfEveryPointWithinTheirPad) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> at(-50, 50), len(0, 60), angle(0, 2 * M_PI), query(-70, 70);
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<std::pair<Point2, Point2>> segs;
    const std::size_t n = trial % 3 == 0 ? 3 : 400;
    for (std::size_t i = 0; i < n; ++i) {
      const Point2 a{at(rng), at(rng)};
      const double l = trial % 4 == 1 ? 0 : len(rng), t = trial % 4 == 2 ? 0 : angle(rng);
      segs.emplace_back(a, Point2{a.x_mm + l * std::cos(t), a.v_mm + l * std::sin(t)});
    }
    const double pad = 0.01 * (trial + 1) * (trial + 1);
    SpatialGrid grid({{-40, -40}, {40, 40}}, n);  // segments and queries also lie outside it
    for (std::size_t i = 0; i < n; ++i) grid.insert_segment(static_cast<int>(i), segs[i].first, segs[i].second, pad);
    for (int q = 0; q < 2000; ++q) {
      const Point2 p{query(rng), query(rng)};
      const std::vector<int>& cell = grid.at(p);
      const std::set<int> seen(cell.begin(), cell.end());
      for (std::size_t i = 0; i < n; ++i) {
        const auto& [a, b] = segs[i];
        const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, l2 = dx * dx + dv * dv;
        const double u = l2 > 0 ? std::clamp(((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / l2, 0.0, 1.0) : 0;
        if (std::hypot(p.x_mm - a.x_mm - u * dx, p.v_mm - a.v_mm - u * dv) <= pad) {
          ASSERT_TRUE(seen.count(static_cast<int>(i)))
              << "trial " << trial << ": segment " << i << " passes within " << pad << " mm of (" << p.x_mm << ", "
              << p.v_mm << ") but is not in its cell";
        }
      }
    }
  }
}

// A long slanted segment fills a band of cells along it, not its whole box: the far corners of
// its box are left empty.
TEST(SpatialGrid, ASlantedSegmentLeavesTheCornersOfItsBoxEmpty) {
  SpatialGrid grid({{0, 0}, {100, 100}}, 10000);
  grid.insert_segment(0, {0, 0}, {100, 100}, 0.01);
  EXPECT_EQ(grid.at({50, 50}).size(), 1u) << "the segment's own cell holds it";
  EXPECT_TRUE(grid.at({95, 5}).empty()) << "a corner of the diagonal's box, 64 mm from it, holds nothing";
  EXPECT_TRUE(grid.at({5, 95}).empty()) << "the other corner holds nothing";
}

}  // namespace
}  // namespace popcut
