// Streaming seam: stroke-numbered jobs, resume, cancel with abort, drain, and device strings.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <utility>
#include <vector>

#include "popcut/drivers/device.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"
#include "popcut/io/model_io.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

std::string config(const std::string& name) { return std::string(POPCUT_SOURCE_DIR) + "/configs/devices/" + name; }

StrokePlan townhouse_plan(const DeviceProfile& p) {
  const std::string path = std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json";
  PlanOptions o = p.plan;
  o.optimise_work = 1000;  // a small work budget: these tests are about sending, not ordering
  return plan_strokes(make_pattern(load_model(path)), o);
}

// Sends `job` to a fresh simulator of `p`; returns what it cut.
struct SimRun {
  SendResult sent;
  std::vector<SimStroke> strokes;
  SimReport report;
};
// As `popcut cut --device sim` runs it: paced by the device's motion where it has no handshake.
SimRun run_on_sim(const DeviceProfile& p, const EncodedJob& job, SendOptions o) {
  if (o.motion.empty()) o.motion = motion_schedule(job.bytes, p);
  auto cutter = std::make_shared<SimCutter>(p);
  SimTransport t(cutter);
  EXPECT_TRUE(t.open().ok());
  SimRun r;
  r.sent = send_job(t, job, o);
  EXPECT_TRUE(cutter->run_to_end()) << "the simulator finishes what it got";
  r.strokes = cutter->strokes();
  r.report = cutter->report();
  return r;
}

TEST(EncodedJob, StrokeEndsFollowTheBytes) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = load_profile(file);
    const StrokePlan plan = townhouse_plan(p);
    const EncodedJob job = encode_job(plan, p.dialect, p.tools);
    EXPECT_EQ(job.bytes, encode_hpgl(plan, p.dialect, p.tools)) << file << ": encode_hpgl is the whole job";
    EXPECT_EQ(job.total_strokes, plan_in_plotter_units(plan, p.dialect).size())
        << file << ": strokes are the sent paths";
    ASSERT_EQ(job.stroke_end.size(), job.total_strokes) << file;
    ASSERT_FALSE(job.command_end.empty()) << file;
    EXPECT_EQ(job.command_end.back(), job.bytes.size()) << file << ": the last command ends the job";
    EXPECT_TRUE(std::is_sorted(job.stroke_end.begin(), job.stroke_end.end())) << file;
    for (std::size_t i = 0; i < job.stroke_end.size(); ++i) {
      EXPECT_TRUE(std::binary_search(job.command_end.begin(), job.command_end.end(), job.stroke_end[i]))
          << file << ": stroke " << i + 1 << " ends on a command boundary";
      EXPECT_EQ(job.last_stroke_within(job.stroke_end[i]), i + 1)
          << file << ": its last byte completes stroke " << i + 1;
      EXPECT_EQ(job.last_stroke_within(job.stroke_end[i] - 1), i) << file << ": one byte short it is not complete";
      ASSERT_EQ(job.stroke_cut_start.size(), job.stroke_end.size()) << file;
      EXPECT_EQ(job.bytes.compare(job.stroke_cut_start[i], 2, "PD"), 0)
          << file << ": stroke " << i + 1 << " cuts from a knife-down";
      EXPECT_EQ(job.bytes.find("PD", i ? job.stroke_end[i - 1] : 0), job.stroke_cut_start[i])
          << file << ": its first knife-down";
      EXPECT_TRUE(std::binary_search(job.command_end.begin(), job.command_end.end(), job.stroke_cut_start[i]))
          << file << ": on a boundary";
    }
  }
}

TEST(EncodedJob, ResumeSendsExactlyTheMissingStrokesKnifeUp) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = load_profile(file);
    const StrokePlan plan = townhouse_plan(p);
    const auto planned = plan_in_plotter_units(plan, p.dialect);
    ASSERT_GT(planned.size(), 10u) << file;
    for (std::size_t from : {std::size_t{2}, planned.size() / 2, planned.size()}) {
      const EncodedJob job = encode_for_device(plan, p, from);  // in the profile's language
      EXPECT_EQ(job.first_stroke, from) << file;
      const EncodedJob whole = encode_for_device(plan, p);
      EXPECT_EQ(job.bytes.compare(0, whole.command_end[0], whole.bytes, 0, whole.command_end[0]), 0)
          << file << " from " << from << ": re-sends init";
      const SimRun r = run_on_sim(p, job, send_options(p));
      ASSERT_TRUE(r.sent.complete()) << file << " from " << from << ": " << r.sent.status.message;
      EXPECT_EQ(r.sent.last_stroke_sent, planned.size()) << file << " from " << from;
      const std::vector<PlotterPath> missing(planned.begin() + static_cast<std::ptrdiff_t>(from - 1), planned.end());
      const auto diff = first_difference(missing, r.strokes);
      EXPECT_FALSE(diff.has_value()) << file << " from " << from << ": cut " << r.strokes.size() << " strokes for "
                                     << missing.size() << " missing, first difference at " << diff.value_or(0);
      EXPECT_EQ(r.report.knife_downs, static_cast<int>(missing.size()))
          << file << " from " << from << ": the knife goes down once per stroke, never on the way to the first";
      if (!r.strokes.empty()) {
        EXPECT_GT(r.strokes.front().pen, 0)
            << file << " from " << from << ": tool setup re-sent before the first stroke";
      }
    }
    EXPECT_THROW(encode_for_device(plan, p, 0), Error) << file << ": strokes are numbered from 1";
    EXPECT_THROW(encode_for_device(plan, p, planned.size() + 1), Error) << file << ": past the last stroke";
  }
}

TEST(SendJob, CancelStopsOnACommandBoundaryAndLiftsTheKnife) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.abort = "\x1b.K";
  const StrokePlan plan = townhouse_plan(p);
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  const auto planned = plan_in_plotter_units(plan, p.dialect);
  std::atomic<bool> cancel{false};
  SendOptions o = send_options(p);
  EXPECT_EQ(o.abort_bytes, "\x1b.KPU;") << "profile abort, then knife up in the dialect";
  o.cancel = &cancel;
  int chunks = 0;
  o.progress = [&](const SendProgress&) {
    if (++chunks == 7) cancel = true;
  };
  const SimRun r = run_on_sim(p, job, o);
  EXPECT_TRUE(r.sent.cancelled) << "the flag was seen";
  EXPECT_FALSE(r.sent.complete());
  EXPECT_TRUE(r.sent.abort_sent) << r.sent.status.message;
  EXPECT_LT(r.sent.bytes_sent, job.bytes.size()) << "it stopped early";
  EXPECT_TRUE(std::binary_search(job.command_end.begin(), job.command_end.end(), r.sent.bytes_sent))
      << "stopped at a command boundary: byte " << r.sent.bytes_sent;
  EXPECT_EQ(r.sent.last_stroke_written, job.last_stroke_within(r.sent.bytes_sent));
  EXPECT_LE(r.sent.last_stroke_sent, r.sent.last_stroke_written) << "received never exceeds written";
  EXPECT_EQ(r.report.bytes_received,
            r.sent.bytes_sent + 3 * static_cast<std::size_t>(r.sent.status_queries) + o.abort_bytes.size())
      << "job bytes and ESC.O status queries, then exactly the abort";
  EXPECT_LE(r.sent.buffered_bytes, p.transport.buffer_bytes + r.sent.bytes_sent - r.sent.bytes_received)
      << "an honest bound: at most the device's buffer and what was on its way";
  EXPECT_GE(r.sent.buffered_last_stroke, r.sent.last_stroke_written)
      << "the strokes it may still cut run to the last one sent";
  // Everything cut is a prefix of the plan (ESC.K discarded the rest), and covers every stroke
  // counted received: ESC.K leaves received at what the device executed.
  EXPECT_TRUE(r.sent.buffer_discarded);
  EXPECT_GE(r.strokes.size(), r.sent.last_stroke_sent) << "no stroke counted received was left uncut";
  ASSERT_LE(r.strokes.size(), r.sent.last_stroke_written + 1);
  for (std::size_t i = 0; i + 1 < r.strokes.size(); ++i) {
    EXPECT_EQ(r.strokes[i].points_pu, planned[i]) << "stroke " << i + 1 << " as planned";
  }
}

