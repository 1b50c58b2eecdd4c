// Status flow (paced by the motion model, corrected by idle/busy answers), the device's own stops (tray empty,
// paused) and a profile talking to a device of another language.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
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

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

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

// Status flow on `p` with 256- and 1024-byte buffers, as fast as the plan and 20 % slower: kept a
// buffer ahead of the model, never stopped between chunks, drained by `drained`; the cut is the plan.
void expect_fed_and_exact(DeviceProfile p, DrainedBy drained) {
  for (const std::size_t buffer : {256u, 1024u}) {
    p.transport.buffer_bytes = buffer;
    const StrokePlan plan = townhouse_plan(p);
    const EncodedJob job = encode_for_device(plan, p);
    for (const double slowdown : {1.0, 1.2}) {
      const StatusRun r = run_on_sim(p, plan, job, SimFaults{std::nullopt, std::nullopt, slowdown});
      ASSERT_TRUE(r.sent.complete()) << p.name << ", " << buffer << ": " << r.sent.status.message;
      EXPECT_EQ(r.sent.drained_by, drained);
      EXPECT_EQ(r.sent.received_counted_by, ReceivedCountedBy::transport) << "the simulator's writes are its count";
      EXPECT_EQ(r.report.overflow_bytes, 0u) << p.name << ", " << buffer << " bytes, " << slowdown << " x slower";
      EXPECT_LE(r.report.max_buffer_used, buffer);
      EXPECT_FALSE(r.mismatch) << p.name << ", " << buffer << ": the sim cut the plan";
      EXPECT_EQ(r.sent.last_stroke_executed, job.total_strokes) << "the idle answer at the end: all of it executed";
      if (slowdown == 1.0) {
        EXPECT_LE(r.report.clock_s, 1.05 * r.report.motion_time_s)
            << p.name << ", " << buffer << " bytes: " << r.report.clock_s << " s for " << r.report.motion_time_s
            << " s of motion";
      }
    }
  }
}

// HP-GL's ESC.O says "buffer empty" as GP-GL's ESC ENQ says "ready": status flow works on either.
TEST(StatusFlow, KeepsADeviceThatAnswersIdleOrBusyFedAndWithinItsBuffer) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.flow = FlowControl::status;
  p.transport.drain_query = DrainQuery::esc_o;
  expect_fed_and_exact(p, DrainedBy::esc_o);
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

// The shipped Cameo 4: paced by status.
DeviceProfile cameo() {
  DeviceProfile p = load_profile(config("silhouette-cameo4.toml"));
  EXPECT_EQ(p.transport.flow, FlowControl::status);
  return p;
}

