// Tests of repair: the staircase closure (eq. 7) and check-guarded window marking (§3.2).
#include "popcut/design/repair.h"

#include <gtest/gtest.h>

#include <random>

#include "popcut/io/voxel_json.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
namespace {

TEST(Repair, FillsBehindTallerFrontColumns) {
  VoxelFile f;
  f.model = VoxelModel::empty(1, 3, 5, 1.0);
  f.model.h_at(0, 0) = 1;
  f.model.h_at(0, 1) = 4;  // a tower in front of a low block: breaks eq. 4
  f.model.h_at(0, 2) = 2;
  f.gap_rows.assign(f.model.windows.size(), 0);
  const RepairResult r = repair(f, {});
  EXPECT_EQ(r.model.h(0, 0), 4) << "the back column is filled up to the tower";
  EXPECT_EQ(r.model.h(0, 1), 4) << "the tower stays";
  EXPECT_EQ(r.model.h(0, 2), 2) << "the front column stays";
  EXPECT_EQ(r.cells_filled, 3) << "exactly the three cells behind the tower are added";
  EXPECT_FALSE(find_violation(r.model)) << "the result satisfies eq. 4";
}

TEST(Repair, FillsGapsFromAVoxelList) {
  const VoxelFile f = parse_voxel_file(
      R"({"format": "popcut.voxel.v1", "voxel_mm": 1, "voxels": [[0,0,0],[0,0,2],[1,0,0]]})", "gaps.json");
  EXPECT_EQ(f.gap_cells, 1) << "(0,0,1) is empty under (0,0,2)";
  const RepairResult r = repair(f, {});
  EXPECT_EQ(r.model.h(0, 0), 3) << "the gap is filled";
  EXPECT_EQ(r.cells_filled, 1) << "one cell was added";
}

TEST(Repair, WindowsKeptOnlyWhereTheCardPopsUp) {
  std::mt19937_64 rng(11);
  int added = 0;
  for (int trial = 0; trial < 150; ++trial) {
    VoxelFile f;
    f.model = VoxelModel::empty(1 + static_cast<int>(rng() % 5), 1 + static_cast<int>(rng() % 4),
                                1 + static_cast<int>(rng() % 6), 1.0);
    for (auto& h : f.model.heights) h = static_cast<int>(rng() % static_cast<unsigned>(f.model.height + 1));
    f.gap_rows.assign(f.model.windows.size(), 0);
    const RepairResult r = repair(f, {true});
    ASSERT_FALSE(find_violation(r.model)) << "trial " << trial;
    EXPECT_TRUE(check_popup(make_pattern(r.model)).pops_up()) << "trial " << trial << ": repair --windows must pop up";
    added += r.windows_added;
  }
  EXPECT_GT(added, 0) << "some filled rows become windows over 150 random models";
}

}  // namespace
}  // namespace popcut