// Passes bytes to the simulator; presses "cancel" the moment the device says XOFF.
class CancelOnXoff final : public Transport {
 public:
  CancelOnXoff(std::shared_ptr<SimCutter> c, std::atomic<bool>& cancel) : sim_(std::move(c)), cancel_(cancel) {}
  TransportStatus open() override { return sim_.open(); }
  IoResult write(std::span<const std::uint8_t> d, std::chrono::milliseconds t) override { return sim_.write(d, t); }
  IoResult read(std::span<std::uint8_t> b, std::chrono::milliseconds t) override {
    const IoResult r = sim_.read(b, t);
    for (std::size_t i = 0; i < r.bytes; ++i) {
      if (b[i] == 0x13) cancel_ = true;
    }
    return r;
  }
  TransportStatus drain(std::chrono::milliseconds t) override { return sim_.drain(t); }
  void close() override { sim_.close(); }
  std::string describe() const override { return "cancel-on-xoff"; }
  bool backpressure() const override { return sim_.backpressure(); }

 private:
  SimTransport sim_;
  std::atomic<bool>& cancel_;
};

TEST(SendJob, CancelDoesNotWaitForXonFromADeviceHoldingTheLine) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.buffer_bytes = 256;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  // The device says XOFF and then stops answering: it would hold the host for hold_timeout.
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{230, std::nullopt, 1});
  std::atomic<bool> cancel{false};
  CancelOnXoff t(cutter, cancel);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.cancel = &cancel;
  o.drain_query = DrainQuery::none;  // 230 bytes of job exactly: no status queries in between
  const SendResult r = send_job(t, job, o);
  EXPECT_EQ(r.holds, 1) << "the cancel came while the device held the line";
  EXPECT_TRUE(r.cancelled) << r.status.message;
  EXPECT_NE(r.status.error, TransportError::timeout)
      << "the cancel ended the wait, not the hold timeout: " << r.status.message;
  EXPECT_TRUE(r.abort_sent);
  EXPECT_TRUE(std::binary_search(job.command_end.begin(), job.command_end.end(), r.bytes_sent))
      << "at a command boundary";
}

TEST(SendJob, CancelWithoutAbortKeyStillLiftsTheKnife) {
  const DeviceProfile p = load_profile(config("generic-hpgl.toml"));
  const StrokePlan plan = townhouse_plan(p);
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  std::atomic<bool> cancel{true};  // before the first byte
  SendOptions o = send_options(p);
  o.cancel = &cancel;
  const SimRun r = run_on_sim(p, job, o);
  EXPECT_TRUE(r.sent.cancelled);
  EXPECT_EQ(r.sent.bytes_sent, 0u) << "nothing of the job was sent";
  EXPECT_EQ(r.sent.last_stroke_sent, 0u);
  EXPECT_EQ(r.report.bytes_received, 3u) << "only PU;";
  EXPECT_EQ(r.report.knife_downs, 0);
}

TEST(SendJob, WaitsForTheDeviceToDrainByQuery) {
  const DeviceProfile secabo = load_profile(config("secabo.toml"));
  EXPECT_EQ(secabo.transport.drain_query, DrainQuery::esc_b) << "ESC.B pacing implies an ESC.B drain check";
  const EncodedJob job = encode_job(townhouse_plan(secabo), secabo.dialect, secabo.tools);
  auto cutter = std::make_shared<SimCutter>(secabo);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const SendResult r = send_job(t, job, send_options(secabo));
  ASSERT_TRUE(r.complete()) << r.status.message;
  EXPECT_EQ(r.drained_by, DrainedBy::esc_b);
  EXPECT_EQ(cutter->buffer_used(), 0u) << "done means the device's buffer is empty";

  DeviceProfile esc_o = load_profile(config("sim.toml"));
  esc_o.transport.drain_query = DrainQuery::esc_o;
  auto c2 = std::make_shared<SimCutter>(esc_o);
  SimTransport t2(c2);
  ASSERT_TRUE(t2.open().ok());
  const SendResult r2 =
      send_job(t2, encode_job(townhouse_plan(esc_o), esc_o.dialect, esc_o.tools), send_options(esc_o));
  ASSERT_TRUE(r2.complete()) << r2.status.message;
  EXPECT_EQ(r2.drained_by, DrainedBy::esc_o);
  EXPECT_EQ(c2->buffer_used(), 0u) << "ESC.O said buffer empty";
}

TEST(SendJob, ADroppedLineNamesTheLastStrokeReceivedAndTheLastWritten) {
  DeviceProfile p = load_profile(config("sim.toml"));
  const StrokePlan plan = townhouse_plan(p);
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  {  // A device that cannot be asked: what the transport took (the simulator's count is exact).
    p.transport.drain_query = DrainQuery::none;
    auto cutter = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, job.stroke_end[4] + 3, 1});
    SimTransport t(cutter);
    ASSERT_TRUE(t.open().ok());
    const SendResult r = send_job(t, job, send_options(p));
    EXPECT_EQ(r.status.error, TransportError::disconnected) << r.status.message;
    EXPECT_EQ(r.last_stroke_sent, 5u) << "stroke 5 ended 3 bytes before the drop";
    EXPECT_EQ(r.last_stroke_written, 5u);
    EXPECT_EQ(r.received_counted_by, ReceivedCountedBy::transport);
  }
}

// A device that stops mid-job (hung, paused for good, power lost): it never cuts what sits in its
// buffer. E (known executed) <= what it really cut <= M (received) <= N (written), and a fresh
// device (a power cycle) resumed from E + 1 completes the card with no stroke missing.
void expect_honest_stop(const std::string& profile_file, FlowControl flow, DrainQuery query,
                        bool answers_tell_progress) {
  DeviceProfile p = load_profile(config(profile_file));
  p.transport.flow = flow;
  p.transport.drain_query = query;
  // A small buffer, a slow line and quick motion: the device works through much of what it gets
  // and answers say so, so E is well above zero and well below M.
  p.transport.buffer_bytes = 256;
  p.transport.baud = 9600;
  const StrokePlan plan = townhouse_plan(p);
  const auto planned = plan_in_plotter_units(plan, p.dialect);
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  const std::string what = profile_file + " (" + to_string(flow) + ", " + to_string(query) + ")";
  const std::size_t stop_at = job.bytes.size() / 2;
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{stop_at, std::nullopt, 1});
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const SendResult r = send_job(t, job, send_options(p));
  EXPECT_EQ(r.status.error, TransportError::timeout) << what << ": " << r.status.message;
  EXPECT_NE(r.status.message.find("the device stopped answering"), std::string::npos)
      << what << ": " << r.status.message;
  EXPECT_NE(r.status.message.find("paused, out of media or stuck, or it lost power"), std::string::npos)
      << what << ": a device that answered before is not a cable or baud problem: " << r.status.message;
  EXPECT_EQ(r.status.message.find("baud"), std::string::npos) << what << ": " << r.status.message;
  EXPECT_LT(r.bytes_sent, job.bytes.size()) << what << ": noticed mid-job, not after the last byte";
  EXPECT_FALSE(cutter->run_to_end()) << what << ": the device is stuck";
  const std::vector<SimStroke>& cut = cutter->strokes();
  ASSERT_TRUE(r.last_stroke_executed.has_value()) << what << ": the device answered queries, so E is known";
  const std::size_t e = *r.last_stroke_executed, m = r.last_stroke_sent, n = r.last_stroke_written;
  EXPECT_LE(e, m) << what;
  EXPECT_LE(m, n) << what;
  if (answers_tell_progress) {
    EXPECT_GT(e, 0u) << what << ": ESC.B answers showed strokes executed";
  }
  ASSERT_LE(e, cut.size()) << what << ": E never claims a stroke the device did not cut (it cut " << cut.size() << ")";
  EXPECT_GT(m, cut.size())
      << what << ": the stuck device received strokes it never cut (so M is no resume point after a reset)";
  for (std::size_t i = 0; i < cut.size(); ++i) EXPECT_EQ(cut[i].points_pu, planned[i]) << what << ": stroke " << i + 1;
  // Power cycle: a fresh device, from E + 1.
  const SimRun again = run_on_sim(p, encode_job(plan, p.dialect, p.tools, e + 1), send_options(p));
  ASSERT_TRUE(again.sent.complete()) << what << ": " << again.sent.status.message;
  std::vector<PlotterPath> both;
  for (std::size_t i = 0; i < e; ++i) both.push_back(cut[i].points_pu);
  for (const SimStroke& s : again.strokes) both.push_back(s.points_pu);
  EXPECT_EQ(both, planned) << what << ": strokes 1.." << e << " before the stop and " << e + 1
                           << ".. after the power cycle cover the card";
}

// A device whose buffer is larger than its profile says: 1024 free of 16384 is not "drained".
TEST(SendJob, AProfileThatUnderstatesTheBufferDoesNotEndTheJobEarly) {
  const DeviceProfile secabo = load_profile(config("secabo.toml"));
  DeviceProfile bigger = secabo;
  bigger.transport.buffer_bytes = 16 * secabo.transport.buffer_bytes;
  auto cutter = std::make_shared<SimCutter>(bigger);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const EncodedJob job = encode_job(townhouse_plan(secabo), secabo.dialect, secabo.tools);
  const SendResult r = send_job(t, job, send_options(secabo));
  ASSERT_TRUE(r.complete()) << r.status.message;
  EXPECT_EQ(cutter->buffer_used(), 0u)
      << "done means the device's whole buffer is empty, not the profile's share of it";
  EXPECT_EQ(cutter->strokes().size(), job.stroke_end.size()) << "every stroke was cut when popcut said done";
}

