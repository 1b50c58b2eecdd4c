// Time pacing at the edge of its margin: no byte lost at exactly the margin's slowdown, job time by the virtual clock,
// a slower device caught.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/motion_model.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/io/model_io.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

StrokePlan townhouse_plan(const DeviceProfile& p) {
  PlanOptions o = p.plan;
  o.optimise_work = 1000;  // these tests are about pacing, not ordering
  return plan_strokes(make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json")), o);
}

// A device that cannot be asked, with a 256-byte buffer (a quarter of a typical one), on a line
// that cannot hold popcut off.
DeviceProfile blind(DeviceProfile p) {
  p.transport.flow = FlowControl::none;
  p.transport.buffer_bytes = 256;
  p.transport.drain_query = DrainQuery::none;
  p.transport.error_query = false;
  return p;
}

struct PacedJob {
  SendResult sent;
  SimReport report;
  std::vector<SimStroke> strokes;
  double model_end_s = 0;  // the motion schedule's end, first-travel allowance included
};

// `job` time-paced with `margin_percent` to a simulator `slowdown` times slower than the plan,
// left by `earlier` where that ended. Everything on the simulator's virtual clock.
PacedJob pace(const DeviceProfile& p, const EncodedJob& job, int margin_percent, double slowdown,
              const std::string& earlier = "") {
  auto cutter = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, std::nullopt, slowdown});
  cutter->preload(earlier);
  cutter->run_to_end();
  const double start_s = cutter->now_s();
  SimTransport t(cutter);
  EXPECT_TRUE(t.open().ok());
  SendOptions o = send_options(p);
  o.motion = motion_schedule(job, p);
  o.pace_margin_percent = margin_percent;
  PacedJob r;
  r.model_end_s = o.motion.back().start_s;
  r.sent = send_job(t, job, o);
  cutter->run_to_end();
  r.report = cutter->report();
  r.report.clock_s -= start_s;
  r.strokes = cutter->strokes();
  return r;
}

// The far corner of the usable area; on a roll feeder, of a piece twice as long as wide, along
// whichever axis the roll runs (longest_first_travel_mm).
std::string far_corner(const HpglDialect& d) {
  const std::int64_t w = d.area_max_x_pu - d.area_min_x_pu, h = d.area_max_y_pu - d.area_min_y_pu;
  const double w_mm = static_cast<double>(w) / d.units_per_mm_x, h_mm = static_cast<double>(h) / d.units_per_mm_y;
  const std::int64_t x =
      w_mm > 2 * h_mm ? d.area_min_x_pu + static_cast<std::int64_t>(2 * h_mm * d.units_per_mm_x) : d.area_max_x_pu;
  const std::int64_t y =
      h_mm > 2 * w_mm ? d.area_min_y_pu + static_cast<std::int64_t>(2 * w_mm * d.units_per_mm_y) : d.area_max_y_pu;
  return std::to_string(x) + "," + std::to_string(y);
}

// Leaves a device at `xy` (plotter units): a knife-up move in the profile's language.
std::string move_to(const DeviceProfile& p, const std::string& xy) {
  return p.language == CutterLanguage::gpgl ? "\x1b\x04M" + xy + "\x03" : "IN;PU" + xy + ";";
}

// A roll feeder's first travel crosses a piece twice as long as wide, whichever plotter axis the
// roll runs along: the Cameo 4's 3000 mm roll runs along plotter x (its axes are swapped).
TEST(TimePacing, TheFirstTravelCrossesARollPieceAlongEitherAxis) {
  const DeviceProfile cameo = load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/silhouette-cameo4.toml");
  EXPECT_NEAR(longest_first_travel_mm(cameo.dialect), std::hypot(304.8, 609.6), 0.5);
  const DeviceProfile graphtec = load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/graphtec-ce.toml");
  EXPECT_NEAR(longest_first_travel_mm(graphtec.dialect), std::hypot(600, 1200), 0.5) << "a roll along plotter y";
}

