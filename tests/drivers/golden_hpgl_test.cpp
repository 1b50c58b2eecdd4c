// Golden HP-GL: the exact bytes each shipped profile produces for three models, reviewed and kept in tests/data/golden.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/io/model_io.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

namespace fs = std::filesystem;

// Regenerate after an intended change with POPCUT_UPDATE_GOLDEN=1, then review the diff.
TEST(GoldenHpgl, EveryProfileWritesTheReviewedBytes) {
  const std::string src = POPCUT_SOURCE_DIR;
  const bool update = std::getenv("POPCUT_UPDATE_GOLDEN") != nullptr;
  // letter_f is asymmetric: orientation_test.cpp checks these jobs are not mirrored.
  for (const char* model : {"examples/voxel/box.json", "examples/faces/porch.json", "tests/data/letter_f.json"}) {
    const Pattern pattern = make_pattern(load_model(src + "/" + model));
    for (const std::string& file : testing::shipped_profiles()) {
      const DeviceProfile prof = load_profile(file);
      if (prof.language != CutterLanguage::hpgl) continue;  // golden_gpgl_test.cpp
      const StrokePlan plan = plan_strokes(pattern, prof.plan);
      const std::string job = encode_hpgl(plan, prof.dialect, prof.tools);
      EXPECT_EQ(encode_for_device(plan, prof).bytes, job) << file << ": the profile's language writes these bytes";
      const fs::path golden = fs::path(src) / "tests/data/golden" /
                              (fs::path(file).stem().string() + "-" + fs::path(model).stem().string() + ".hpgl");
      if (update) std::ofstream(golden, std::ios::binary) << job;
      std::ifstream in(golden, std::ios::binary);
      ASSERT_TRUE(in.good()) << golden << " is missing: run with POPCUT_UPDATE_GOLDEN=1";
      std::stringstream want;
      want << in.rdbuf();
      EXPECT_EQ(job, want.str()) << golden.filename() << ": the job changed; if intended, regenerate and review";
    }
  }
}

}  // namespace
}  // namespace popcut::drivers