// Ctrl-C while popcut waits for the answer of a device that stopped mid-job: the wait ends and
// the cancel goes on to the abort (it used to wait out timeout_ms and end in a device error,
// with no abort and no knife-up sent).
// Cancels `job` on a simulator of `p` slowed by `slowdown` after `chunks` progress reports, then
// resumes from the advised stroke (last received + 1) on the same, now idle, device: what both
// runs cut must be the whole plan, each stroke at least once.
struct CancelAndResume {
  SendResult cancelled;
  SimReport report;
  std::size_t cut_before = 0;  // strokes cut before the abort took effect
  std::vector<PlotterPath> cut;
};
CancelAndResume cancel_then_resume(const DeviceProfile& p, const StrokePlan& plan, double slowdown, int chunks) {
  SimFaults slow;
  slow.slowdown = slowdown;
  auto cutter = std::make_shared<SimCutter>(p, slow);
  SimTransport t(cutter);
  EXPECT_TRUE(t.open().ok());
  std::atomic<bool> cancel{false};
  SendOptions o = send_options(p);
  o.cancel = &cancel;
  int seen = 0;
  o.progress = [&](const SendProgress&) {
    if (++seen == chunks) cancel = true;
  };
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  o.motion = motion_schedule(job.bytes, p);
  CancelAndResume r;
  r.cancelled = send_job(t, job, o);
  EXPECT_TRUE(cutter->run_to_end());
  r.report = cutter->report();
  r.cut_before = cutter->strokes().size();
  for (const SimStroke& st : cutter->strokes()) r.cut.push_back(st.points_pu);
  const EncodedJob rest = encode_job(plan, p.dialect, p.tools, r.cancelled.last_stroke_sent + 1);
  SendOptions again = send_options(p);
  again.motion = motion_schedule(rest.bytes, p);
  const SimRun resumed = run_on_sim(p, rest, again);
  EXPECT_TRUE(resumed.sent.complete()) << resumed.sent.status.message;
  for (const SimStroke& st : resumed.strokes) r.cut.push_back(st.points_pu);
  return r;
}

// Every planned stroke is among `cut`, in order, allowing strokes cut twice at the seam.
bool covers_plan(const std::vector<PlotterPath>& cut, const std::vector<PlotterPath>& planned) {
  std::size_t next = 0;
  for (const PlotterPath& c : cut) {
    if (next < planned.size() && c == planned[next]) ++next;
  }
  return next == planned.size();
}

// An abort that makes the device drop its buffer (ESC.K): what it received and had not cut is
// gone, so "received" falls back to what it executed and the default resume point cuts the rest.
// It used to stay at what had arrived, and a resume from there skipped the strokes dropped.
TEST(SendJob, AnAbortThatDiscardsTheBufferLeavesReceivedAtExecuted) {
  for (const char* flow : {"xon_xoff", "esc_b"}) {
    SCOPED_TRACE(flow);
    DeviceProfile p = load_profile(config("sim.toml"));
    ASSERT_TRUE(p.transport.abort_discards_buffer) << "sim.toml's ESC.K discards the buffer by default";
    if (std::string(flow) == "esc_b") {
      p.transport.flow = FlowControl::esc_b;
      p.transport.drain_query = DrainQuery::esc_b;
    }
    const StrokePlan plan = townhouse_plan(p);
    const CancelAndResume r = cancel_then_resume(p, plan, 4, 10);
    const SendResult& s = r.cancelled;
    ASSERT_TRUE(s.cancelled && s.abort_sent) << s.status.message;
    ASSERT_GT(r.report.discarded_bytes, 0u) << "the device held strokes it had not cut (else this test proves nothing)";
    ASSERT_GT(s.received_before_abort, r.cut_before)
        << "it had received strokes it never cut (else this proves nothing)";
    EXPECT_TRUE(s.buffer_discarded);
    EXPECT_EQ(s.last_stroke_sent, s.last_stroke_executed.value_or(0)) << "received is what it executed";
    EXPECT_LE(s.last_stroke_sent, r.cut_before) << "no stroke counted received was dropped uncut";
    EXPECT_EQ(s.buffered_bytes, 0u) << "it cuts nothing more after dropping its buffer";
    EXPECT_TRUE(covers_plan(r.cut, plan_in_plotter_units(plan, p.dialect)))
        << "the resume from the advised stroke covers the card";
  }
}

// A profile that says its abort keeps the buffer (the device goes on cutting what it holds):
// received stands, and resuming after it neither skips nor re-cuts.
TEST(SendJob, AnAbortThatKeepsTheBufferLeavesReceivedAsItWas) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.abort = "\x1b.J";  // abort device control: the sim ignores it and keeps cutting
  p.transport.abort_discards_buffer = false;
  const StrokePlan plan = townhouse_plan(p);
  const CancelAndResume r = cancel_then_resume(p, plan, 4, 10);
  ASSERT_TRUE(r.cancelled.cancelled && r.cancelled.abort_sent) << r.cancelled.status.message;
  EXPECT_FALSE(r.cancelled.buffer_discarded);
  EXPECT_EQ(r.report.discarded_bytes, 0u);
  EXPECT_GE(r.cut_before, r.cancelled.last_stroke_sent) << "it cut everything it received";
  EXPECT_TRUE(covers_plan(r.cut, plan_in_plotter_units(plan, p.dialect)));
}

// Under ESC.B the device is asked after the abort: one that honoured ESC.K holds only the
// knife-up, so it may cut nothing more of the job (it used to say "3 bytes (strokes 7..15)").
TEST(SendJob, AfterAnHonouredAbortTheDeviceMayCutNothingMore) {
  DeviceProfile p = load_profile(config("secabo.toml"));
  p.transport.abort = "\x1b.K";
  SimFaults slow;
  slow.slowdown = 5;  // a full buffer when the cancel comes
  auto cutter = std::make_shared<SimCutter>(p, slow);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  std::atomic<bool> cancel{false};
  SendOptions o = send_options(p);
  o.cancel = &cancel;
  int chunks = 0;
  o.progress = [&](const SendProgress&) {
    if (++chunks == 12) cancel = true;
  };
  const SendResult r = send_job(t, encode_job(townhouse_plan(p), p.dialect, p.tools), o);
  ASSERT_TRUE(r.cancelled && r.abort_sent) << r.status.message;
  ASSERT_TRUE(r.buffer_known) << "asked after the abort";
  EXPECT_EQ(r.buffered_bytes, 0u) << "the knife-up is not the job's";
  EXPECT_GT(r.buffered_first_stroke, r.buffered_last_stroke) << "no stroke left to cut";
}

// A cancel that stops after the next stroke's travel (knife up) but before its knife-down: that
// stroke cannot be cut, so it is not among those the device may still cut.
TEST(SendJob, AStrokeWhoseKnifeNeverWentDownIsNotLeftToCut) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.flow = FlowControl::none;
  p.transport.drain_query = DrainQuery::none;
  p.transport.error_query = false;
  p.transport.buffer_bytes = 64;  // chunks of 8 bytes, ending on command boundaries
  EncodedJob job;
  job.bytes = "IN;PU;PA0,0;PD10,0;PU;PA20,0;PD30,0;";
  for (std::size_t i = 0; i < job.bytes.size(); ++i) {
    if (job.bytes[i] == ';') job.command_end.push_back(i + 1);
  }
  job.stroke_end = {job.bytes.find("PD10,0;") + 7, job.bytes.size()};
  job.stroke_cut_start = {job.bytes.find("PD10"), job.bytes.find("PD30")};
  job.total_strokes = 2;
  const std::size_t travel_end = job.bytes.find("PD30");  // "...PU;PA20,0;" went out, "PD30,0;" did not
  auto cutter = std::make_shared<SimCutter>(p);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  std::atomic<bool> cancel{false};
  SendOptions o = send_options(p);
  o.cancel = &cancel;
  o.progress = [&](const SendProgress& s) {
    if (s.bytes_sent >= travel_end) cancel = true;
  };
  const SendResult r = send_job(t, job, o);
  ASSERT_TRUE(r.cancelled) << r.status.message;
  ASSERT_EQ(r.bytes_sent, travel_end) << "stopped after the travel, before the knife-down";
  EXPECT_EQ(r.buffered_last_stroke, 1u) << "stroke 2's knife never went down";
}

