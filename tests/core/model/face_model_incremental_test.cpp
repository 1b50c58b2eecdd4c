// A face model read after every edit (as an editor does) lays each edit over the last state; it must equal the whole
// history worked out at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include "popcut/model/face_model.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"
#include "random_models.h"

namespace popcut {
namespace {

// What a pattern says independent of the order faces come out in: its lines (sorted by
// make_pattern) and each face's plane and area.
struct Summary {
  std::vector<Segment> lines;
  std::vector<std::tuple<int, double, long long>> faces;  // kind, t, area in 1e-6 mm²
  bool pops_up = false;
};

Summary summary(const FaceModel& m) {
  const Pattern p = make_pattern(m);
  Summary s{p.lines, {}, check_popup(p).pops_up()};
  for (const PatternFace& f : p.faces) {
    s.faces.emplace_back(static_cast<int>(f.kind), f.t_mm, std::llround(face_area_mm2(f) * 1e6));
  }
  std::sort(s.faces.begin(), s.faces.end());
  return s;
}

void expect_same(const Summary& a, const Summary& b, const std::string& what) {
  EXPECT_EQ(a.lines, b.lines) << what;
  EXPECT_EQ(a.faces, b.faces) << what;
  EXPECT_EQ(a.pops_up, b.pops_up) << what;
}

TEST(FaceModelIncremental, EveryStateEqualsTheHistoryWorkedOutAtOnce) {
  std::mt19937_64 rng(2112);
  int compared = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const FaceModel drawn = testing::random_face_model(rng, {14, true});
    const Rect sheet = drawn.sheet();
    FaceModel live(sheet.max.x_mm, sheet.max.v_mm, -sheet.min.v_mm);
    live.face_count();  // read at once, as an editor does: every edit after this is laid over
    for (std::size_t k = 0; k < drawn.edits().size(); ++k) {
      live.apply(drawn.edits()[k]);
      // Now and then step back and forth, so states come from the kept ones and from redo too.
      if (std::uniform_int_distribution<int>(0, 3)(rng) == 0) {
        ASSERT_TRUE(live.undo());
        live.face_count();
        ASSERT_TRUE(live.redo());
      }
      // Read now or after a few more edits: the edits since the last read are laid over it at once.
      const bool last = k + 1 == drawn.edits().size();
      if (!last && std::uniform_int_distribution<int>(0, 2)(rng) != 0) continue;
      FaceModel fresh(sheet.max.x_mm, sheet.max.v_mm, -sheet.min.v_mm);
      for (std::size_t j = 0; j <= k; ++j) fresh.apply(drawn.edits()[j]);
      expect_same(summary(live), summary(fresh),
                  "trial " + std::to_string(trial) + ", after edits[" + std::to_string(k) + "]");
      ++compared;
      if (::testing::Test::HasFailure()) return;
    }
  }
  EXPECT_GT(compared, 200) << "enough states compared";
}

}  // namespace
}  // namespace popcut