TEST(GpglStatus, AGpglProfileAsksEscEnqAndNothingHpglOnly) {
  const DeviceProfile p = load_profile(config("silhouette-cameo4.toml"));
  EXPECT_EQ(p.transport.drain_query, DrainQuery::esc_enq) << "the language's own query by default";
  EXPECT_EQ(p.transport.flow, FlowControl::status);
  const std::string text = slurp(config("silhouette-cameo4.toml"));
  const auto refusal = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    try {
      parse_profile(t, "cameo.toml");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string flow = "flow_control = \"status\"";
  EXPECT_NE(refusal(flow, "flow_control = \"esc_b\"")
                .find("[transport] flow_control: \"esc_b\" asks ESC.B for free buffer space, which [device] language "
                      "\"gpgl\" devices do not answer: use \"status\""),
            std::string::npos)
      << refusal(flow, "flow_control = \"esc_b\"");
  EXPECT_NE(refusal(flow, flow + "\ndrain_query = \"esc_o\"")
                .find("[transport] drain_query: \"esc_o\" is not a query of [device] language \"gpgl\", whose devices "
                      "answer \"esc_enq\""),
            std::string::npos);
  EXPECT_NE(refusal(flow, flow + "\nerror_query = \"esc_e\"").find("[transport] error_query"), std::string::npos);
  EXPECT_NE(refusal(flow, flow + "\ndrain_query = \"none\"").find("it needs drain_query \"esc_enq\""),
            std::string::npos);
}

TEST(GpglStatus, StatusFlowKeepsACameoFedAndCutsThePlan) { expect_fed_and_exact(cameo(), DrainedBy::esc_enq); }

TEST(GpglStatus, NoSheetLoadedRefusesTheJobBeforeAnyByte) {
  const DeviceProfile p = cameo();
  const StrokePlan plan = townhouse_plan(p);
  const EncodedJob job = encode_for_device(plan, p);
  SimFaults faults;
  faults.tray_empty_after_bytes = 0;
  const StatusRun r = run_on_sim(p, plan, job, faults);
  EXPECT_FALSE(r.sent.status.ok());
  EXPECT_EQ(r.sent.device_stop, DeviceStop::tray_empty);
  EXPECT_FALSE(r.sent.cancelled);
  EXPECT_EQ(r.sent.bytes_sent, 0u);
  EXPECT_FALSE(r.sent.abort_sent) << "nothing to abort";
  EXPECT_EQ(r.report.bytes_received, 2u) << "ESC ENQ only";
  EXPECT_EQ(r.report.knife_downs, 0);
  EXPECT_EQ(r.sent.status.message.rfind("no sheet loaded: the device reports its tray empty (ESC ENQ answer), before "
                                        "any byte of the job was sent",
                                        0),
            0u)
      << r.sent.status.message;
}

// The sheet running out or the pause key mid-job ends it like a cancel: the command in flight,
// then the knife-up; the device keeps what it holds, and once it goes on it cuts that, so
// --resume-from M+1 cuts exactly the rest (M+1..N twice at most, as the advice says).
TEST(GpglStatus, ADeviceThatStopsMidJobEndsItWithTheKnifeUpAndTheResumeCutsTheRest) {
  DeviceProfile p = cameo();
  p.transport.buffer_bytes = 256;  // a quarter of the job ahead, so that it stops mid-job
  const StrokePlan plan = townhouse_plan(p);
  const EncodedJob job = encode_for_device(plan, p);
  const std::vector<PlotterPath> planned = planned_paths(plan, p.dialect, 1);
  for (const DeviceStop why : {DeviceStop::tray_empty, DeviceStop::paused}) {
    SimFaults faults;
    (why == DeviceStop::tray_empty ? faults.tray_empty_after_bytes : faults.pause_after_bytes) = job.bytes.size() / 3;
    auto cutter = std::make_shared<SimCutter>(p, faults);
    SimTransport t(cutter);
    ASSERT_TRUE(t.open().ok());
    SendOptions o = send_options(p);
    o.motion = motion_schedule(job.bytes, p);
    const SendResult sent = send_job(t, job, o);
    const std::string what = to_string(why);
    EXPECT_EQ(sent.device_stop, why) << what;
    EXPECT_FALSE(sent.status.ok()) << what;
    EXPECT_FALSE(sent.cancelled) << what;
    EXPECT_TRUE(sent.abort_sent) << what << ": the knife-up went out";
    EXPECT_LT(sent.bytes_sent, job.bytes.size() / 3 + 256 + 64) << what << ": stopped soon after";
    EXPECT_NE(sent.status.message.find(why == DeviceStop::tray_empty ? "no sheet loaded" : "the device is paused"),
              std::string::npos)
        << sent.status.message;
    ASSERT_LE(sent.last_stroke_sent, sent.last_stroke_written);
    ASSERT_LT(sent.last_stroke_sent, job.total_strokes);
    EXPECT_LE(sent.last_stroke_executed.value_or(0), sent.last_stroke_sent);
    // The device goes on: it cuts what it holds, then lifts the knife.
    cutter->set_media_loaded(true);
    cutter->set_paused(false);
    ASSERT_TRUE(cutter->run_to_end());
    EXPECT_FALSE(cutter->knife_down()) << what << ": popcut's knife-up ends what it holds";
    const std::size_t cut = cutter->strokes().size();
    EXPECT_GE(cut, sent.last_stroke_sent) << what << ": it had received M strokes";
    EXPECT_LE(cut, sent.last_stroke_written) << what;
    EXPECT_FALSE(first_difference(std::vector<PlotterPath>(planned.begin(), planned.begin() + static_cast<long>(cut)),
                                  cutter->strokes()))
        << what << ": what it cut is the plan's first strokes";
    const StatusRun rest = run_on_sim(p, plan, encode_for_device(plan, p, sent.last_stroke_sent + 1));
    ASSERT_TRUE(rest.sent.complete()) << rest.sent.status.message;
    EXPECT_FALSE(rest.mismatch) << what << ": the resume cuts strokes M+1.. exactly";
  }
}

// GP-GL's init (ESC EOT) resets the device: a job sent while it still cuts an earlier one (a
// resume sent at once, say) waits until it answers ready, so the earlier strokes are all cut.
TEST(GpglStatus, AJobWaitsForTheDeviceToFinishAnEarlierOneBeforeItsInitResetsIt) {
  const DeviceProfile p = cameo();
  const StrokePlan plan = townhouse_plan(p);
  const EncodedJob job = encode_for_device(plan, p);
  auto cutter = std::make_shared<SimCutter>(p);
  cutter->preload(job.bytes);  // the earlier job, all in its buffer: it is cutting
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  const SendResult sent = send_job(t, job, o);
  ASSERT_TRUE(sent.complete()) << sent.status.message;
  ASSERT_TRUE(cutter->run_to_end());
  EXPECT_EQ(cutter->strokes().size(), 2 * job.total_strokes) << "both jobs cut whole, one after the other";
  EXPECT_GT(sent.status_queries, 3) << "asked until the device was ready";

  // A device that stays busy past hold_timeout: nothing is sent, and the message says why.
  auto stuck = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, std::nullopt, 50});
  stuck->preload(job.bytes);
  SimTransport st(stuck);
  ASSERT_TRUE(st.open().ok());
  o.hold_timeout = std::chrono::milliseconds(5000);
  const SendResult refused = send_job(st, job, o);
  EXPECT_FALSE(refused.status.ok());
  EXPECT_EQ(refused.bytes_sent, 0u);
  EXPECT_NE(refused.status.message.find("still busy"), std::string::npos) << refused.status.message;
}

