// Status flow (paced by the motion model, corrected by idle/busy answers), the device's own stops (tray empty,
// paused) and a profile talking to a device of another language.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"
#include "popcut/io/model_io.h"
#include "send_line_fake.h"

namespace popcut::drivers {
namespace {

using testing::ScriptedLine;

std::string config(const std::string& name) { return std::string(POPCUT_SOURCE_DIR) + "/configs/devices/" + name; }

StrokePlan townhouse_plan(const DeviceProfile& p) {
  PlanOptions o = p.plan;
  o.optimise_work = 1000;  // a small work budget: these tests are about sending, not ordering
  return plan_strokes(make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json")), o);
}

// What a send to a fresh simulator of `p` (with `faults`) did, and what the simulator made of it.
struct StatusRun {
  SendResult sent;
  SimReport report;
  std::optional<std::size_t> mismatch;  // first_difference against the plan from the job's first stroke
  bool ran_to_end = false;
};

StatusRun run_on_sim(const DeviceProfile& p, const StrokePlan& plan, const EncodedJob& job, SimFaults faults = {}) {
  auto cutter = std::make_shared<SimCutter>(p, faults);
  SimTransport t(cutter);
  EXPECT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  StatusRun r;
  r.sent = send_job(t, job, o);
  r.ran_to_end = cutter->run_to_end();
  r.report = cutter->report();
  r.mismatch = first_difference(planned_paths(plan, p.dialect, job.first_stroke), cutter->strokes());
  return r;
}

// HP-GL's ESC.O says "buffer empty" as GP-GL's ESC ENQ says "ready": status flow keeps the device
// fed from the motion model and loses nothing, also on a device slower than the plan.
TEST(StatusFlow, KeepsADeviceThatAnswersIdleOrBusyFedAndWithinItsBuffer) {
  for (const std::size_t buffer : {256u, 1024u}) {
    DeviceProfile p = load_profile(config("sim.toml"));
    p.transport.flow = FlowControl::status;
    p.transport.drain_query = DrainQuery::esc_o;
    p.transport.buffer_bytes = buffer;
    const StrokePlan plan = townhouse_plan(p);
    const EncodedJob job = encode_for_device(plan, p);
    for (const double slowdown : {1.0, 1.2}) {
      const StatusRun r = run_on_sim(p, plan, job, SimFaults{std::nullopt, std::nullopt, slowdown});
      ASSERT_TRUE(r.sent.complete()) << buffer << ": " << r.sent.status.message;
      EXPECT_EQ(r.sent.drained_by, DrainedBy::esc_o);
      EXPECT_EQ(r.report.overflow_bytes, 0u) << buffer << " bytes, " << slowdown << " x slower";
      EXPECT_LE(r.report.max_buffer_used, buffer);
      EXPECT_FALSE(r.mismatch) << buffer << ": the sim cut the plan";
      EXPECT_EQ(r.sent.last_stroke_executed, job.total_strokes);
      if (slowdown == 1.0) {
        EXPECT_LE(r.report.clock_s, 1.05 * r.report.motion_time_s)
            << buffer << " bytes: " << r.report.clock_s << " s for " << r.report.motion_time_s << " s of motion";
      }
    }
  }
}

// Status flow is paced by idle/busy answers: a profile without such a query, or with one its
// language does not have, is refused naming the key.
TEST(StatusFlow, AProfileNeedsAQueryThatSaysIdleOrBusy) {
  const std::string base = "[device]\nname = \"x\"\n[transport]\n";
  const auto refusal = [&](const std::string& text) {
    try {
      parse_profile(base + text, "s.toml");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal("flow_control = \"status\"\n")
                .find("[transport] flow_control: \"status\" paces by the device's ready/busy answers: it needs "
                      "drain_query \"esc_o\""),
            std::string::npos)
      << refusal("flow_control = \"status\"\n");
  EXPECT_NE(refusal("flow_control = \"status\"\ndrain_query = \"esc_b\"\n").find("use flow_control \"esc_b\""),
            std::string::npos);
  EXPECT_NE(refusal("drain_query = \"esc_enq\"\n")
                .find("[transport] drain_query: \"esc_enq\" is not a query of [device] language \"hpgl\", whose "
                      "devices answer \"esc_b\" or \"esc_o\""),
            std::string::npos)
      << refusal("drain_query = \"esc_enq\"\n");
  EXPECT_EQ(parse_profile(base + "flow_control = \"status\"\ndrain_query = \"esc_o\"\n", "s.toml").transport.flow,
            FlowControl::status);
}

// An HP-GL device answers ESC.O with a number and CR; a GP-GL one that gets it and answers with
// ETX is named as such before any byte of the job.
TEST(WrongLanguage, AnHpglProfileHearingGpglAnswersSaysSo) {
  ScriptedLine line;
  line.default_answer = "0\x03";
  SendOptions o;
  o.drain_query = DrainQuery::esc_o;
  o.timeout = std::chrono::milliseconds(200);
  const SendResult r = send_job(line, std::string_view("IN;PU0,0;PD10,0;"), o);
  EXPECT_FALSE(r.status.ok());
  EXPECT_EQ(r.bytes_sent, 0u) << "caught before the first stroke";
  EXPECT_NE(r.status.message.find("an HP-GL profile seems to be talking to a device that speaks GP-GL"),
            std::string::npos)
      << r.status.message;
}

}  // namespace
}  // namespace popcut::drivers