// The user presses Ctrl-C while popcut listens for an answer from a device that went silent.
class CancelWhileListening final : public Transport {
 public:
  CancelWhileListening(std::shared_ptr<SimCutter> c, std::atomic<bool>& cancel)
      : cutter_(c), sim_(c), cancel_(cancel) {}
  TransportStatus open() override { return sim_.open(); }
  IoResult write(std::span<const std::uint8_t> d, std::chrono::milliseconds t) override { return sim_.write(d, t); }
  IoResult read(std::span<std::uint8_t> b, std::chrono::milliseconds t) override {
    if (cutter_->frozen() && !b.empty()) cancel_ = true;
    return sim_.read(b, t);
  }
  TransportStatus drain(std::chrono::milliseconds t) override { return sim_.drain(t); }
  void close() override { sim_.close(); }
  std::string describe() const override { return "sim"; }

 private:
  std::shared_ptr<SimCutter> cutter_;
  SimTransport sim_;
  std::atomic<bool>& cancel_;
};

TEST(SendJob, ACancelWhileWaitingForAnAnswerStillAborts) {
  for (const char* profile : {"secabo.toml", "sim.toml"}) {  // ESC.B pacing; ESC.O pings under XON/XOFF
    const DeviceProfile p = load_profile(config(profile));
    SimFaults stuck;
    stuck.stop_answering_after_bytes = 700;
    auto cutter = std::make_shared<SimCutter>(p, stuck);
    std::atomic<bool> cancel{false};
    CancelWhileListening t(cutter, cancel);
    ASSERT_TRUE(t.open().ok());
    SendOptions o = send_options(p);
    o.cancel = &cancel;
    const SendResult r = send_job(t, encode_job(townhouse_plan(p), p.dialect, p.tools), o);
    EXPECT_TRUE(r.cancelled) << profile << ": a cancel, not a device error: " << r.status.message;
    EXPECT_TRUE(r.abort_sent) << profile << ": the abort and knife-up went out";
  }
}

// Ctrl-C while popcut waits for a silent device's first answer: cancelled at once, nothing sent
// (it used to wait out the timeout and report the device as not answering).
TEST(SendJob, ACancelBeforeTheFirstAnswerEndsTheWaitWithNothingSent) {
  const DeviceProfile sim = load_profile(config("sim.toml"));
  SimFaults mute;
  mute.stop_answering_after_bytes = 0;
  auto cutter = std::make_shared<SimCutter>(sim, mute);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  std::atomic<bool> cancel{true};
  SendOptions o = send_options(sim);
  o.cancel = &cancel;
  const SendResult r = send_job(t, encode_job(townhouse_plan(sim), sim.dialect, sim.tools), o);
  EXPECT_TRUE(r.cancelled) << "the wait for the first answer notices the cancel: " << r.status.message;
  EXPECT_TRUE(r.status.ok()) << "a cancel, not a device fault: " << r.status.message;
  EXPECT_EQ(r.bytes_sent, 0u) << "no job byte went out";
}

// And one whose buffer is smaller: it never reports the profile's 1024 free, yet it does empty.
TEST(SendJob, AProfileThatOverstatesTheBufferStillSeesTheJobEnd) {
  const DeviceProfile secabo = load_profile(config("secabo.toml"));
  DeviceProfile smaller = secabo;
  smaller.transport.buffer_bytes = secabo.transport.buffer_bytes / 4;
  auto cutter = std::make_shared<SimCutter>(smaller);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const EncodedJob job = encode_job(townhouse_plan(secabo), secabo.dialect, secabo.tools);
  const SendResult r = send_job(t, job, send_options(secabo));
  ASSERT_TRUE(r.complete()) << "the job ends when the device's own buffer is empty: " << r.status.message;
  EXPECT_EQ(cutter->buffer_used(), 0u) << "and it is";
  EXPECT_EQ(cutter->report().overflow_bytes, 0u) << "its answers paced popcut, not the profile's size";
}

// A buffer smaller than the profile's chunk and than the longest command (castle's 72-byte PA):
// popcut sends what the device says is free rather than waiting for a share of the profile's size
// that a tiny buffer, partly holding the command in progress, never reports.
TEST(SendJob, ATinyBufferIsFedWhatItHasRoomFor) {
  DeviceProfile escb = load_profile(config("sim.toml"));
  escb.transport.flow = FlowControl::esc_b;
  escb.transport.drain_query = DrainQuery::esc_b;
  DeviceProfile tiny = escb;
  tiny.transport.buffer_bytes = 64;
  PlanOptions po = escb.plan;
  po.optimise_work = 1000;
  const StrokePlan plan =
      plan_strokes(make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/castle.json")), po);
  const EncodedJob job = encode_job(plan, escb.dialect, escb.tools);
  std::size_t longest = 0;
  for (std::size_t i = 0, from = 0; i < job.command_end.size(); from = job.command_end[i++])
    longest = std::max(longest, job.command_end[i] - from);
  ASSERT_GT(longest, 64u) << "the job has a command longer than the device's buffer";
  const SimRun run = run_on_sim(tiny, job, send_options(escb));
  ASSERT_TRUE(run.sent.complete()) << run.sent.status.message;
  EXPECT_EQ(run.report.overflow_bytes, 0u) << "paced by its answers";
  EXPECT_EQ(first_difference(plan_in_plotter_units(plan, escb.dialect), run.strokes), std::nullopt)
      << "the device cut exactly the job";
}

// A device far slower than the plan's estimate that keeps freeing its buffer is waited for: its
// ESC.B answers show progress, so hold_timeout counts only time without any.
TEST(SendJob, ASlowDeviceThatKeepsCuttingIsWaitedForAfterTheLastByte) {
  const DeviceProfile secabo = load_profile(config("secabo.toml"));
  SimFaults slow;
  slow.slowdown = 40;
  auto cutter = std::make_shared<SimCutter>(secabo, slow);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(secabo);
  o.hold_timeout = std::chrono::seconds(60);  // longer than any one command takes it
  const EncodedJob job = encode_job(townhouse_plan(secabo), secabo.dialect, secabo.tools);
  o.motion = {{0, 0}, {1.0, job.bytes.size()}};  // the plan's estimate: one second
  const SendResult r = send_job(t, job, o);
  ASSERT_TRUE(r.complete()) << r.status.message;
  EXPECT_GT(cutter->now_s(), 60 + 1) << "it took longer than the estimate and hold_timeout together";
  EXPECT_EQ(cutter->buffer_used(), 0u) << "done when the device's buffer was empty";
  EXPECT_EQ(cutter->strokes().size(), job.stroke_end.size()) << "every stroke cut";
}

// A profile whose flow control the device does not do: the device never says XOFF, its buffer
// overflows and it cuts something else. Every byte went out and the drain succeeded, so only the
// device's own error report (ESC.E 16) can tell; popcut must not call that job done.
TEST(SendJob, ADeviceThatLostBytesToOverflowFailsTheJob) {
  const DeviceProfile host = load_profile(config("sim.toml"));  // XON/XOFF, asks ESC.E
  ASSERT_TRUE(host.transport.error_query) << "sim.toml asks ESC.E";
  DeviceProfile device = host;
  device.transport.flow = FlowControl::esc_b;  // paced by ESC.B: it never says XOFF
  device.transport.buffer_bytes = 256;
  SimFaults slow;
  slow.slowdown = 5;
  auto cutter = std::make_shared<SimCutter>(device, slow);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const SendResult r = send_job(t, encode_job(townhouse_plan(host), host.dialect, host.tools), send_options(host));
  ASSERT_GT(cutter->report().overflow_bytes, 0u) << "the mismatch lost bytes";
  EXPECT_FALSE(r.complete()) << "a job the device did not get whole is not done";
  EXPECT_NE(r.status.message.find("I/O error 16 (ESC.E): its input buffer overflowed"), std::string::npos)
      << r.status.message;
  EXPECT_FALSE(r.last_stroke_executed.has_value())
      << "with bytes lost, nothing it did is known to be the job's strokes";

  // The same device with a matching profile reports no error, and the job is done.
  DeviceProfile matching = device;
  matching.transport.drain_query = DrainQuery::esc_b;
  auto fine = std::make_shared<SimCutter>(device, slow);
  SimTransport t2(fine);
  ASSERT_TRUE(t2.open().ok());
  const SendResult ok =
      send_job(t2, encode_job(townhouse_plan(host), host.dialect, host.tools), send_options(matching));
  EXPECT_TRUE(ok.complete()) << ok.status.message;
  EXPECT_EQ(fine->report().overflow_bytes, 0u);

  // An error left from an earlier job nobody asked about does not fail the next one: popcut
  // reads (and so clears) ESC.E before sending.
  auto used = std::make_shared<SimCutter>(device, slow);
  SimTransport t3(used);
  ASSERT_TRUE(t3.open().ok());
  SendOptions careless = send_options(host);
  careless.error_query = false;
  EXPECT_TRUE(send_job(t3, encode_job(townhouse_plan(host), host.dialect, host.tools), careless).complete())
      << "not asked, not seen";
  ASSERT_GT(used->report().overflow_bytes, 0u) << "the earlier job lost bytes";
  const SendResult next =
      send_job(t3, encode_job(townhouse_plan(host), host.dialect, host.tools), send_options(matching));
  EXPECT_TRUE(next.complete()) << "the stale error is cleared before the job: " << next.status.message;
}

TEST(SendJob, ADeviceThatStopsMidJobIsNoticedThenAndNamesWhatItExecuted) {
  expect_honest_stop("secabo.toml", FlowControl::esc_b, DrainQuery::esc_b,
                     true);  // pacing answers: executed from free space
  // Pipelined ESC.O pings: "not empty" all along (XON/XOFF keeps the buffer a quarter full)
  // shows nothing executed, and E stays at 0; the device stops while it holds the line.
  expect_honest_stop("sim.toml", FlowControl::xon_xoff, DrainQuery::esc_o, false);
}

// A serial-like line: each write's bytes reach the device only with the next write or while the
// host waits for an answer (they sit in an OS queue meanwhile); the line drops after
// `drop_after` bytes have reached it.
class QueuedLine final : public Transport {
 public:
  QueuedLine(std::shared_ptr<SimCutter> c, std::size_t drop_after) : sim_(std::move(c)), drop_after_(drop_after) {}
  TransportStatus open() override { return sim_.open(); }
  IoResult write(std::span<const std::uint8_t> d, std::chrono::milliseconds t) override {
    // The queued bytes go on the line, up to the drop; the queue itself stays counted in flight.
    const std::size_t take = std::min(queue_.size(), drop_after_ - std::min(drop_after_, delivered_));
    delivered_ += sim_.write(std::span<const std::uint8_t>(queue_.data(), take), t).bytes;
    if (delivered_ >= drop_after_) return {0, {TransportError::disconnected, EIO, "line dropped"}};
    queue_.assign(d.begin(), d.end());
    return {d.size(), {}};
  }
  // Waiting for an answer lets the line carry the queue (up to the drop).
  IoResult read(std::span<std::uint8_t> b, std::chrono::milliseconds t) override {
    if (!b.empty()) {
      const std::size_t take = std::min(queue_.size(), drop_after_ - std::min(drop_after_, delivered_));
      delivered_ += sim_.write(std::span<const std::uint8_t>(queue_.data(), take), t).bytes;
      queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(take));
    }
    return sim_.read(b, t);
  }
  TransportStatus drain(std::chrono::milliseconds t) override {
    const IoResult r = sim_.write(std::exchange(queue_, {}), t);
    delivered_ += r.bytes;
    return r.status;
  }
  void close() override { sim_.close(); }
  std::string describe() const override { return "queued-line"; }
  bool backpressure() const override { return sim_.backpressure(); }
  bool writes_acknowledged() const override { return false; }
  std::chrono::steady_clock::time_point now() const override { return sim_.now(); }
  // Like a serial port, which also holds back bytes an adapter or a pty may hide.
  std::size_t in_flight() override { return queue_.size() + unseen_; }
  std::size_t expected_in_flight() override { return queue_.size(); }
  std::size_t delivered() const { return delivered_; }
  void hold_back_unseen(std::size_t bytes) { unseen_ = bytes; }

 private:
  SimTransport sim_;
  std::size_t drop_after_;
  std::vector<std::uint8_t> queue_;
  std::size_t delivered_ = 0;
  std::size_t unseen_ = 0;
};

