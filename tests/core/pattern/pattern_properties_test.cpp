// Property tests over thousands of random staircases with windows, checked by an independent oracle.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pattern_oracle.h"
#include "popcut/io/pattern_io.h"
#include "popcut/io/voxel_json.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"

namespace popcut {
namespace {

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += "\n  " + x;
  return s;
}

// Every point of the sheet, mapped to 3D at 90°, lies on the voxel solid's surface (no windows).
std::vector<std::string> check_on_surface(const VoxelModel& m, const Pattern& p) {
  std::vector<std::string> problems;
  const double mm = m.voxel_mm;
  const int side = static_cast<int>(std::lround(resolve_sheet(m, "").side));
  const auto h = [&](double x_mm, double y_mm) {
    const int x = static_cast<int>(std::floor(x_mm / mm)) - side;
    const int y = static_cast<int>(std::floor(y_mm / mm));
    return (x < 0 || x >= m.width || y < 0) ? 0 : m.h(x, y);
  };
  for (double x = p.sheet.min.x_mm + mm / 2; x < p.sheet.max.x_mm; x += mm) {
    for (double v = p.sheet.min.v_mm + mm / 2; v < p.sheet.max.v_mm; v += mm) {
      const int fi = testing::face_at(p, {x, v});
      if (fi < 0) continue;
      const PatternFace& f = p.faces[static_cast<std::size_t>(fi)];
      const Point3 q = to_card(f.kind, f.t_mm, {x, v});
      bool ok;
      if (f.kind == FaceKind::vertical) {
        // Solid (or the back wall) just behind, empty just in front.
        const double z = q.z_mm / mm;
        ok = z >= 0 && (f.t_mm == 0 || z < h(x, q.y_mm - mm / 2) / 1.0) && z >= h(x, q.y_mm + mm / 2);
      } else {
        ok = q.y_mm >= 0 && h(x, q.y_mm) * mm == f.t_mm;
      }
      if (!ok) {
        problems.push_back("sheet point (" + std::to_string(x) + ", " + std::to_string(v) + ") of face " + std::to_string(fi) +
                           " is not on the voxel surface");
        if (problems.size() > 10) return problems;
      }
    }
  }
  return problems;
}

class RandomModels : public ::testing::TestWithParam<double> {};

TEST_P(RandomModels, PatternIsConsistent) {
  const double window_probability = GetParam();
  std::mt19937_64 rng(static_cast<std::uint64_t>(1000 * window_probability) + 17);
  testing::RandomModelSpec spec;
  spec.window_probability = window_probability;
  spec.random_sheet = true;
  const int trials = 1200;
  int failing = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const VoxelModel m = testing::random_model(rng, spec);
    const std::string what = "trial " + std::to_string(trial) + " model:\n" + to_voxel_json(m);
    const Pattern p = make_pattern(m);
    auto tiling = testing::check_tiling(p, m.voxel_mm);
    ASSERT_TRUE(tiling.empty()) << "regions must tile the sheet exactly; " << what << join(tiling);
    auto lines = testing::check_lines(p, m.voxel_mm);
    ASSERT_TRUE(lines.empty()) << "lines must be maximal, x-parallel folds, kinds from 3D; " << what << join(lines);
    auto folds = testing::check_folds(p);
    ASSERT_TRUE(folds.empty()) << "fold links must match the faces; " << what << join(folds);
    ASSERT_EQ(parse_pattern(to_pattern_json(p), "rt"), p) << "pattern JSON round trip; " << what;
    ASSERT_EQ(make_pattern(parse_voxel_model(to_voxel_json(m), "rt")), p) << "model JSON round trip; " << what;
    const PopupReport r = check_popup(p);
    if (window_probability == 0) {
      ASSERT_TRUE(r.pops_up()) << "every staircase without windows pops up; " << what;
      auto surface = check_on_surface(m, p);
      ASSERT_TRUE(surface.empty()) << "faces must lie on the voxel surface; " << what << join(surface);
    }
    failing += !r.pops_up();
  }
  if (window_probability > 0) {
    EXPECT_GT(failing, 0) << "random windows should produce some cards that do not pop up";
    EXPECT_LT(failing, trials) << "random windows should leave some cards that pop up";
  }
}

INSTANTIATE_TEST_SUITE_P(WindowProbability, RandomModels, ::testing::Values(0.0, 0.15, 0.4));

}  // namespace
}  // namespace popcut