// The guarantee at its edge: a device exactly the margin slower than the plan, at the origin or
// left at the far corner of its area, loses nothing and cuts the whole job, whatever the margin
// (the shipped 25 %, the calibrated default 10 %, and 5 %).
TEST(TimePacing, ADeviceExactlyTheMarginSlowerLosesNothing) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = blind(load_profile(file));
    const StrokePlan plan = townhouse_plan(p);
    const EncodedJob job = encode_for_device(plan, p);
    const std::vector<PlotterPath> planned = plan_in_plotter_units(plan, p.dialect);
    for (const int margin : {25, 10, 5}) {
      for (const std::string& earlier : {std::string(), move_to(p, far_corner(p.dialect))}) {
        const PacedJob r = pace(p, job, margin, 1 + margin / 100.0, earlier);
        const std::string what = file + ", margin " + std::to_string(margin) + " %" + (earlier.empty() ? "" : ", far");
        ASSERT_TRUE(r.sent.complete()) << what << ": " << r.sent.status.message;
        EXPECT_EQ(r.report.overflow_bytes, 0u) << what;
        EXPECT_LE(r.report.max_buffer_used, 256u) << what;
        EXPECT_FALSE(first_difference(planned, r.strokes).has_value()) << what << ": the whole job cut";
      }
    }
  }
}

// Job time on the virtual clock: a device as fast as the plan waits for bytes as the margin says,
// over the motion schedule (which allows for a first travel across the area): the margin times
// that, and no more (pacing granularity and the end of the job add under 1 %). A smaller margin
// costs proportionally less.
TEST(TimePacing, JobTimeIsTheMarginTimesTheSchedule) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = blind(load_profile(file));
    const EncodedJob job = encode_for_device(townhouse_plan(p), p);
    double previous_s = 0;
    for (const int margin : {5, 10, 25}) {
      const PacedJob r = pace(p, job, margin, 1);
      ASSERT_TRUE(r.sent.complete()) << file << ": " << r.sent.status.message;
      const double paced_s = (1 + margin / 100.0) * r.model_end_s;
      EXPECT_LT(r.report.clock_s, 1.01 * paced_s + 0.1) << file << ", margin " << margin;
      EXPECT_GT(r.report.clock_s, 0.95 * paced_s)
          << file << ", margin " << margin << ": done only when the slowed model is";
      EXPECT_GT(r.report.clock_s, previous_s) << file << ": a larger margin takes longer";
      previous_s = r.report.clock_s;
      if (margin == 5) {
        EXPECT_LT(r.report.clock_s, 1.25 * r.report.motion_time_s)
            << file << ": a calibrated margin of 5 %: " << r.report.clock_s << " s for " << r.report.motion_time_s
            << " s of motion";
      }
    }
  }
}