// Paced by time over a line that may hide 4 KB (a USB-serial adapter): a status answer overdue
// by timeout_ms is a device that stopped, not one behind a held line (nothing holds it), and all
// sent to it from then on is lost. popcut stops there instead of writing the rest of the job.
TEST(SendJob, TimePacingStopsSendingToADeviceThatFellSilent) {
  DeviceProfile p = load_profile(config("sim.toml"));  // answers ESC.O
  p.transport.flow = FlowControl::none;
  p.transport.buffer_bytes = 256;
  p.transport.error_query = false;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{std::size_t{800}, std::nullopt, 1});
  QueuedLine t(cutter, job.bytes.size() * 2);
  t.hold_back_unseen(4096);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  const SendResult r = send_job(t, job, o);
  EXPECT_EQ(r.status.error, TransportError::timeout) << r.status.message;
  EXPECT_NE(r.status.message.find("while"), std::string::npos) << "found while sending or pacing: " << r.status.message;
  EXPECT_LT(r.bytes_sent, job.bytes.size() - 500) << "it stopped writing to a silent device";
  EXPECT_GT(r.busy_for_s, 0) << "and says how long what it held may take, should it resume";
}

TEST(SendJob, AJobThatDrainedCountsEveryStrokeReceivedWhateverThePortHoldsBack) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.drain_query = DrainQuery::none;
  p.transport.error_query = false;  // a device that cannot be asked anything
  p.transport.flow = FlowControl::none;
  p.transport.buffer_bytes = 1 << 20;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  auto cutter = std::make_shared<SimCutter>(p);
  QueuedLine t(cutter, job.bytes.size() + 1);
  t.hold_back_unseen(4096);
  ASSERT_TRUE(t.open().ok());
  const SendResult r = send_job(t, job, send_options(p));
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  EXPECT_EQ(r.last_stroke_sent, job.total_strokes)
      << "a finished job was received whole, though the port's estimate holds bytes back";
  EXPECT_EQ(r.bytes_received, r.bytes_sent);
}

TEST(SendJob, BytesStillInTheOsQueueAreNotClaimedReceived) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.drain_query = DrainQuery::none;  // nothing to ask: the queue is all popcut knows
  p.transport.flow = FlowControl::none;
  p.transport.buffer_bytes = 1 << 20;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  auto cutter = std::make_shared<SimCutter>(p);
  QueuedLine t(cutter, job.stroke_end[20] + 5);
  ASSERT_TRUE(t.open().ok());
  const SendResult r = send_job(t, job, send_options(p));
  ASSERT_EQ(r.status.error, TransportError::disconnected) << r.status.message;
  EXPECT_LE(r.bytes_received, t.delivered()) << "received counts only what reached the device";
  EXPECT_GT(r.bytes_sent, r.bytes_received) << "a chunk was still queued when the line dropped";
  EXPECT_EQ(r.last_stroke_sent, job.last_stroke_within(r.bytes_received));
  ASSERT_GT(r.last_stroke_sent, 0u) << "some strokes got through before the drop";
  EXPECT_LE(job.stroke_end[r.last_stroke_sent - 1], t.delivered())
      << "stroke " << r.last_stroke_sent << " really arrived";
  EXPECT_GE(r.last_stroke_written, r.last_stroke_sent);
}

TEST(SendJob, OverASerialLineOnlyTheDevicesAnswersCountAsReceived) {
  DeviceProfile p = load_profile(config("sim.toml"));
  ASSERT_EQ(p.transport.drain_query, DrainQuery::esc_o) << "the simulated device answers ESC.O";
  p.transport.buffer_bytes = 1 << 20;  // no XOFF: this is about counting
  p.transport.flow = FlowControl::none;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  SendOptions o = send_options(p);
  o.status_every_bytes = 256;
  auto cutter = std::make_shared<SimCutter>(p);
  QueuedLine t(cutter, job.stroke_end[29] + 3);
  ASSERT_TRUE(t.open().ok());
  const SendResult r = send_job(t, job, o);
  ASSERT_EQ(r.status.error, TransportError::disconnected) << r.status.message;
  EXPECT_EQ(r.received_counted_by, ReceivedCountedBy::status_answers);
  EXPECT_GT(r.status_queries, 1) << "queried while sending, not only before";
  EXPECT_LE(r.bytes_received, t.delivered()) << "never more than the device got";
  EXPECT_GT(r.last_stroke_sent, 0u) << "the answers confirmed some strokes";
  EXPECT_GT(r.last_stroke_written, r.last_stroke_sent) << "written runs ahead of what the answers confirm";
}

