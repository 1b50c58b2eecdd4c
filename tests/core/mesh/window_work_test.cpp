// The windows phase's work follows the card's faces, not its area: a thin tall plate (openscad's issue945f) imports in
// a bounded number of steps.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>

#include "popcut/mesh/mesh_import.h"
#include "popcut/model/voxel_model.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "test_meshes.h"

namespace popcut {
namespace {

using P = std::array<double, 3>;

void add_triangle(TriangleSoup& s, P a, P b, P c) {
  const auto i = static_cast<std::uint32_t>(s.points.size());
  s.points.insert(s.points.end(), {a, b, c});
  s.triangles.push_back({i, i + 1, i + 2});
}

// A triangle in the (y, z) plane extruded from x0 to x1: its caps and three sides.
void add_wedge(TriangleSoup& s, double x0, double x1, std::array<std::array<double, 2>, 3> yz) {
  const auto at = [&](double x, int k) {
    return P{x, yz[static_cast<std::size_t>(k)][0], yz[static_cast<std::size_t>(k)][1]};
  };
  add_triangle(s, at(x0, 0), at(x0, 1), at(x0, 2));
  add_triangle(s, at(x1, 0), at(x1, 2), at(x1, 1));
  for (int k = 0; k < 3; ++k) {
    add_triangle(s, at(x0, k), at(x1, k), at(x1, (k + 1) % 3));
    add_triangle(s, at(x0, k), at(x1, (k + 1) % 3), at(x0, (k + 1) % 3));
  }
}

// The shape of openscad-testing-data's issue945f.stl: a plate 3 wide, 48 deep, 60 tall, seen
// edge-on from the front, with a wedge standing out of its front face halfway up; eq. 7 fills
// everything under the wedge, so every slice has hundreds of window candidates.
TriangleSoup thin_plate() {
  TriangleSoup s;
  testing::add_box(s, 0, -20, 0, 3, 28, 60);
  add_wedge(s, 0, 3, {{{-20, 32}, {-29.6066, 22.3934}, {-20, 12.7868}}});
  return s;
}

struct Work {
  std::int64_t decisions = 0, work = 0, full_checks = 0;
  std::int64_t faces = 0, columns = 0;
};

Work windows_work(const TriangleSoup& mesh, int resolution) {
  ImportOptions o;
  o.resolution = resolution;
  const ImportResult r = import_mesh(mesh, o, "plate");
  const Pattern p = make_pattern(r.model);
  EXPECT_TRUE(check_popup(p).pops_up()) << "the card still pops up";
  Work w;
  w.decisions = r.stats.windows_added + r.stats.windows_rejected;
  w.work = r.stats.window_work;
  w.full_checks = r.stats.window_full_checks;
  w.faces = static_cast<std::int64_t>(p.faces.size());
  w.columns = r.model.width + 2 * resolve_sheet(r.model, "plate").side;
  std::printf("%d across: %lld decisions, %lld work (%.0f a decision), %lld faces, %lld columns, %lld full checks\n",
              resolution, static_cast<long long>(w.decisions), static_cast<long long>(w.work),
              static_cast<double>(w.work) / static_cast<double>(std::max<std::int64_t>(1, w.decisions)),
              static_cast<long long>(w.faces), static_cast<long long>(w.columns),
              static_cast<long long>(w.full_checks));
  return w;
}

// Each decision re-labels the few faces the window touches and walks the graph of the card's
// faces. Re-walking everything a window could reach instead would cover nearly all of this card
// (1,600 rows high at 80 across) on each of its ~47,680 decisions: minutes, not seconds.
void expect_bounded(const Work& w) {
  ASSERT_GT(w.decisions, 1000) << "the plate gives many window candidates";
  EXPECT_LE(w.work, w.decisions * 6 * (w.faces + w.columns))
      << "work per decision follows the faces and slices, not the card's area";
  EXPECT_EQ(w.full_checks, 0) << "no decision needs the full check";
}

TEST(WindowWork, ThinTallPlateIsBoundedByItsFaces) { expect_bounded(windows_work(thin_plate(), 40)); }

TEST(WindowWork, InstalledIssue945Meshes) {
  int found = 0;
  for (const char* name : {"issue945e.stl", "issue945f.stl"}) {
    const std::filesystem::path path = std::filesystem::path("/usr/share/openscad/testdata/scad/bugs") / name;
    if (!std::filesystem::exists(path)) continue;
    ++found;
    expect_bounded(windows_work(read_mesh(path.string()), 80));
  }
  if (found == 0) GTEST_SKIP() << "openscad-testing-data is not installed (issue945e.stl, issue945f.stl)";
}

}  // namespace
}  // namespace popcut
