// The face path equals the voxel path: same faces, lines and pop-up verdict over random models.
#include "popcut/pattern/face_pattern.h"

#include <gtest/gtest.h>

#include <random>

#include "pattern_compare.h"
#include "pattern_oracle.h"
#include "popcut/io/voxel_json.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"

namespace popcut {
namespace {

TEST(FacePattern, MatchesTheVoxelPathOnRandomModels) {
  std::mt19937_64 rng(99);
  testing::RandomModelSpec spec;
  spec.max_width = 5;
  spec.max_depth = 4;
  spec.max_height = 5;
  spec.window_probability = 0.3;
  spec.random_sheet = true;
  int failing = 0;
  const int trials = 250;
  for (int trial = 0; trial < trials; ++trial) {
    const VoxelModel m = testing::random_model(rng, spec);
    const Pattern voxel = make_pattern(m);
    const Pattern faces = make_pattern(to_face_model(m));
    const std::string diff = testing::compare_patterns(voxel, faces);
    ASSERT_EQ(diff, "") << "trial " << trial << ": the two paths disagree for\n" << to_voxel_json(m);
    const auto lines = testing::check_lines(faces, m.voxel_mm);
    ASSERT_TRUE(lines.empty()) << "trial " << trial << ": " << lines.front();
    failing += !check_popup(faces).pops_up();
  }
  EXPECT_GT(failing, 0) << "the sample includes cards that do not pop up";
}

}  // namespace
}  // namespace popcut