// Answers every status query with `answer`.
class Answering final : public Transport {
 public:
  explicit Answering(std::string answer) : answer_(std::move(answer)) {}
  TransportStatus open() override { return {}; }
  IoResult write(std::span<const std::uint8_t> d, std::chrono::milliseconds) override {
    for (const std::uint8_t b : d) {
      if (b == 0x1b) replies_ += answer_;
    }
    return {d.size(), {}};
  }
  IoResult read(std::span<std::uint8_t> b, std::chrono::milliseconds) override {
    const std::size_t n = std::min(b.size(), replies_.size());
    std::copy_n(replies_.begin(), n, b.begin());
    replies_.erase(0, n);
    if (n == 0) return {0, {TransportError::timeout, ETIMEDOUT, "silence"}};
    return {n, {}};
  }
  TransportStatus drain(std::chrono::milliseconds) override { return {}; }
  void close() override {}
  std::string describe() const override { return "serial:/dev/answering"; }

 private:
  std::string answer_, replies_;
};

// A serial line whose device holds XOFF for a while after each query (cutting a full buffer): the
// query waits in the OS queue with the job's bytes, and its answer comes only after XON.
class HeldAnswers final : public Transport {
 public:
  HeldAnswers(int hold_reads, bool shows_hold) : hold_reads_(hold_reads), shows_hold_(shows_hold) {}
  TransportStatus open() override { return {}; }
  IoResult write(std::span<const std::uint8_t> d, std::chrono::milliseconds) override {
    for (const std::uint8_t b : d) {
      if (b == 0x1b) held_.push_back(hold_reads_);
    }
    return {d.size(), {}};
  }
  IoResult read(std::span<std::uint8_t> b, std::chrono::milliseconds) override {
    for (int& left : held_) --left;
    while (!held_.empty() && held_.front() <= 0) {
      held_.erase(held_.begin());
      replies_ += "8\r";
    }
    const std::size_t n = std::min(b.size(), replies_.size());
    std::copy_n(replies_.begin(), n, b.begin());
    replies_.erase(0, n);
    if (n == 0) return {0, {TransportError::timeout, ETIMEDOUT, "silence"}};
    return {n, {}};
  }
  bool holding_line() override { return shows_hold_ && !held_.empty(); }
  TransportStatus drain(std::chrono::milliseconds) override { return {}; }
  void close() override {}
  std::string describe() const override { return "serial:/dev/held"; }

 private:
  int hold_reads_;
  bool shows_hold_;
  std::vector<int> held_;
  std::string replies_;
};

TEST(SendJob, AQueryBehindAHeldLineIsWaitedForUpToTheHoldTimeout) {
  const DeviceProfile p = load_profile(config("sim.toml"));
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  SendOptions o = send_options(p);
  o.timeout = std::chrono::milliseconds(100);  // a few reads' worth
  o.hold_timeout = std::chrono::seconds(60);
  o.error_query = false;
  HeldAnswers held(40, true);
  const SendResult r = send_job(held, job, o);
  EXPECT_TRUE(r.complete()) << "answers held back by XOFF are not silence: " << r.status.message;
  HeldAnswers unseen(40, false);
  const SendResult u = send_job(unseen, job, o);
  EXPECT_FALSE(u.complete()) << "where no hold can be seen, the timeout stands";
  // A line held for good: hold_timeout, then the usual timeout, then a message that says so.
  o.hold_timeout = std::chrono::seconds(2);
  HeldAnswers forever(1 << 30, true);
  const SendResult f = send_job(forever, job, o);
  EXPECT_FALSE(f.complete());
  EXPECT_NE(f.status.message.find("behind a line it held"), std::string::npos) << f.status.message;
}

TEST(SendJob, SilenceOrGarbageInsteadOfAnAnswerStopsBeforeTheJob) {
  const DeviceProfile p = load_profile(config("sim.toml"));
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  SendOptions o = send_options(p);
  o.timeout = std::chrono::milliseconds(200);
  o.error_query = false;  // these doubles answer every query alike ("8" would be an ESC.E error)
  Answering silent("");
  const SendResult r = send_job(silent, job, o);
  EXPECT_EQ(r.status.error, TransportError::timeout) << r.status.message;
  EXPECT_NE(r.status.message.find("did not answer ESC.O before sending within 200 ms"), std::string::npos)
      << r.status.message;
  EXPECT_NE(r.status.message.find("the profile says 115200 baud"), std::string::npos) << r.status.message;
  EXPECT_EQ(r.bytes_sent, 0u) << "no byte of the job went out";

  Answering garbage("\xe7x!\r");
  const SendResult g = send_job(garbage, job, o);
  EXPECT_EQ(g.status.error, TransportError::io) << g.status.message;
  EXPECT_NE(g.status.message.find("answered '\\xe7x!'"), std::string::npos)
      << "shows what came back: " << g.status.message;
  EXPECT_EQ(g.bytes_sent, 0u);

  Answering fine("8\r");
  const SendResult ok = send_job(fine, job, o);
  EXPECT_TRUE(ok.complete()) << ok.status.message;
  EXPECT_EQ(ok.bytes_received, job.bytes.size()) << "all confirmed at the end";
}

TEST(DeviceString, ParsesEveryForm) {
  DeviceAddress a;
  ASSERT_TRUE(parse_device("sim", a).ok());
  EXPECT_EQ(a.kind, DeviceKind::sim);
  ASSERT_TRUE(parse_device("file:/tmp/x.hpgl", a).ok());
  EXPECT_EQ(a.kind, DeviceKind::file);
  EXPECT_EQ(a.path, "/tmp/x.hpgl");
  ASSERT_TRUE(parse_device("serial:/dev/ttyUSB0", a).ok());
  EXPECT_EQ(a.kind, DeviceKind::serial);
  EXPECT_EQ(a.path, "/dev/ttyUSB0");
  ASSERT_TRUE(parse_device("serial:0403:6001:A50285BI", a).ok());
  EXPECT_EQ(a.kind, DeviceKind::serial);
  EXPECT_EQ(*a.vid, 0x0403);
  EXPECT_EQ(*a.pid, 0x6001);
  EXPECT_EQ(a.serial_number, "A50285BI");
  ASSERT_TRUE(parse_device("usb:0B4D:110a", a).ok());
  EXPECT_EQ(a.kind, DeviceKind::usb);
  EXPECT_EQ(usb_id_string(*a.vid, *a.pid), "0b4d:110a") << "ids are case-insensitive hex";
  EXPECT_TRUE(a.serial_number.empty());
}

TEST(DeviceString, MalformedStringsSayWhatWasExpected) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "empty"},
      {"ttyUSB0", "unknown device"},
      {"tcp:host:9100", "unknown scheme 'tcp:'"},
      {"file:", "file: needs a path"},
      {"serial:", "serial: needs a port"},
      {"serial:ttyUSB0", "expected VID:PID"},
      {"usb:", "usb: needs VID:PID"},
      {"usb:0b4d", "expected VID:PID"},
      {"usb:0b4:110a", "vendor id '0b4' is not four hex digits"},
      {"usb:0b4d:11g0", "product id '11g0' is not four hex digits"},
      {"usb:0b4d:110a:", "empty serial number"},
      {"usb:0b4d:110a:A B", "printable characters only"},
  };
  for (const auto& [text, expect] : cases) {
    DeviceAddress a;
    const TransportStatus st = parse_device(text, a);
    EXPECT_EQ(st.error, TransportError::bad_argument) << "'" << text << "' is refused";
    EXPECT_NE(st.message.find(expect), std::string::npos) << "'" << text << "': " << st.message;
    EXPECT_NE(st.message.find(std::string("'") + text + "'"), std::string::npos) << "names the string: " << st.message;
  }
  const MadeTransport m = make_transport("usb:zzzz:0000", load_profile(config("sim.toml")));
  EXPECT_EQ(m.status.error, TransportError::bad_argument) << "the factory parses first";
  EXPECT_EQ(m.transport, nullptr);
}

TEST(DeviceString, FactoryBuildsSimAndFile) {
  const DeviceProfile p = load_profile(config("sim.toml"));
  const MadeTransport sim = make_transport("sim", p);
  ASSERT_TRUE(sim.status.ok()) << sim.status.message;
  EXPECT_NE(sim.sim, nullptr) << "sim exposes the simulated device";
  EXPECT_EQ(sim.transport->describe(), "sim");
  const MadeTransport file = make_transport("file:/nonexistent-dir/x.hpgl", p);
  ASSERT_TRUE(file.status.ok());
  EXPECT_FALSE(file.transport->answers()) << "a file cannot answer queries";
  EXPECT_EQ(file.transport->open().error, TransportError::not_found) << "open reports the missing directory";
}