// Beyond the margin nothing on the line can tell popcut the device is behind; one that answers
// ESC.E reports the overflow after the job, and the job fails naming the margin to raise.
TEST(TimePacing, ADeviceSlowerThanTheMarginIsCaughtByItsErrorAnswer) {
  DeviceProfile p = blind(load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/sim.toml"));
  p.transport.error_query = true;
  const EncodedJob job = encode_for_device(townhouse_plan(p), p);
  const PacedJob r = pace(p, job, 10, 1.6);
  ASSERT_GT(r.report.overflow_bytes, 0u) << "60 % slower than the plan overruns a 10 % margin";
  EXPECT_FALSE(r.sent.complete());
  EXPECT_EQ(r.sent.status.error, TransportError::io) << r.sent.status.message;
  EXPECT_NE(r.sent.status.message.find("a pace margin of 10 %"), std::string::npos) << r.sent.status.message;
  const PacedJob within = pace(p, job, 10, 1.1);
  EXPECT_TRUE(within.sent.complete()) << "at the margin the same device reports no error: "
                                      << within.sent.status.message;
}

// The overflow message names the margin in use and the key it came from: the profile's own margin
// for a guessed pace, the calibrated one (and where the pace was measured) for a measured pace.
TEST(TimePacing, TheOverflowNamesTheMarginInUseAndItsKey) {
  DeviceProfile p = blind(load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/sim.toml"));
  p.transport.error_query = true;
  p.transport.pace_margin_percent = 12;
  p.transport.pace_margin_calibrated_percent = 4;
  EXPECT_EQ(p.transport.pace_margin_in_use(), 12);
  EXPECT_STREQ(p.transport.pace_margin_key(), "[transport] pace_margin_percent");
  const EncodedJob job = encode_for_device(townhouse_plan(p), p);
  const PacedJob guessed = pace(p, job, p.transport.pace_margin_in_use(), 1.6);
  ASSERT_EQ(guessed.sent.status.error, TransportError::io) << guessed.sent.status.message;
  EXPECT_NE(guessed.sent.status.message.find("a pace margin of 12 % ([transport] pace_margin_percent in " + p.source +
                                             ": the pace is not calibrated)"),
            std::string::npos)
      << guessed.sent.status.message;
  p.transport.pace_measured = true;
  p.calibration.overlay = "/cal/sim.toml";
  EXPECT_EQ(p.transport.pace_margin_in_use(), 4);
  EXPECT_STREQ(p.transport.pace_margin_key(), "[transport] pace_margin_calibrated_percent");
  const PacedJob measured = pace(p, job, p.transport.pace_margin_in_use(), 1.6);
  ASSERT_EQ(measured.sent.status.error, TransportError::io) << measured.sent.status.message;
  EXPECT_NE(measured.sent.status.message.find("a pace margin of 4 % ([transport] pace_margin_calibrated_percent in " +
                                              p.source +
                                              ", since [kinematics] time_factor in /cal/sim.toml measured "
                                              "the pace)"),
            std::string::npos)
      << measured.sent.status.message;
}

// The calibrated margin: 10 % by default, never above the profile's own margin.
TEST(TimePacing, TheCalibratedMarginIsReadAndChecked) {
  const std::string base = "[device]\nname = \"x\"\n[transport]\n";
  EXPECT_EQ(parse_profile(base, "t.toml").transport.pace_margin_calibrated_percent, 10);
  EXPECT_EQ(parse_profile(base + "pace_margin_percent = 5\n", "t.toml").transport.pace_margin_calibrated_percent, 5)
      << "a profile's margin below the default is the calibrated one's too";
  EXPECT_EQ(
      parse_profile(base + "pace_margin_calibrated_percent = 3\n", "t.toml").transport.pace_margin_calibrated_percent,
      3);
  const std::pair<const char*, const char*> cases[] = {
      {"pace_margin_calibrated_percent = 30", "must not exceed pace_margin_percent (25)"},
      {"pace_margin_calibrated_percent = -1", "out of range"},
      {"pace_margin_calibrated_percent = 2.5", "whole number"},
  };
  DeviceProfile p = parse_profile(base + "pace_margin_percent = 30\npace_margin_calibrated_percent = 7\n", "t.toml");
  EXPECT_EQ(send_options(p).pace_margin_percent, 30) << "a guessed pace: the profile's margin";
  p.transport.pace_measured = true;
  EXPECT_EQ(send_options(p).pace_margin_percent, 7) << "a measured pace: the calibrated margin";
  for (const auto& [line, expect] : cases) {
    try {
      parse_profile(base + line + "\n", "t.toml");
      ADD_FAILURE() << line << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << line << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("[transport] pace_margin_calibrated_percent"), std::string::npos)
          << e.what();
    }
  }
}

// A device that stands where its finish leaves the head when a job starts ([kinematics] starts_at
// "origin"), the finish made absolute where a shipped HP-GL one is not, calibrated.
DeviceProfile parked(DeviceProfile p) {
  if (p.language == CutterLanguage::hpgl) p.dialect.finish = "PU;PA0,0;SP0;";
  p.starts_at = StartsAt::origin;
  p.transport.pace_measured = true;
  check_starts_at(p);
  return p;
}

// With the start known, the model allows no first travel: a calibrated device as fast as its
// measured pace ends within the calibrated margin (10 %) of its motion, under the 1.15 the
// cutters issue asks of devices that cannot be asked; one exactly that margin slower, started
// where the last job's finish (or a cancel) left it, loses nothing.
TEST(TimePacing, ADeviceThatStartsWhereItsFinishParksIsPacedWithoutTheFirstTravel) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = parked(blind(load_profile(file)));
    const StrokePlan plan = townhouse_plan(p);
    const EncodedJob job = encode_for_device(plan, p);
    const std::vector<PlotterPath> planned = plan_in_plotter_units(plan, p.dialect);
    const std::string park = language_unit(p.language).park(p);
    const int margin = send_options(p).pace_margin_percent;
    ASSERT_EQ(margin, 10) << file;
    const PacedJob fast = pace(p, job, margin, 1, park);
    ASSERT_TRUE(fast.sent.complete()) << file << ": " << fast.sent.status.message;
    EXPECT_LE(fast.report.clock_s, 1.11 * fast.report.motion_time_s) << file;
    EXPECT_GT(fast.report.clock_s, 1.05 * fast.report.motion_time_s) << file << ": the margin is still paid";
    for (const std::string& earlier : {park, park + move_to(p, "40,40") + send_options(p).abort_bytes}) {
      const PacedJob slow = pace(p, job, margin, 1.10, earlier);
      ASSERT_TRUE(slow.sent.complete()) << file << ": " << slow.sent.status.message;
      EXPECT_EQ(slow.report.overflow_bytes, 0u) << file;
      EXPECT_FALSE(first_difference(planned, slow.strokes).has_value()) << file << ": the whole job cut";
    }
  }
}

