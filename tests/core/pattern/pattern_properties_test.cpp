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

// Every point of the sheet, mapped to 3D at 90°, lies where the paper can put paper: on the voxel
// solid's surface, or (a window's relocated cell) on a ledge over the first solid row below the
// window or on the back wall behind the column.
std::vector<std::string> check_on_surface(const VoxelModel& m, const Pattern& p) {
  std::vector<std::string> problems;
  const double mm = m.voxel_mm;
  const int side = resolve_sheet(m, "").side;
  for (double x_mm = p.sheet.min.x_mm + mm / 2; x_mm < p.sheet.max.x_mm; x_mm += mm) {
    const int x = static_cast<int>(std::floor(x_mm / mm)) - side;
    const bool model_column = x >= 0 && x < m.width;
    const auto h = [&](double y_mm) {
      const int y = static_cast<int>(std::floor(y_mm / mm));
      return (!model_column || y < 0) ? 0 : m.h(x, y);
    };
    const auto window = [&](int z) { return model_column && m.is_window(x, z); };
    for (double v = p.sheet.min.v_mm + mm / 2; v < p.sheet.max.v_mm; v += mm) {
      const int fi = testing::face_at(p, {x_mm, v});
      if (fi < 0) continue;
      const PatternFace& f = p.faces[static_cast<std::size_t>(fi)];
      const Point3 q = to_card(f.kind, f.t_mm, {x_mm, v});
      const double z = q.z_mm / mm;
      const int t = static_cast<int>(std::lround(f.t_mm / mm));
      bool ok;
      if (f.kind == FaceKind::vertical) {
        // A front face: solid just behind, empty just in front, and its row is no window.
        ok = z >= 0 && (t == 0 || (z < h(q.y_mm - mm / 2) && z >= h(q.y_mm + mm / 2) && !window(static_cast<int>(z))));
      } else {
        // A top face; or a ledge at t inside the solid: row t opens, row t - 1 is solid (or floor).
        const int below = h(q.y_mm);
        ok = q.y_mm >= 0 && (below == t || (below > t && window(t) && (t == 0 || !window(t - 1))));
      }
      if (!ok) {
        problems.push_back("sheet point (" + std::to_string(x_mm) + ", " + std::to_string(v) + ") of face " +
                           std::to_string(fi) + " is not where the paper can be");
        if (problems.size() > 10) return problems;
      }
    }
  }
  return problems;
}

// Voxel paper Fig. 7 and §2.3 applied voxel by voxel: each top face and each front face of a
// filled voxel owns one pattern cell; a front face on a window row moves to the top of the
// voxel cell[x][j - (k - h) + 1][h] (h: highest solid row below), or onto the back wall.
std::vector<std::string> check_voxel_faces(const VoxelModel& m, const CellGrid& g) {
  std::vector<std::string> problems;
  const auto at = [&](int x, int v) { return g.at(x + g.sheet.side, v + g.sheet.floor); };
  for (int x = 0; x < m.width; ++x) {
    for (int j = 0; j < m.depth; ++j) {
      for (int k = 0; k < m.h(x, j); ++k) {
        const std::string where =
            "voxel (" + std::to_string(x) + ", " + std::to_string(j) + ", " + std::to_string(k) + ")";
        if (k + 1 == m.h(x, j) && at(x, k - j) != CellGrid::pack(FaceKind::horizontal, k + 1)) {
          problems.push_back(where + ": top face is not an HFace at its height");
        }
        if (m.h(x, j + 1) > k) continue;  // no front face: the voxel in front is filled
        std::uint32_t expect = CellGrid::pack(FaceKind::vertical, j + 1);
        if (m.is_window(x, k)) {
          int hp = k - 1;
          while (hp >= 0 && m.is_window(x, hp)) --hp;
          expect = j - (k - hp) + 1 >= 0 ? CellGrid::pack(FaceKind::horizontal, hp + 1)
                                         : CellGrid::pack(FaceKind::vertical, 0);
        }
        if (at(x, k - j - 1) != expect) problems.push_back(where + ": front face cell shows the wrong face");
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
    const CellGrid g = make_cell_grid(m);
    auto voxel_faces = check_voxel_faces(m, g);
    ASSERT_TRUE(voxel_faces.empty()) << "every voxel face has its cell (Fig. 7, §2.3); " << what << join(voxel_faces);
    const Pattern p = make_pattern(g);
    auto surface = check_on_surface(m, p);
    ASSERT_TRUE(surface.empty()) << "paper lies on the voxel surface or a window's ledge; " << what << join(surface);
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
