// Tests of the voxel model rules, sheet sizing and the editor operations of voxel paper §2.7.
#include "popcut/model/voxel_model.h"

#include <gtest/gtest.h>

#include <random>

#include "popcut/error.h"
#include "random_models.h"

namespace popcut {
namespace {

VoxelModel box(int w, int d, int h) {
  VoxelModel m = VoxelModel::empty(w, d, h, 1.0);
  for (int x = 0; x < w; ++x)
    for (int y = 0; y < d; ++y) m.h_at(x, y) = h;
  return m;
}

TEST(VoxelModel, ValidBoxHasNoViolation) {
  EXPECT_FALSE(find_violation(box(3, 2, 4))) << "a solid box satisfies the staircase constraint";
}

TEST(VoxelModel, RisingColumnIsNamed) {
  VoxelModel m = box(2, 3, 4);
  m.h_at(1, 0) = 2;  // column (1,1) = 4 now rises above (1,0) = 2
  auto v = find_violation(m);
  ASSERT_TRUE(v) << "a column higher than the one behind it breaks eq. 4";
  EXPECT_EQ(v->field, "heights[1][1]") << "the first offending x, y is named";
  EXPECT_NE(v->message.find("heights[1][0] = 2"), std::string::npos) << v->message;
}

TEST(VoxelModel, WindowAboveColumnIsRejected) {
  VoxelModel m = box(2, 1, 4);
  m.h_at(1, 0) = 2;
  m.set_window(1, 3, true);
  auto v = find_violation(m);
  ASSERT_TRUE(v) << "a window on a row without a front face is meaningless";
  EXPECT_NE(v->message.find("no front face"), std::string::npos) << v->message;
}

TEST(VoxelModel, AddVoxelFillsBehindAndBelow) {
  VoxelModel m = VoxelModel::empty(1, 4, 5, 1.0);
  add_voxel(m, 0, 2, 3);
  for (int y = 0; y <= 2; ++y) EXPECT_EQ(m.h(0, y), 4) << "cells behind and below (0,2,3) are filled, y=" << y;
  EXPECT_EQ(m.h(0, 3), 0) << "cells in front stay empty";
  EXPECT_FALSE(find_violation(m)) << "add keeps the staircase";
}

TEST(VoxelModel, RemoveVoxelClearsInFrontAndAbove) {
  VoxelModel m = box(1, 4, 5);
  m.set_window(0, 4, true);
  remove_voxel(m, 0, 1, 2);
  EXPECT_EQ(m.h(0, 0), 5) << "column behind is untouched";
  for (int y = 1; y < 4; ++y) EXPECT_EQ(m.h(0, y), 2) << "cells in front and above (0,1,2) are cleared, y=" << y;
  remove_voxel(m, 0, 0, 3);
  EXPECT_EQ(m.h(0, 0), 3) << "removing at the back lowers the back column";
  EXPECT_FALSE(m.is_window(0, 4)) << "a window above the new top is cleared with it";
  EXPECT_FALSE(find_violation(m)) << "remove keeps the staircase";
}

TEST(VoxelModel, ToggleWindowNeedsAFrontFace) {
  VoxelModel m = box(1, 1, 3);
  toggle_window(m, 0, 1);
  EXPECT_TRUE(m.is_window(0, 1)) << "toggle sets the window";
  toggle_window(m, 0, 1);
  EXPECT_FALSE(m.is_window(0, 1)) << "toggle again clears it";
  m.h_at(0, 0) = 1;
  EXPECT_THROW(toggle_window(m, 0, 2), Error) << "row 2 has no front face on a column of height 1";
  EXPECT_THROW(add_voxel(m, 0, 1, 0), Error) << "y = 1 is outside a grid of depth 1";
}

TEST(VoxelModel, RandomEditsKeepTheConstraint) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    VoxelModel m = VoxelModel::empty(4, 5, 6, 1.0);
    for (int op = 0; op < 40; ++op) {
      const int x = static_cast<int>(rng() % 4), y = static_cast<int>(rng() % 5), z = static_cast<int>(rng() % 6);
      switch (rng() % 3) {
        case 0: add_voxel(m, x, y, z); break;
        case 1: remove_voxel(m, x, y, z); break;
        default:
          if (z < m.h(x, 0)) toggle_window(m, x, z);
      }
      ASSERT_FALSE(find_violation(m)) << "trial " << trial << " op " << op << ": " << find_violation(m)->message;
    }
  }
}

TEST(VoxelModel, SheetDefaultsEncloseTheClosedCard) {
  VoxelModel m = box(2, 3, 4);  // deepest point: y = 2, h = 4 → 2 + 4 + 1 = 7
  EXPECT_EQ(min_sheet_half_voxels(m), 7) << "max(y + h + 1)";
  const SheetVoxels s = resolve_sheet(m, "m.json");
  EXPECT_EQ(s.back, 7 + kDefaultSheetMarginVoxels) << "default back = minimum + margin";
  EXPECT_EQ(s.floor, 7 + kDefaultSheetMarginVoxels) << "default floor = minimum + margin";
  EXPECT_EQ(s.side, kDefaultSideVoxels) << "default side columns";
}

TEST(VoxelModel, SheetTooSmallSaysTheMinimum) {
  VoxelModel m = box(2, 3, 4);
  m.sheet.back = 6;
  try {
    resolve_sheet(m, "m.json");
    FAIL() << "a back half of 6 cannot enclose a model that needs 7";
  } catch (const Error& e) {
    EXPECT_EQ(e.location(), "sheet.back") << e.what();
    EXPECT_NE(e.message().find("at least 7 voxels"), std::string::npos) << e.what();
  }
}

TEST(VoxelModel, PatternCellLimitIsEnforced) {
  VoxelModel m = VoxelModel::empty(4096, 1, 1, 1.0);
  m.sheet.back = 4096;
  m.sheet.floor = 4096;
  try {
    resolve_sheet(m, "big.json");
    FAIL() << "a 4100 x 8192 sheet is over the documented cell limit";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::limit) << e.what();
  }
}

}  // namespace
}  // namespace popcut
