// Nesting copies of a card: the grid that fits, and a plan that cuts every card's strokes exactly once, outlines last.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "popcut/pattern/voxel_pattern.h"
#include "popcut/plan/nest.h"
#include "random_models.h"

namespace popcut {
namespace {

TEST(NestLayout, FitsWholeCardsWithTheirGaps) {
  const Rect card{{0, 0}, {100, 70}};
  NestLayout l = nest_layout(card, 305, 305, 5);  // a 12-inch mat
  EXPECT_EQ(l.columns, 2) << "100 + 5 + 100 = 205; a third needs 310";
  EXPECT_EQ(l.rows, 4) << "4 × 70 + 3 × 5 = 295";
  EXPECT_EQ(l.count(), 8);
  EXPECT_EQ(nest_layout(card, 205, 70, 5).count(), 2) << "exactly fitting counts";
  EXPECT_EQ(nest_layout(card, 204.9, 70, 5).count(), 1);
  EXPECT_EQ(nest_layout(card, 99, 300, 0).count(), 0) << "not even one card: none, not a partial row";
  EXPECT_EQ(nest_layout(card, 300, 69, 0).rows, 0);
  EXPECT_THROW(nest_layout(card, 300, 300, -1), std::invalid_argument);
}

// Every stroke of the nested plan, shifted back by its card's offset, is one of the card's, and
// each of the card's strokes appears once per copy.
TEST(NestPlan, EveryCardGetsEveryStrokeOnceAndOutlinesComeLast) {
  std::mt19937_64 rng(20261202);
  for (int trial = 0; trial < 40; ++trial) {
    const StrokePlan card = plan_strokes(make_pattern(make_cell_grid(testing::random_model(rng, {}))));
    ASSERT_FALSE(card.strokes.empty());
    const Rect e = card.extent();
    const double w = e.max.x_mm - e.min.x_mm, h = e.max.v_mm - e.min.v_mm;
    const NestLayout layout = nest_layout(e, 3 * w + 2 * 4 + 1, 2 * h + 4 + 1, 4);
    ASSERT_EQ(layout.count(), 6);
    const int copies = 1 + trial % 6;
    const StrokePlan nested = nest_plan(card, layout, copies);
    ASSERT_EQ(nested.strokes.size(), card.strokes.size() * static_cast<std::size_t>(copies));
    std::map<std::pair<long, long>, int> per_offset;  // how many strokes each card got
    std::map<std::vector<long>, int> want, got;
    const auto key = [](const Stroke& s, double dx, double dy) {
      std::vector<long> k = {static_cast<long>(s.kind), s.precut, s.pass};
      for (const Point2& p : s.points) {
        k.push_back(std::lround((p.x_mm - dx) * 1e3));
        k.push_back(std::lround((p.v_mm - dy) * 1e3));
      }
      return k;
    };
    for (const Stroke& s : card.strokes) want[key(s, 0, 0)] += copies;
    bool outline_seen = false;
    for (const Stroke& s : nested.strokes) {
      // The card a stroke is on: its first point's grid cell.
      const double col = std::floor((s.points.front().x_mm - e.min.x_mm + 2) / (w + 4));
      const double row = std::floor((s.points.front().v_mm - e.min.v_mm + 2) / (h + 4));
      ++per_offset[{static_cast<long>(col), static_cast<long>(row)}];
      ++got[key(s, col * (w + 4), row * (h + 4))];
      if (s.kind == PlanKind::outline) outline_seen = true;
      EXPECT_FALSE(outline_seen && s.kind != PlanKind::outline) << "trial " << trial << ": a card cut free early";
    }
    EXPECT_EQ(got, want) << "trial " << trial;
    EXPECT_EQ(per_offset.size(), static_cast<std::size_t>(copies));
    EXPECT_EQ(nested.total().strokes, card.total().strokes * copies);
    EXPECT_NEAR(nested.total().cut_mm, card.total().cut_mm * copies, 1e-6 * copies * card.total().cut_mm);
    EXPECT_LE(nested.extent().max.x_mm, e.min.x_mm + 3 * w + 2 * 4 + 1 + 1e-9) << "inside the media";
    EXPECT_LE(nested.extent().max.v_mm, e.min.v_mm + 2 * h + 4 + 1 + 1e-9);
  }
}

TEST(NestPlan, KindsStayInTheCardsOrderAcrossCards) {
  std::mt19937_64 rng(7);
  const StrokePlan card = plan_strokes(make_pattern(make_cell_grid(testing::random_model(rng, {}))));
  const Rect e = card.extent();
  const StrokePlan nested = nest_plan(card, nest_layout(e, 10 * (e.max.x_mm - e.min.x_mm), 1000, 3), 4);
  // valley, mountain, cut, outline: the card's own order, never going back to an earlier kind.
  std::size_t last = 0;
  for (const Stroke& s : nested.strokes) {
    EXPECT_GE(index_of(s.kind), last);
    last = index_of(s.kind);
  }
  EXPECT_THROW(nest_plan(card, nest_layout(e, 1, 1, 0), 1), std::invalid_argument);
  EXPECT_THROW(nest_plan(card, nest_layout(e, 1000, 1000, 0), 0), std::invalid_argument);
}

}  // namespace
}  // namespace popcut
