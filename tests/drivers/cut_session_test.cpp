// The one cut path popcut cut and popcutd share: device strings, the plain-file rule, and the one clean-cut verdict.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/send_report.h"
#include "popcut/io/model_io.h"

namespace popcut::drivers {
namespace {

DeviceProfile sim_profile() { return load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/sim.toml"); }

StrokePlan townhouse_plan(const DeviceProfile& p) {
  PlanOptions o = p.plan;
  o.optimise_work = 1000;  // a small work budget: these tests are about sending, not ordering
  return plan_strokes(make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json")), o);
}

CutResult cut_on(const std::string& device, const DeviceProfile& p, const StrokePlan& plan, std::size_t from = 1,
                 const CutSessionOptions& options = {}) {
  CutSession session(device, p, options);
  EXPECT_TRUE(session.made().ok()) << session.made().message;
  const EncodedJob job = encode_job(plan, p.dialect, p.tools, from);
  return session.run(job, planned_paths(plan, p.dialect, from), {});
}

TEST(CutSession, SimCutsExactlyThePlan) {
  const DeviceProfile p = sim_profile();
  const StrokePlan plan = townhouse_plan(p);
  const CutResult r = cut_on("sim", p, plan);
  ASSERT_TRUE(r.open_status.ok()) << r.open_status.message;
  EXPECT_TRUE(r.sent.complete()) << r.sent.status.message;
  ASSERT_TRUE(r.sim.has_value()) << "the sim device is judged";
  EXPECT_EQ(r.sim->verdict(), SimVerdict::exact);
  EXPECT_TRUE(r.sim->cut_exactly_the_plan());
  EXPECT_TRUE(r.sim->ran_to_end);
  EXPECT_FALSE(r.sim->first_mismatch);
}

TEST(CutSession, ResumedCutIsHeldAgainstThePlanFromItsFirstStroke) {
  const DeviceProfile p = sim_profile();
  const StrokePlan plan = townhouse_plan(p);
  const std::size_t total = plan_in_plotter_units(plan, p.dialect).size();
  ASSERT_GT(total, 4u);
  const std::size_t from = total / 2;
  EXPECT_EQ(planned_paths(plan, p.dialect, from).size(), total - from + 1);
  EXPECT_EQ(planned_paths(plan, p.dialect, total + 5).size(), 0u) << "past the end: nothing to cut";
  const CutResult r = cut_on("sim", p, plan, from);
  ASSERT_TRUE(r.sim.has_value());
  EXPECT_TRUE(r.sim->cut_exactly_the_plan()) << to_string(r.sim->verdict());

  // Bytes from one stroke, held against the plan from another: the verdict shows it.
  CutSession session("sim", p);
  const EncodedJob job = encode_job(plan, p.dialect, p.tools, from);
  const CutResult wrong = session.run(job, planned_paths(plan, p.dialect, from - 1), {});
  ASSERT_TRUE(wrong.sim.has_value());
  EXPECT_EQ(wrong.sim->verdict(), SimVerdict::not_as_planned);
  EXPECT_EQ(wrong.sim->first_mismatch, std::optional<std::size_t>(0));
}

TEST(CutSession, PlainFileGetsTheJobUnpacedAndIsNotJudged) {
  const DeviceProfile p = sim_profile();
  const StrokePlan plan = townhouse_plan(p);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("cut_session_" + std::to_string(::getpid()) + ".hpgl");
  CutSession session("file:" + path.string(), p);
  ASSERT_TRUE(session.made().ok()) << session.made().message;
  EXPECT_TRUE(session.plain_file());
  EXPECT_EQ(session.simulator(), nullptr);
  EXPECT_EQ(session.describe(), "file:" + path.string());
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  const CutResult r = session.run(job, {}, {});
  ASSERT_TRUE(r.open_status.ok()) << r.open_status.message;
  EXPECT_TRUE(r.sent.complete()) << r.sent.status.message;
  EXPECT_FALSE(r.sim.has_value()) << "a file has nothing to hold against the plan";
  EXPECT_EQ(r.sent.drained_by, DrainedBy::none) << "a plain file is not waited for by the motion model";
  std::ifstream in(path, std::ios::binary);
  std::stringstream written;
  written << in.rdbuf();
  EXPECT_EQ(written.str(), job.bytes);
  std::filesystem::remove(path);
}

TEST(CutSession, DeviceNodesAreNotPlainFiles) {
  const DeviceProfile p = sim_profile();
  EXPECT_FALSE(CutSession("file:/dev/usb/lp0", p).plain_file()) << "a printer-port node has a device behind it";
  EXPECT_FALSE(CutSession("sim", p).plain_file());
  EXPECT_TRUE(CutSession("file:job.hpgl", p).plain_file());
}

TEST(CutSession, MalformedDeviceIsRefusedBeforeAnyOpen) {
  CutSession session("telnet:cutter", sim_profile());
  EXPECT_FALSE(session.made().ok());
  EXPECT_EQ(session.made().error, TransportError::bad_argument);
}

TEST(CutSession, FileThatCannotBeOpenedSendsNothing) {
  const DeviceProfile p = sim_profile();
  CutSession session("file:/nonexistent-dir-for-popcut/job.hpgl", p);
  ASSERT_TRUE(session.made().ok());
  const EncodedJob job = encode_job(townhouse_plan(p), p.dialect, p.tools);
  const CutResult r = session.run(job, {}, {});
  EXPECT_FALSE(r.open_status.ok());
  EXPECT_EQ(r.sent.bytes_sent, 0u);
}

TEST(CutSession, CancelBeforeTheFirstByteCutsNothing) {
  const DeviceProfile p = sim_profile();
  const StrokePlan plan = townhouse_plan(p);
  CutSession session("sim", p);
  const std::atomic<bool> cancel{true};
  CutControl control;
  control.cancel = &cancel;
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  const CutResult r = session.run(job, planned_paths(plan, p.dialect, 1), control);
  EXPECT_TRUE(r.sent.cancelled);
  EXPECT_EQ(r.sent.bytes_sent, 0u);
  ASSERT_TRUE(r.sim.has_value());
  EXPECT_EQ(r.sim->verdict(), SimVerdict::not_complete) << "a cancelled job is never a clean cut";
}

TEST(CutSession, SimThatStopsAnsweringIsNotACleanCut) {
  const DeviceProfile p = sim_profile();
  const StrokePlan plan = townhouse_plan(p);
  CutSessionOptions options;
  options.sim_faults.stop_answering_after_bytes = 200;
  CutSession session("sim", p, options);
  std::size_t progress_calls = 0;
  CutControl control;
  control.progress = [&](const SendProgress&) { ++progress_calls; };
  const EncodedJob job = encode_job(plan, p.dialect, p.tools);
  const CutResult r = session.run(job, planned_paths(plan, p.dialect, 1), control);
  EXPECT_FALSE(r.sent.complete());
  EXPECT_GT(progress_calls, 0u) << "the caller's progress hook sees the send";
  ASSERT_TRUE(r.sim.has_value());
  EXPECT_FALSE(r.sim->cut_exactly_the_plan());
  EXPECT_EQ(r.sim->verdict(), SimVerdict::not_complete);
}

// The single definition of a clean simulated cut: every fact must hold; each one alone spoils
// it, and the verdict names the worst.
TEST(SimCheck, CleanCutNeedsEveryFact) {
  SimCheck clean;
  clean.job_complete = true;
  clean.ran_to_end = true;
  EXPECT_EQ(clean.verdict(), SimVerdict::exact);
  EXPECT_TRUE(clean.cut_exactly_the_plan());

  SimCheck c = clean;
  c.job_complete = false;
  EXPECT_EQ(c.verdict(), SimVerdict::not_complete);
  c = clean;
  c.ran_to_end = false;
  EXPECT_EQ(c.verdict(), SimVerdict::stalled);
  c = clean;
  c.overflow_bytes = 1;
  EXPECT_EQ(c.verdict(), SimVerdict::lost_bytes);
  c = clean;
  c.outside_area = true;
  EXPECT_EQ(c.verdict(), SimVerdict::outside_area);
  c = clean;
  c.first_mismatch = 3;
  EXPECT_EQ(c.verdict(), SimVerdict::not_as_planned);
  c = clean;
  c.command_errors = 2;
  EXPECT_EQ(c.verdict(), SimVerdict::command_errors);
  EXPECT_FALSE(c.cut_exactly_the_plan()) << "malformed commands spoil a clean cut even when the strokes match";

  // Worst first: lost bytes outrank a mismatch they caused, a mismatch outranks command errors.
  c = clean;
  c.overflow_bytes = 5;
  c.first_mismatch = 0;
  c.command_errors = 1;
  EXPECT_EQ(c.verdict(), SimVerdict::lost_bytes);
  c.overflow_bytes = 0;
  EXPECT_EQ(c.verdict(), SimVerdict::not_as_planned);
  EXPECT_STREQ(to_string(SimVerdict::command_errors), "command_errors");
}

// A profile's own init string with a malformed command: the strokes are the plan's, yet the cut
// is not clean (popcutd's sim_match is false; popcut cut accepts it and lists the errors).
TEST(CutSession, MalformedInitIsACommandErrorNotAMismatch) {
  DeviceProfile p = sim_profile();
  p.dialect.init = "IN;PA1;";  // an odd number of coordinates: moves nothing
  const StrokePlan plan = townhouse_plan(p);
  const CutResult r = cut_on("sim", p, plan);
  ASSERT_TRUE(r.sim.has_value());
  EXPECT_TRUE(r.sent.complete()) << r.sent.status.message;
  EXPECT_FALSE(r.sim->first_mismatch) << "the knife-down paths are still the plan's";
  EXPECT_GT(r.sim->command_errors, 0u);
  EXPECT_EQ(r.sim->verdict(), SimVerdict::command_errors);
  EXPECT_FALSE(r.sim->cut_exactly_the_plan());
}

TEST(SendReport, StrokePositionsAndWhatIsStillBuffered) {
  SendResult sent;
  sent.first_stroke = 1;
  sent.total_strokes = 20;
  sent.last_stroke_sent = 7;
  sent.last_stroke_written = 9;
  sent.received_counted_by = ReceivedCountedBy::status_answers;
  EXPECT_EQ(counts_brief(sent),
            "last stroke known executed unknown, last stroke certainly received 7 of 20, last written 9");
  EXPECT_EQ(counts_text(sent),
            "last stroke known executed unknown (the device did not say), last stroke certainly received 7 of 20 "
            "(confirmed by the device's answers), last stroke written 9");
  sent.last_stroke_executed = 4;
  sent.bytes_sent = 300;
  EXPECT_EQ(resume_advice(sent),
            "; if the device still holds its buffer and goes on cutting, finish with the same command and "
            "--resume-from 8 (strokes 8..9 "
            "may have been cut already and are then cut a second time); if it was reset or power-cycled, or lost its "
            "buffer, use "
            "--resume-from 5 (strokes 5..7 may have been cut already)");
  EXPECT_EQ(still_buffered_text(sent), "nothing more");
  sent.buffered_bytes = 212;
  sent.buffered_first_stroke = 5;
  sent.buffered_last_stroke = 9;
  EXPECT_EQ(still_buffered_text(sent), "up to 212 bytes (strokes 5..9)");
  sent.buffer_known = true;
  EXPECT_EQ(still_buffered_text(sent), "212 bytes (strokes 5..9)");
  const nlohmann::json j = send_result_json(sent, 1000);
  EXPECT_EQ(j["bytes_total"], 1000);
  EXPECT_EQ(j["buffered_strokes"], nlohmann::json::array({5, 9}));
  EXPECT_EQ(j["last_stroke_executed"], 4);
  EXPECT_TRUE(j["device_io_error"].is_null());
}

}  // namespace
}  // namespace popcut::drivers
