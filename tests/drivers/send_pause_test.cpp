// Pause and continue on the simulated cutter: the paused run and the resumed one cut every planned stroke once.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <string>

#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/motion_model.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/io/model_io.h"

namespace popcut::drivers {
namespace {

DeviceProfile profile_named(const std::string& stem) {
  return load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/" + stem + ".toml");
}

StrokePlan townhouse_plan(const DeviceProfile& p) {
  PlanOptions o = p.plan;
  o.optimise_work = 1000;  // these tests are about sending, not ordering
  return plan_strokes(make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json")), o);
}

// Sends the plan from `from` to the simulator, pausing once `pause_at` strokes are written (0: never).
SendResult send_from(const std::shared_ptr<SimCutter>& cutter, const DeviceProfile& p, const StrokePlan& plan,
                     std::size_t from, std::size_t pause_at) {
  SimTransport line(cutter);
  EXPECT_TRUE(line.open().ok());
  const EncodedJob job = encode_for_device(plan, p, from);
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job, p);
  std::atomic<bool> pause{false};
  o.pause = &pause;
  o.progress = [&](const SendProgress& at) {
    if (pause_at > 0 && at.last_stroke_written >= pause_at) pause = true;
  };
  const SendResult r = send_job(line, job, o);
  line.close();
  return r;
}

class SendPause : public ::testing::TestWithParam<const char*> {};

TEST_P(SendPause, PausedAndContinuedCutsEveryStrokeExactlyOnce) {
  const DeviceProfile p = profile_named(GetParam());
  const StrokePlan plan = townhouse_plan(p);
  auto cutter = std::make_shared<SimCutter>(p);
  const SendResult first = send_from(cutter, p, plan, 1, 0);
  const std::size_t total = first.total_strokes;
  ASSERT_GT(total, 6u);
  // The same device for both runs, as after a pause: a fresh cutter holds the union of the two.
  cutter = std::make_shared<SimCutter>(p);
  const SendResult paused = send_from(cutter, p, plan, 1, total / 3);
  ASSERT_TRUE(paused.paused_cleanly()) << paused.status.message;
  EXPECT_FALSE(paused.complete());
  EXPECT_FALSE(paused.cancelled);
  EXPECT_FALSE(paused.abort_sent) << "a pause sends no abort: the device keeps and cuts what it holds";
  const std::size_t k = paused.last_stroke_written;
  EXPECT_GE(k, total / 3);
  EXPECT_LT(k, total) << "paused before the end";
  EXPECT_EQ(paused.last_stroke_sent, k) << "drained: everything written was received";
  if (paused.last_stroke_executed) {
    EXPECT_EQ(*paused.last_stroke_executed, k) << "and executed";
  }
  ASSERT_TRUE(cutter->run_to_end());
  EXPECT_EQ(first_difference(planned_paths(plan, p.dialect, 1), cutter->strokes()).value_or(k), k)
      << "the paused run cut strokes 1..K exactly, no more";
  EXPECT_EQ(cutter->strokes().size(), k);

  const SendResult rest = send_from(cutter, p, plan, k + 1, 0);
  ASSERT_TRUE(rest.complete()) << rest.status.message;
  ASSERT_TRUE(cutter->run_to_end());
  EXPECT_FALSE(first_difference(planned_paths(plan, p.dialect, 1), cutter->strokes()))
      << "the union of both runs is the plan, each stroke once";
  EXPECT_TRUE(cutter->report().errors.empty());
  EXPECT_FALSE(cutter->report().outside_area);
}

TEST_P(SendPause, PauseBeforeTheFirstByteSendsNothing) {
  const DeviceProfile p = profile_named(GetParam());
  const StrokePlan plan = townhouse_plan(p);
  auto cutter = std::make_shared<SimCutter>(p);
  SimTransport line(cutter);
  ASSERT_TRUE(line.open().ok());
  const EncodedJob job = encode_for_device(plan, p, 1);
  SendOptions o = send_options(p);
  const std::atomic<bool> pause{true};
  o.pause = &pause;
  const SendResult r = send_job(line, job, o);
  EXPECT_TRUE(r.paused_cleanly()) << r.status.message;
  EXPECT_EQ(r.bytes_sent, 0u);
  EXPECT_EQ(r.last_stroke_written, 0u);
  EXPECT_TRUE(cutter->strokes().empty());
}

TEST_P(SendPause, CancelDuringThePauseWins) {
  const DeviceProfile p = profile_named(GetParam());
  const StrokePlan plan = townhouse_plan(p);
  auto cutter = std::make_shared<SimCutter>(p);
  SimTransport line(cutter);
  ASSERT_TRUE(line.open().ok());
  const EncodedJob job = encode_for_device(plan, p, 1);
  SendOptions o = send_options(p);
  const std::atomic<bool> both{true};
  o.pause = &both;
  o.cancel = &both;
  const SendResult r = send_job(line, job, o);
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.paused_cleanly());
}

INSTANTIATE_TEST_SUITE_P(Languages, SendPause, ::testing::Values("sim", "silhouette-cameo4"));

}  // namespace
}  // namespace popcut::drivers
