// Property tests: the incremental window decision equals the full pop-up check on random cards.
#include "popcut/pattern/incremental_popup.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "popcut/error.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"

namespace popcut {
namespace {

bool full_check(const VoxelModel& m) { return check_popup(make_pattern(m)).pops_up(); }

// Random cards that pop up, each walked through random window toggles: every decision is
// compared with check_popup on the toggled model, and about half the accepted ones are kept so
// later decisions start from states the incremental walks reached themselves.
void compare_on_random_cards(std::uint64_t seed, const testing::RandomModelSpec& spec, int cards, int steps) {
  std::mt19937_64 rng(seed);
  int judged = 0, accepted = 0, rejected = 0, cards_used = 0;
  std::int64_t fallbacks = 0, decisions = 0;
  for (int card = 0; card < cards; ++card) {
    VoxelModel m = testing::random_model(rng, spec);
    if (!full_check(m)) continue;
    ++cards_used;
    IncrementalPopup inc(m);
    for (int step = 0; step < steps; ++step) {
      const int x = static_cast<int>(rng() % static_cast<unsigned>(m.width));
      const int top = inc.model().h(x, 0);
      if (top == 0) continue;
      // Half the edits are windows, half dropped top faces (§3.3) of a step of the slice.
      const bool window = rng() % 2 == 0;
      const int z = window ? static_cast<int>(rng() % static_cast<unsigned>(top))
                           : inc.model().h(x, static_cast<int>(rng() % static_cast<unsigned>(inc.model().depth)));
      if (!window && z == 0) continue;
      const bool on = window ? !inc.model().is_window(x, z) : !inc.model().is_top_dropped(x, z);
      VoxelModel toggled = inc.model();
      if (window) {
        toggled.set_window(x, z, on);
      } else {
        toggled.set_top_dropped(x, z, on);
      }
      const bool expected = full_check(toggled);
      ASSERT_EQ(window ? inc.pops_up_with_window(x, z, on) : inc.pops_up_with_top_dropped(x, z, on), expected)
          << "seed " << seed << " card " << card << " step " << step << ": " << (window ? "window" : "dropped top")
          << " (" << x << ", " << z << ") " << (on ? "on" : "off") << " judged differently from check_popup";
      ++judged;
      (expected ? accepted : rejected) += 1;
      if (rng() % 2 == 0) {
        const VoxelModel before = inc.model();
        ASSERT_EQ(window ? inc.try_window(x, z, on) : inc.try_drop_top(x, z, on), expected)
            << "trying agrees with the decision";
        ASSERT_TRUE(inc.model() == (expected ? toggled : before)) << "kept exactly when it stands";
        ASSERT_TRUE(full_check(inc.model())) << "seed " << seed << " card " << card << ": the kept model pops up";
      }
    }
    fallbacks += inc.stats().full_checks;
    decisions += inc.stats().decisions;
  }
  std::printf("seed %llu: %d cards, %d decisions (%d stand, %d do not), %lld full checks\n",
              static_cast<unsigned long long>(seed), cards_used, judged, accepted, rejected,
              static_cast<long long>(fallbacks));
  EXPECT_GT(cards_used, cards / 4) << "enough random cards pop up to test on";
  EXPECT_GT(accepted, judged / 10) << "the random windows include many that stand";
  EXPECT_GT(rejected, judged / 10) << "and many that do not";
  EXPECT_LT(fallbacks * 5, decisions) << "most decisions are settled by the local walks, not the full check";
}

testing::RandomModelSpec spec_of(int width, int depth, int height, double windows, bool random_sheet) {
  testing::RandomModelSpec spec;
  spec.max_width = width;
  spec.max_depth = depth;
  spec.max_height = height;
  spec.window_probability = windows;
  spec.random_sheet = random_sheet;
  return spec;
}

TEST(IncrementalPopup, MatchesFullCheckOnSmallCards) {
  compare_on_random_cards(1, spec_of(6, 5, 7, 0.15, true), 400, 40);
}

TEST(IncrementalPopup, MatchesFullCheckOnWiderCards) {
  compare_on_random_cards(2, spec_of(24, 10, 14, 0.05, false), 60, 150);
}

TEST(IncrementalPopup, MatchesFullCheckOnRandomSheets) {
  // Random sheets include side = 0: with no bare board strip beside the model every strip may
  // carry windows, and the floor is then more often reached only through them, which the local
  // walks must notice (or hand to the full check).
  for (int seed = 3; seed < 8; ++seed) {
    compare_on_random_cards(static_cast<std::uint64_t>(seed) * 7919, spec_of(8, 5, 8, 0.1, true), 80, 30);
  }
}

TEST(IncrementalPopup, RejectsACardThatDoesNotPopUp) {
  // A window row across the whole only slice cuts the front wall in two (voxel paper Fig. 8 b).
  VoxelModel m = VoxelModel::empty(1, 2, 4, 1.0);
  m.h_at(0, 0) = 4;
  m.h_at(0, 1) = 4;
  m.set_window(0, 1, true);
  m.sheet.side = 0;
  ASSERT_FALSE(full_check(m)) << "precondition: this card does not pop up";
  EXPECT_THROW(IncrementalPopup{m}, Error) << "windows cannot be judged on a card that fails already";
}

TEST(IncrementalPopup, WindowNeedsAFrontFace) {
  VoxelModel m = VoxelModel::empty(2, 2, 4, 1.0);
  m.h_at(0, 0) = 2;
  IncrementalPopup inc(m);
  EXPECT_THROW(inc.pops_up_with_window(0, 3, true), Error) << "row 3 is above the column";
  EXPECT_THROW(inc.pops_up_with_window(5, 0, true), Error) << "slice 5 is outside the grid";
}

}  // namespace
}  // namespace popcut