// A device still cutting an earlier job when asked before this one reports less than its whole
// buffer free. At the end, as much free as then is not empty: it may still hold what it held
// then. It is done once it has read nothing for longer than any command takes it.
TEST(SendJob, AnEscBDrainWaitsOutADeviceThatWasBusyWhenFirstAsked) {
  const DeviceProfile p = load_profile(config("secabo.toml"));
  ASSERT_EQ(p.transport.flow, FlowControl::esc_b);
  auto cutter = std::make_shared<SimCutter>(p);
  std::string earlier = "IN;SP1;";
  while (earlier.size() < p.transport.buffer_bytes / 2) earlier += "PU0,0;PD800,0;";  // 20 mm: under half a second each
  cutter->receive(reinterpret_cast<const std::uint8_t*>(earlier.data()), earlier.size(), 1);
  ASSERT_GT(cutter->buffer_used(), p.transport.buffer_bytes / 4) << "still busy with the earlier job";
  EncodedJob job;
  job.bytes = "IN;SP1;";
  for (int i = 0; i < 10; ++i) job.bytes += "PU0,0;PD400,0;";
  for (std::size_t i = 0; i < job.bytes.size(); ++i) {
    if (job.bytes[i] == ';') job.command_end.push_back(i + 1);
  }
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  const SendResult r = send_job(t, job, o);
  ASSERT_TRUE(r.complete()) << r.status.message;
  EXPECT_EQ(r.drained_by, DrainedBy::esc_b);
  EXPECT_EQ(cutter->buffer_used(), 0u) << "called done while the device still held bytes";
}

// Time pacing: a device with no handshake on a line that cannot hold popcut off (flow "none").
struct PacedRun {
  SendResult sent;
  SimReport report;
  std::vector<SimStroke> strokes;
  std::size_t left_after_send = 0;  // bytes the device still held when send_job returned
};
// A device that cannot be asked anything, with a 256-byte buffer (a quarter of a typical one).
DeviceProfile cannot_be_asked(DeviceProfile p) {
  p.transport.buffer_bytes = 256;
  p.transport.drain_query = DrainQuery::none;
  p.transport.error_query = false;
  return p;
}

// `earlier`: what the device did before this job (it is left where that ended).
PacedRun run_paced(DeviceProfile p, const EncodedJob& job, double slowdown, int margin_percent,
                   const std::string& earlier = "") {
  p.transport.flow = FlowControl::none;
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, std::nullopt, slowdown});
  cutter->preload(earlier);
  cutter->run_to_end();
  SimTransport t(cutter);
  EXPECT_TRUE(t.open().ok());
  EXPECT_FALSE(t.backpressure()) << "nothing holds popcut off";
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  o.pace_margin_percent = margin_percent;
  PacedRun r;
  r.sent = send_job(t, job, o);
  r.left_after_send = cutter->buffer_used();
  cutter->run_to_end();
  r.report = cutter->report();
  r.strokes = cutter->strokes();
  return r;
}

// The device is modelled working through the job at the motion model's pace, slowed by the
// margin: one up to that much slower than the plan never loses a byte, with a buffer a quarter of
// a typical one, whatever the dialect's bytes per mm; without the margin the same device
// overflows (so the simulator does show a device that loses bytes).
TEST(SendJob, TimePacingKeepsADeviceWithNoHandshakeWithinItsBuffer) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = cannot_be_asked(load_profile(file));
    const StrokePlan plan = townhouse_plan(p);
    const EncodedJob job = encode_for_device(plan, p);
    const PacedRun r = run_paced(p, job, 1.2, 25);
    ASSERT_TRUE(r.sent.complete()) << file << ": " << r.sent.status.message;
    EXPECT_EQ(r.sent.drained_by, DrainedBy::estimate) << file;
    EXPECT_EQ(r.left_after_send, 0u) << file << ": done only once the device, by the model, has worked through the job";
    EXPECT_EQ(r.report.overflow_bytes, 0u) << file << ": 20 % slower than the plan, within the 25 % margin";
    EXPECT_LE(r.report.max_buffer_used, 192u)
        << file << ": about half the buffer, as paced (a full one would be at the edge)";
    EXPECT_FALSE(first_difference(plan_in_plotter_units(plan, p.dialect), r.strokes).has_value())
        << file << ": the whole job cut";
    // Pacing costs little: the device waits for bytes for a small part of the job, and the model
    // allows once for a first travel across the area (it may start anywhere).
    const double first_travel_s = 1.25 * move_time_s(longest_first_travel_mm(p.dialect), p.kinematics.travel_speed_mm_s,
                                                     p.kinematics.accel_mm_s2);
    EXPECT_LT(r.report.clock_s, 1.1 * r.report.motion_time_s + first_travel_s)
        << file << ": clock " << r.report.clock_s << " s for " << r.report.motion_time_s << " s of motion";
    // GP-GL sends a straight line as one short D, so its townhouse is too sparse for a device
    // 20 % slow to run 256 bytes behind: half as slow again shows the same loss.
    const PacedRun tight = run_paced(p, job, p.language == CutterLanguage::gpgl ? 1.5 : 1.2, 0);
    EXPECT_GT(tight.report.overflow_bytes, 0u) << file << ": paced at the plan's pace, a slower device overflows";
  }
}

// The margin costs a device as fast as the plan a quarter more time (and the allowance for a first
// travel across the area, which it did not need). One that answers ESC.O says
// when it has caught up ("buffer empty"), and the model moves on to where it is.
TEST(SendJob, TimePacingCatchesUpWithADeviceThatSaysItsBufferIsEmpty) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.buffer_bytes = 256;
  p.transport.error_query = false;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  p.transport.drain_query = DrainQuery::none;
  const PacedRun blind = run_paced(p, job, 1, 25);
  p.transport.drain_query = DrainQuery::esc_o;
  const PacedRun told = run_paced(p, job, 1, 25);
  ASSERT_TRUE(blind.sent.complete() && told.sent.complete()) << blind.sent.status.message << told.sent.status.message;
  EXPECT_GT(blind.report.clock_s / blind.report.motion_time_s, 1.25)
      << "paced a quarter slower than the plan, after the first travel";
  EXPECT_LT(told.report.clock_s, 1.1 * told.report.motion_time_s)
      << "its answers let it go at its own pace: " << told.report.clock_s << " s for " << told.report.motion_time_s
      << " s of motion";
  EXPECT_EQ(told.report.overflow_bytes, 0u);
}

// The model starts at the origin; a device left at the far corner of its area by an earlier job
// first travels across all of it, and must still not be sent more than it holds.
TEST(SendJob, TimePacingAllowsForADeviceLeftAnywhereInItsArea) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = cannot_be_asked(load_profile(file));
    const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
    // The far corner; on a roll feeder, of a piece twice as long as wide (longest_first_travel_mm).
    const HpglDialect& d = p.dialect;
    const std::int64_t far_y = std::min(d.area_max_y_pu, d.area_min_y_pu + 2 * (d.area_max_x_pu - d.area_min_x_pu));
    const std::string corner = "PU" + std::to_string(d.area_max_x_pu) + "," + std::to_string(far_y) + ";";
    const PacedRun r = run_paced(p, job, 1.2, 25, "IN;" + corner);
    ASSERT_TRUE(r.sent.complete()) << file << ": " << r.sent.status.message;
    EXPECT_EQ(r.report.overflow_bytes, 0u) << file << ": left at " << corner;
  }
}

// A profile with no handshake whose device answers ESC.B: its answers say where it is, later or
// sooner than the model, so even a device three times slower than the plan loses nothing.
TEST(SendJob, TimePacingFollowsADeviceThatAnswersEscB) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.buffer_bytes = 256;
  p.transport.drain_query = DrainQuery::esc_b;
  p.transport.error_query = false;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  for (const double slowdown : {0.5, 1.0, 3.0}) {
    const PacedRun r = run_paced(p, job, slowdown, 25);
    ASSERT_TRUE(r.sent.complete()) << slowdown << ": " << r.sent.status.message;
    EXPECT_EQ(r.report.overflow_bytes, 0u) << slowdown << " times the plan's motion time";
    EXPECT_EQ(r.strokes.size(), job.stroke_end.size()) << slowdown;
  }
}

// A device that answers but does not move (paused) holds the model back for good: after
// hold_timeout that is an error, not a wait forever.
TEST(SendJob, TimePacingGivesUpOnADeviceWhoseAnswersShowNoProgress) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.buffer_bytes = 256;
  p.transport.drain_query = DrainQuery::esc_b;
  p.transport.error_query = false;
  p.transport.flow = FlowControl::none;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, std::nullopt, 1e6});  // one move takes days
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  o.hold_timeout = std::chrono::seconds(30);
  const SendResult r = send_job(t, job, o);
  EXPECT_EQ(r.status.error, TransportError::timeout) << r.status.message;
  EXPECT_NE(r.status.message.find("showed no progress"), std::string::npos) << r.status.message;
  EXPECT_EQ(cutter->report().overflow_bytes, 0u);
  EXPECT_LT(cutter->now_s(), 120) << "ended after hold_timeout, not a wait forever";
}