// An HP-GL plotter ignores ESC ENQ: a GP-GL profile talking to one hears nothing and says which
// mistake that likely is, before the first stroke.
TEST(WrongLanguage, AGpglProfileTalkingToAnHpglDeviceSaysSo) {
  const DeviceProfile gpgl = cameo();
  const DeviceProfile hpgl = load_profile(config("sim.toml"));
  const StrokePlan plan = townhouse_plan(gpgl);
  const EncodedJob job = encode_for_device(plan, gpgl);
  auto cutter = std::make_shared<SimCutter>(hpgl);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(gpgl);
  o.motion = motion_schedule(job.bytes, gpgl);
  const SendResult r = send_job(t, job, o);
  EXPECT_FALSE(r.status.ok());
  EXPECT_EQ(r.bytes_sent, 0u) << "caught before the first stroke";
  EXPECT_EQ(cutter->report().knife_downs, 0);
  EXPECT_NE(r.status.message.find("the device did not answer ESC ENQ before sending within 5000 ms: a GP-GL profile "
                                  "seems to be talking to a device that does not speak GP-GL (an HP-GL plotter "
                                  "ignores ESC ENQ): check [device] language"),
            std::string::npos)
      << r.status.message;
  // An HP-GL answer (a number and CR) says so too.
  ScriptedLine line;
  line.default_answer = "8\r\n";
  o.timeout = std::chrono::milliseconds(200);
  o.motion.clear();
  const SendResult heard = send_job(line, job, o);
  EXPECT_EQ(heard.bytes_sent, 0u);
  EXPECT_NE(heard.status.message.find("its answer ends in CR, as an HP-GL plotter's does"), std::string::npos)
      << heard.status.message;
}

}  // namespace
}  // namespace popcut::drivers
