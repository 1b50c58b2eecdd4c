// Golden GP-GL: the exact bytes each shipped GP-GL profile produces for three models, reviewed and kept in
// tests/data/golden, and what the simulator cuts from them stroke by stroke against the plan.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/gpgl/gpgl.h"
#include "popcut/io/model_io.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Regenerate after an intended change with POPCUT_UPDATE_GOLDEN=1, then review the diff.
TEST(GoldenGpgl, EveryGpglProfileWritesTheReviewedBytes) {
  const std::string src = POPCUT_SOURCE_DIR;
  const bool update = std::getenv("POPCUT_UPDATE_GOLDEN") != nullptr;
  int profiles = 0;
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile prof = load_profile(file);
    if (prof.language != CutterLanguage::gpgl) continue;
    ++profiles;
    for (const char* model : {"examples/voxel/box.json", "examples/faces/porch.json", "tests/data/letter_f.json"}) {
      const StrokePlan plan = plan_strokes(make_pattern(load_model(src + "/" + model)), prof.plan);
      const std::string job = encode_for_device(plan, prof).bytes;
      const fs::path golden = fs::path(src) / "tests/data/golden" /
                              (fs::path(file).stem().string() + "-" + fs::path(model).stem().string() + ".gpgl");
      if (update) std::ofstream(golden, std::ios::binary) << job;
      ASSERT_TRUE(fs::exists(golden)) << golden << " is missing: run with POPCUT_UPDATE_GOLDEN=1";
      const std::string want = read_all(golden);
      EXPECT_EQ(job, want) << golden.filename() << ": the job changed; if intended, regenerate and review";
      EXPECT_EQ(want.rfind("\x1b\x04", 0), 0u) << golden.filename() << ": starts by initialising the device";

      // The reviewed bytes, sent to the simulated device, cut exactly the plan, each stroke with
      // its kind's holder, inside the area, with nothing the device would not know.
      auto cutter = std::make_shared<SimCutter>(prof);
      SimTransport t(cutter);
      ASSERT_TRUE(t.open().ok());
      EncodedJob sent = encode_for_device(plan, prof);
      sent.bytes = want;
      ASSERT_TRUE(send_job(t, sent, send_options(prof)).status.ok()) << golden.filename();
      ASSERT_TRUE(cutter->run_to_end());
      const auto planned = plan_in_plotter_units(plan, prof.dialect);
      const auto diff = first_difference(planned, cutter->strokes(), 0);
      EXPECT_FALSE(diff.has_value()) << golden.filename() << ": stroke " << diff.value_or(0) + 1 << " of "
                                     << planned.size() << " differs (" << cutter->strokes().size() << " cut)";
      const SimReport& r = cutter->report();
      EXPECT_FALSE(r.outside_area) << golden.filename();
      EXPECT_EQ(r.overflow_bytes, 0u) << golden.filename();
      EXPECT_TRUE(r.unknown.empty()) << golden.filename() << ": " << (r.unknown.empty() ? "" : r.unknown[0].command);
      EXPECT_TRUE(r.errors.empty()) << golden.filename() << ": " << (r.errors.empty() ? "" : r.errors[0].message);
      std::size_t k = 0;
      for (const Stroke& s : drop_below_resolution(plan, prof.dialect).strokes) {
        if (k >= cutter->strokes().size()) break;
        const ToolSetting& tool = prof.tools[index_of(s.kind)];
        EXPECT_EQ(cutter->strokes()[k].pen, tool.pen) << golden.filename() << " stroke " << k + 1;
        EXPECT_EQ(cutter->strokes()[k].force, prof.gpgl.force_level(tool.force_g)) << golden.filename();
        EXPECT_NEAR(cutter->strokes()[k].speed_cm_s,
                    prof.gpgl.speed_level(tool.speed_cm_s) * prof.gpgl.speed_cm_s_per_level, 1e-9)
            << golden.filename();
        ++k;
      }
    }
  }
  EXPECT_EQ(profiles, 5) << "the shipped GP-GL profiles: Cameo 3, Cameo 4, Portrait 3, Curio, CE6000";
}

}  // namespace
}  // namespace popcut::drivers