// A device with no handshake that stops (paused, stuck) goes on taking bytes and loses what
// overruns its buffer; nothing tells popcut when. What it certainly holds is its buffer's worth
// from the start, so a resume never skips strokes it lost.
TEST(SendJob, TimePacingClaimsNoMoreReceivedThanTheBufferHolds) {
  DeviceProfile p = load_profile(config("sim.toml"));  // answers ESC.E: the stop is found after the job
  p.transport.flow = FlowControl::none;
  p.transport.buffer_bytes = 256;
  p.transport.drain_query = DrainQuery::none;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{std::size_t{1200}, std::nullopt, 1});
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  const SendResult r = send_job(t, job, o);
  ASSERT_FALSE(r.complete()) << "the stop is found by the silence after the job";
  EXPECT_EQ(r.received_counted_by, ReceivedCountedBy::buffer_size);
  EXPECT_LE(r.bytes_received, 256u) << "not the " << r.bytes_sent << " bytes written";
  EXPECT_LE(r.last_stroke_sent, job.last_stroke_within(256));
  EXPECT_LE(r.buffered_bytes, 256u) << "and it may still cut no more than its buffer holds (it lost the rest)";
}

// After a cancel, a device with no abort sequence goes on cutting what it holds; popcut says for
// how long, and that is long enough for a device within the margin.
TEST(SendJob, TimePacingSaysHowLongACancelledDeviceMayGoOnCutting) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.flow = FlowControl::none;
  p.transport.buffer_bytes = 256;
  p.transport.drain_query = DrainQuery::none;
  p.transport.error_query = false;
  p.transport.abort.clear();  // only the knife-up: the device keeps its buffer
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, std::nullopt, 1.2});
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job.bytes, p);
  std::atomic<bool> cancel{false};
  o.cancel = &cancel;
  o.progress = [&](const SendProgress& s) {
    if (s.bytes_sent > job.bytes.size() / 2) cancel = true;
  };
  const SendResult r = send_job(t, job, o);
  ASSERT_TRUE(r.cancelled) << r.status.message;
  ASSERT_GT(cutter->buffer_used(), 0u) << "still holds part of the job";
  EXPECT_GT(r.busy_for_s, 0.5);
  cutter->advance(cutter->now_s() + r.busy_for_s);
  EXPECT_EQ(cutter->buffer_used(), 0u) << "still busy " << r.busy_for_s << " s later";
  EXPECT_FALSE(cutter->next_start_s().has_value()) << "nothing left to start";
}

// A device far slower than the margin loses bytes whatever popcut does; one that reports it
// (ESC.E 16) fails the job rather than passing a spoiled card as done.
TEST(SendJob, ADeviceFarSlowerThanThePaceMarginIsCaughtByItsErrorReport) {
  DeviceProfile p = load_profile(config("sim.toml"));
  ASSERT_TRUE(p.transport.error_query);
  p.transport.buffer_bytes = 256;
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  const PacedRun r = run_paced(p, job, 3, 25);
  EXPECT_GT(r.report.overflow_bytes, 0u);
  EXPECT_FALSE(r.sent.complete());
  EXPECT_EQ(r.sent.device_io_error, 16) << r.sent.status.message;
}

// A line slower than the device: it waits for bytes, and the model must wait with it. Were the
// modelled device to run on meanwhile, it would be counted as having read the slow moves that
// follow long before it does, and be sent more than it holds.
TEST(SendJob, TimePacingWaitsWithADeviceStarvedByASlowLine) {
  DeviceProfile p = load_profile(config("sim.toml"));
  p.transport.baud = 300;  // 30 bytes/s: slower than the short strokes take them
  p.transport.buffer_bytes = 256;
  p.transport.drain_query = DrainQuery::none;
  p.transport.error_query = false;
  EncodedJob job;
  job.bytes = "IN;SP1;";
  for (int i = 0; i < 400; ++i) job.bytes += "PU0,0;PD1,0;";     // 12 bytes per 60 ms of knife up and down
  for (int i = 0; i < 100; ++i) job.bytes += "PU0,0;PD2000,0;";  // 15 bytes per second or so
  for (std::size_t i = 0; i < job.bytes.size(); ++i) {
    if (job.bytes[i] == ';') job.command_end.push_back(i + 1);
  }
  const PacedRun r = run_paced(p, job, 1, 25);
  ASSERT_TRUE(r.sent.complete()) << r.sent.status.message;
  EXPECT_EQ(r.report.overflow_bytes, 0u) << "most held " << r.report.max_buffer_used;
  EXPECT_EQ(r.strokes.size(), 500u);
}

// A printer-port node cannot answer and does not hold popcut off by byte count alone: the job is
// paced and drained by the plan's time estimate, never by reading from it (which it refuses).
TEST(SendJob, APrinterPortNodeIsPacedByTimeAndNeverRead) {
  for (const std::string& profile : {std::string("generic-hpgl.toml"), std::string("sim.toml")}) {
    const DeviceProfile p = load_profile(config(profile));
    const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
    const MadeTransport made = make_transport("file:/dev/null", p);
    ASSERT_TRUE(made.status.ok()) << made.status.message;
    ASSERT_TRUE(made.transport->open().ok());
    SendOptions o = send_options(p);
    o.motion = {{0, 0}, {0.2, job.bytes.size()}};  // a short wait for the drain share
    const SendResult r = send_job(*made.transport, job, o);
    EXPECT_TRUE(r.complete()) << profile << ": " << r.status.message;
    EXPECT_EQ(r.bytes_sent, job.bytes.size()) << profile << ": every byte written";
    made.transport->close();
  }
}

TEST(Profile, AbortAndTransportKeysAreValidated) {
  const std::string base = "[device]\nname = \"x\"\n[transport]\n";
  const std::pair<const char*, const char*> cases[] = {
      {"abort = \"PU;PD;\"", "must not lower the knife"},
      {"abort = \"\\u0007\"", "only ESC"},
      {"parity = \"mark\"", "is not one of"},
      {"data_bits = 9", "out of range"},
      {"flow_control = \"cts\"", "is not one of"},
      {"drain_query = \"esc_x\"", "is not one of"},
      {"drain_query = \"esc_e\"", "is not one of"},  // ESC.E says nothing of the buffer
      {"error_query = \"esc_o\"", "is not one of"},
      {"usb_ids = [\"0b4d-110a\"]", "is not a USB id"},
      {"adapter_fifo_bytes = 0", "out of range"},
      {"adapter_fifo_bytes = 2000000", "out of range"},
      {"pace_margin_percent = -1", "out of range"},
      {"pace_margin_percent = 1001", "out of range"},
      {"pace_margin_percent = 12.5", "whole number"},
      {"pace_margin_percent = \"25\"", "whole number"},
      {"abort_discards_buffer = true", "needs an abort sequence"},
      {"abort = \"\\u001b.K\"\nabort_discards_buffer = 1", "true or false"},
  };
  for (const auto& [line, expect] : cases) {
    try {
      parse_profile(base + line + "\n", "t.toml");
      ADD_FAILURE() << line << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << line << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("[transport]"), std::string::npos) << "names the section: " << e.what();
    }
  }
  const DeviceProfile ok =
      parse_profile(base + "abort = \"\\u001b.K\"\nflow_control = \"dtr_dsr\"\nusb_ids = [\"0B4D:110A\"]\n", "t.toml");
  EXPECT_EQ(ok.transport.abort, "\x1b.K");
  EXPECT_TRUE(ok.transport.abort_discards_buffer)
      << "an abort is taken to drop the device's buffer unless the profile says not";
  EXPECT_FALSE(parse_profile(base + "abort = \"\\u001b.K\"\nabort_discards_buffer = false\n", "t.toml")
                   .transport.abort_discards_buffer);
  EXPECT_FALSE(parse_profile(base, "t.toml").transport.abort_discards_buffer)
      << "no abort: the device keeps its buffer";
  EXPECT_EQ(ok.transport.flow, FlowControl::dtr_dsr);
  EXPECT_EQ(ok.transport.usb_ids, std::vector<std::string>{"0b4d:110a"});
  EXPECT_EQ(ok.transport.adapter_fifo_bytes, 4096u) << "unknown adapters: a margin above every FIFO checked";
  EXPECT_EQ(parse_profile(base + "adapter_fifo_bytes = 640\n", "t.toml").transport.adapter_fifo_bytes, 640u);
  EXPECT_FALSE(ok.transport.error_query) << "ESC.E is asked only where the profile says the device answers it";
  EXPECT_TRUE(parse_profile(base + "error_query = \"esc_e\"\n", "t.toml").transport.error_query);
}

}  // namespace
}  // namespace popcut::drivers