// Two jobs in a row on one device, the second started where the first's finish left the head, a
// device the margin slower: the second loses nothing either.
TEST(TimePacing, ASecondJobStartsWhereTheFirstParkedAndLosesNothing) {
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = parked(blind(load_profile(file)));
    const EncodedJob job = encode_for_device(townhouse_plan(p), p);
    const PacedJob second = pace(p, job, 10, 1.10, job.bytes);
    ASSERT_TRUE(second.sent.complete()) << file << ": " << second.sent.status.message;
    EXPECT_EQ(second.report.overflow_bytes, 0u) << file;
  }
}

// What starts_at = "origin" rests on: a device left far from where the finish parks, as slow as
// the margin allows, overflows in some dialect; and a resumed job (which starts where its
// interrupted run stopped) keeps the first-travel allowance.
TEST(TimePacing, StartsAtOriginIsAClaimAboutTheDeviceAndAResumeDoesNotRelyOnIt) {
  std::size_t overflowed = 0;
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = parked(blind(load_profile(file)));
    const StrokePlan plan = townhouse_plan(p);
    const PacedJob far = pace(p, encode_for_device(plan, p), 10, 1.10, move_to(p, far_corner(p.dialect)));
    overflowed += far.report.overflow_bytes;
    const EncodedJob resumed = encode_for_device(plan, p, 20);
    const std::vector<MotionMark> marks = motion_schedule(resumed, p), anywhere = motion_schedule(resumed.bytes, p);
    ASSERT_EQ(marks.size(), anywhere.size()) << file;
    EXPECT_DOUBLE_EQ(marks.back().start_s, anywhere.back().start_s) << file;
  }
  EXPECT_GT(overflowed, 0u) << "a device left at the far corner is not paced for by starts_at = \"origin\"";
}

// `text` with its first `from` replaced by `to` (which must be there).
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

// A finish that leaves the head where the job ended (no move, or a relative one) cannot carry
// starts_at = "origin": refused at load, naming the key and where the head is left.
TEST(TimePacing, StartsAtOriginNeedsAFinishThatGoesThere) {
  const std::string base = std::string(POPCUT_SOURCE_DIR) + "/configs/devices/";
  for (const std::string name : {"generic-hpgl", "secabo"}) {
    std::string text = replaced(read_text_file(base + name + ".toml", 1 << 20), "[kinematics]",
                                "[kinematics]\nstarts_at = \"origin\"");
    if (name == "secabo") text = replaced(text, "finish = \"PU;PA0,0;\"", "finish = \"PU0,0;\"");
    try {
      parse_profile(text, name);
      ADD_FAILURE() << name << ": accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("[kinematics] starts_at"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("leaves it at"), std::string::npos) << e.what();
    }
  }
  const std::string ok =
      replaced(read_text_file(base + "secabo.toml", 1 << 20), "[kinematics]", "[kinematics]\nstarts_at = \"origin\"");
  EXPECT_EQ(parse_profile(ok, "secabo").starts_at, StartsAt::origin) << "its finish goes home absolutely";
}

}  // namespace
}  // namespace popcut::drivers
