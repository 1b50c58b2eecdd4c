// HP-GL reader and simulated cutter: parsing, flow control, faults, and plan ⇄ recovered strokes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "popcut/drivers/hpgl_reader.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

std::string config(const std::string& name) { return std::string(POPCUT_SOURCE_DIR) + "/configs/devices/" + name; }

using testing::shipped_profiles;

TEST(HpglReader, CommandsParamsAndSeparators) {
  const auto c = parse_hpgl("IN;SP1;PU100,200;PD 300 400,500,600\nPA;!FS80;VS10,1;ZZ3;PR-5,+7");
  std::vector<std::string> names;
  for (const auto& x : c) names.push_back(x.name);
  EXPECT_EQ(names, (std::vector<std::string>{"IN", "SP", "PU", "PD", "PA", "!FS", "VS", "ZZ", "PR"}));
  EXPECT_EQ(c[3].params, (std::vector<double>{300, 400, 500, 600})) << "blanks and commas both separate";
  EXPECT_EQ(c[5].params, std::vector<double>{80}) << "Roland !FS";
  EXPECT_EQ(c[8].params, (std::vector<double>{-5, 7})) << "signed numbers; the last command needs no terminator";
}

TEST(HpglReader, SplitWritesAndOutOfBandEscapes) {
  const std::string job = "PU;PA10,20,30,40,50,60;PD;";
  HpglReader r;
  std::vector<HpglCommand> out;
  r.feed("PU;PA10,2", out);
  r.feed("0,30,4\x1b.B", out);  // a buffer query arrives inside the coordinates
  r.feed("0,50,60;PD;", out);
  r.finish(out);
  std::vector<double> pa;
  bool query = false;
  for (const auto& c : out) {
    if (c.name == "PA") pa.insert(pa.end(), c.params.begin(), c.params.end());
    if (c.name == "ESC.B") query = true;
    EXPECT_FALSE(c.malformed) << c.name << " at " << c.offset;
  }
  EXPECT_TRUE(query) << "ESC.B is taken out wherever it arrives";
  EXPECT_EQ(pa, (std::vector<double>{10, 20, 30, 40, 50, 60})) << "the coordinates survive the split and the query";
}

double dist_to_segment(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, l2 = dx * dx + dv * dv;
  const double t = l2 > 0 ? std::clamp(((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / l2, 0.0, 1.0) : 0;
  return std::hypot(p.x_mm - a.x_mm - t * dx, p.v_mm - a.v_mm - t * dv);
}

DeviceProfile sim_profile() { return load_profile(config("sim.toml")); }

std::string drain_replies(SimTransport& t) {
  std::string s;
  std::uint8_t buf[64];
  for (;;) {
    const IoResult r = t.read(buf, std::chrono::milliseconds(0));
    if (r.bytes == 0) return s;
    s.append(reinterpret_cast<const char*>(buf), r.bytes);
  }
}

TEST(SimCutter, RecordsStrokesWithToolForceAndSpeedAndReportsUnknownCommands) {
  auto cutter = std::make_shared<SimCutter>(sim_profile());
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const std::string job = "IN;SP2;VS12;FS55;PU100,100;PD200,100,200,200;PU;XX9;PA400,400;PD;PR0,40;PU;";
  ASSERT_TRUE(t.write({reinterpret_cast<const std::uint8_t*>(job.data()), job.size()}, std::chrono::milliseconds(1000))
                  .status.ok());
  ASSERT_TRUE(cutter->run_to_end());
  const auto& s = cutter->strokes();
  ASSERT_EQ(s.size(), 2u) << "two knife-down paths";
  EXPECT_EQ(s[0].points_pu, (PlotterPath{{100, 100}, {200, 100}, {200, 200}}));
  EXPECT_EQ(s[0].pen, 2);
  EXPECT_EQ(s[0].force, 55);
  EXPECT_EQ(s[0].speed_cm_s, 12);
  EXPECT_EQ(s[1].points_pu, (PlotterPath{{400, 400}, {400, 440}})) << "relative move after PR";
  ASSERT_EQ(cutter->report().unknown.size(), 1u) << "XX is reported";
  EXPECT_EQ(cutter->report().unknown[0].command, "XX");
  EXPECT_NEAR(cutter->report().knife_down_mm, 2.5 + 2.5 + 1, 1e-9) << "100 units = 2.5 mm at 40/mm";
  EXPECT_GT(cutter->report().motion_time_s, 0);
}

// A line that ends in the middle of "PD200,3480" delivers "PD200,348": a real device never sees
// that command end and never runs it; a file that simply lacks the last ';' does run it.
TEST(SimCutter, ACommandCutShortByAHangUpIsNotRun) {
  const std::string job = "IN;SP1;PU100,100;PD200,100,200,348";
  for (const bool whole : {false, true}) {
    auto cutter = std::make_shared<SimCutter>(sim_profile());
    SimTransport t(cutter);
    ASSERT_TRUE(t.open().ok());
    ASSERT_TRUE(
        t.write({reinterpret_cast<const std::uint8_t*>(job.data()), job.size()}, std::chrono::milliseconds(1000))
            .status.ok());
    ASSERT_TRUE(cutter->run_to_end(whole));
    // Whole coordinate pairs run as they arrive (the reader splits a long PD); the last pair,
    // "200,348", is the one whose end the line may have cut.
    ASSERT_EQ(cutter->strokes().size(), 1u) << "the knife went down for the pairs that arrived whole";
    const PlotterPath whole_path{{100, 100}, {200, 100}, {200, 348}}, cut_short{{100, 100}, {200, 100}};
    EXPECT_EQ(cutter->strokes()[0].points_pu, whole ? whole_path : cut_short)
        << (whole ? "a whole input's last command runs" : "a command cut short by a hang-up does not run");
    EXPECT_EQ(cutter->report().errors.size(), whole ? 0u : 1u) << "and the cut-short one is reported";
  }
}

TEST(SimCutter, HostileNumbersAreReportedNotFatal) {
  auto cutter = std::make_shared<SimCutter>(sim_profile());
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  // HP-GL has no exponents (a letter starts a command): huge numbers are long digit strings.
  const std::string job = "IN;PR" + std::string(30, '9') + ",1;PR-" + std::string(30, '9') + ",1;PA1" +
                          std::string(400, '0') + ",5;PD1,2,3;";
  t.write({reinterpret_cast<const std::uint8_t*>(job.data()), job.size()}, std::chrono::milliseconds(100));
  ASSERT_TRUE(cutter->run_to_end());
  EXPECT_TRUE(cutter->report().outside_area) << "moves far off the table are flagged";
  const auto& errors = cutter->report().errors;
  ASSERT_EQ(errors.size(), 3u) << "PA: a number beyond double (malformed, leaving an odd count); PD: three numbers";
  EXPECT_EQ(errors[0].command + " " + errors[0].message, "PA malformed parameters");
  EXPECT_EQ(errors[1].command + " " + errors[1].message, "PA odd number of coordinates");
  EXPECT_EQ(errors[2].command + " " + errors[2].message, "PD odd number of coordinates");
}

TEST(SimCutter, AnswersBufferAndStatusQueries) {
  auto cutter = std::make_shared<SimCutter>(sim_profile());
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const std::string q = "\x1b.B\x1b.O";
  t.write({reinterpret_cast<const std::uint8_t*>(q.data()), q.size()}, std::chrono::milliseconds(100));
  EXPECT_EQ(drain_replies(t), "1024\r8\r") << "an idle device: whole buffer free, status 8 (buffer empty)";
  const std::string part = "PU;PD1000,1000,0,0,1000,1000;";  // queued behind a long move
  t.write({reinterpret_cast<const std::uint8_t*>(part.data()), part.size()}, std::chrono::milliseconds(100));
  const std::string q2 = "IN;SP1;PA5,5;\x1b.B";
  t.write({reinterpret_cast<const std::uint8_t*>(q2.data()), q2.size()}, std::chrono::milliseconds(100));
  const std::string free_bytes = drain_replies(t);
  // The PD's first pair is executing; the rest of it ("PD" is the device's, "0,0,1000,1000;" 14
  // bytes arrived) and the 13 bytes that came in the same read as the query wait in the buffer.
  EXPECT_EQ(free_bytes, std::to_string(1024 - 14 - 13) + "\r") << "every byte ahead of the query is counted";
}

// A pacing host sends exactly what ESC.B said was free; the answer must count every byte that
// arrived ahead of the query, however the line groups them, or the host overruns the buffer.
TEST(SimCutter, BufferAnswerCountsEveryByteAheadOfTheQuery) {
  DeviceProfile p = sim_profile();
  p.transport.flow = FlowControl::esc_b;
  p.transport.buffer_bytes = 256;
  p.kinematics.travel_speed_mm_s = 1;  // nothing leaves the buffer while this test sends
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    auto cutter = std::make_shared<SimCutter>(p);
    SimTransport t(cutter);
    ASSERT_TRUE(t.open().ok());
    const std::string start = "IN;PU0,0;PD4000,4000;";  // the long move holds everything behind it
    ASSERT_TRUE(
        t.write({reinterpret_cast<const std::uint8_t*>(start.data()), start.size()}, std::chrono::milliseconds(100))
            .status.ok());
    std::string line, expected;
    std::size_t hpgl = 0;
    for (int k = 0; k < 6; ++k) {
      std::string cmd = "PU" + std::to_string(rng() % 100) + "," + std::to_string(rng() % 100) + ";";
      if (rng() % 2) cmd += "\n";  // separators occupy the buffer too
      line += cmd;
      hpgl += cmd.size();
      line += "\x1b.B";
      expected += std::to_string(256 - hpgl) + "\r";
    }
    // Split the line into writes of random sizes, as a pseudo-terminal delivers it.
    for (std::size_t i = 0; i < line.size();) {
      const std::size_t n = std::min<std::size_t>(line.size() - i, 1 + rng() % 40);
      ASSERT_TRUE(t.write({reinterpret_cast<const std::uint8_t*>(line.data()) + i, n}, std::chrono::milliseconds(100))
                      .status.ok());
      i += n;
    }
    EXPECT_EQ(drain_replies(t), expected) << "trial " << trial << ": " << line;
  }
}

TEST(SimCutter, XonXoffKeepsTheBufferFromOverflowing) {
  DeviceProfile p = sim_profile();
  p.transport.buffer_bytes = 256;
  auto cutter = std::make_shared<SimCutter>(p);
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  std::string job = "IN;SP1;";
  for (int i = 0; i < 200; ++i) job += "PU0,0;PD4000,0,4000,4000;";
  const SendResult r = send_job(t, job, send_options(p));
  ASSERT_TRUE(r.status.ok()) << r.status.message;
  EXPECT_GT(r.holds, 0) << "a slow device holds the host off";
  ASSERT_TRUE(cutter->run_to_end());
  EXPECT_EQ(cutter->report().overflow_bytes, 0u) << "the host honoured XOFF";
  EXPECT_LE(cutter->report().max_buffer_used, 256u);
  EXPECT_EQ(cutter->strokes().size(), 200u);

  // A host that ignores flow control loses bytes: the model notices.
  auto rude = std::make_shared<SimCutter>(p);
  SimTransport t2(rude);
  ASSERT_TRUE(t2.open().ok());
  SendOptions none = send_options(p);
  none.flow = FlowControl::none;
  send_job(t2, job, none);
  EXPECT_GT(rude->report().overflow_bytes, 0u) << "ignoring XOFF overflows the buffer";
}

TEST(SimCutter, FaultsShowUpAsTransportErrors) {
  const DeviceProfile p = sim_profile();
  std::string job = "IN;SP1;";
  for (int i = 0; i < 300; ++i) job += "PU0,0;PD400,0,400,400;";
  {
    auto c = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, 500, 1});
    SimTransport t(c);
    ASSERT_TRUE(t.open().ok());
    const SendResult r = send_job(t, job, send_options(p));
    EXPECT_EQ(r.status.error, TransportError::disconnected) << r.status.message;
    EXPECT_EQ(r.bytes_sent + 3 * static_cast<std::size_t>(r.status_queries), 500u)
        << "exactly the bytes before the drop got through (the job's and the ESC.O status queries')";
  }
  {
    auto c = std::make_shared<SimCutter>(p, SimFaults{700, std::nullopt, 1});
    SimTransport t(c);
    ASSERT_TRUE(t.open().ok());
    SendOptions o = send_options(p);
    o.hold_timeout = std::chrono::milliseconds(2000);
    const SendResult r = send_job(t, job, o);
    EXPECT_EQ(r.status.error, TransportError::timeout)
        << "a device that stops answering times out: " << r.status.message;
    EXPECT_FALSE(c->run_to_end()) << "and never finishes";
  }
  {
    auto fast = std::make_shared<SimCutter>(p);
    auto slow = std::make_shared<SimCutter>(p, SimFaults{std::nullopt, std::nullopt, 3});
    for (auto& c : {fast, slow}) {
      SimTransport t(c);
      ASSERT_TRUE(t.open().ok());
      ASSERT_TRUE(send_job(t, job, send_options(p)).status.ok());
      ASSERT_TRUE(c->run_to_end());
    }
    EXPECT_NEAR(slow->report().motion_time_s, 3 * fast->report().motion_time_s, 1e-6) << "slowdown scales motion";
    EXPECT_EQ(slow->strokes().size(), fast->strokes().size()) << "but cuts the same";
  }
}

// The core property: for random models and every shipped profile, what the simulator recovers
// from the bytes is exactly the plan (within one plotter unit), with nothing outside the area.
TEST(SimCutter, RecoversThePlannedStrokesForEveryProfile) {
  std::mt19937_64 rng(5);
  testing::RandomModelSpec spec;
  spec.window_probability = 0.2;
  std::vector<Pattern> patterns;
  for (int i = 0; i < 12; ++i) patterns.push_back(make_pattern(testing::random_model(rng, spec)));
  for (int i = 0; i < 4; ++i) patterns.push_back(make_pattern(AnyModel(testing::random_face_model(rng, {}))));
  for (const std::string& file : shipped_profiles()) {
    const DeviceProfile prof = load_profile(file);
    for (std::size_t n = 0; n < patterns.size(); ++n) {
      const StrokePlan plan = plan_strokes(patterns[n], prof.plan);
      const EncodedJob job = encode_for_device(plan, prof);  // in the profile's language
      auto cutter = std::make_shared<SimCutter>(prof);
      SimTransport t(cutter);
      ASSERT_TRUE(t.open().ok());
      const SendResult sent = send_job(t, job, send_options(prof));
      ASSERT_TRUE(sent.status.ok()) << file << " model " << n << ": " << sent.status.message;
      ASSERT_TRUE(cutter->run_to_end());
      const SimReport& r = cutter->report();
      const auto planned = plan_in_plotter_units(plan, prof.dialect);
      const auto diff = first_difference(planned, cutter->strokes());
      EXPECT_FALSE(diff.has_value()) << file << " model " << n << ": stroke " << diff.value_or(0) << " differs ("
                                     << planned.size() << " planned, " << cutter->strokes().size() << " cut)";
      EXPECT_FALSE(r.outside_area) << file << " model " << n << ": a move left the usable area";
      EXPECT_EQ(r.overflow_bytes, 0u) << file << " model " << n;
      EXPECT_TRUE(r.unknown.empty()) << file << " model " << n << ": "
                                     << (r.unknown.empty() ? "" : r.unknown[0].command);
      EXPECT_TRUE(r.errors.empty()) << file << " model " << n << ": " << (r.errors.empty() ? "" : r.errors[0].message);
      // Each stroke carries the tool its kind was given.
      std::size_t k = 0;
      for (const Stroke& s : plan.strokes) {
        if (k >= cutter->strokes().size()) break;
        const ToolSetting& tool = prof.tools[index_of(s.kind)];
        EXPECT_EQ(cutter->strokes()[k].pen, tool.pen) << file << " model " << n << " stroke " << k;
        ++k;
      }
    }
  }
}

// A drag knife with precuts on the simulated cutter: it cuts exactly the plan, each precut is
// followed by its stroke, and every knife-down point stays within the blade offset of a line of
// the pattern (the axis runs that far ahead of the tip, which follows the lines): nothing is cut
// where the pattern has no line.
TEST(SimCutter, PrecutsCutOnlyAlongThePatternsLines) {
  std::ifstream in(config("sim.toml"));
  std::stringstream text;
  text << in.rdbuf();
  const double offset_mm = 0.3;
  const DeviceProfile prof =
      parse_profile(text.str() + "\n[plan]\nblade_offset_mm = 0.3\nprecut_mm = 1.0\n", "sim+precut.toml");
  ASSERT_FALSE(prof.dialect.swap_axes || prof.dialect.flip_x || prof.dialect.flip_y)
      << "the mm mapping below assumes plain axes";
  std::mt19937_64 rng(31);
  int precuts_seen = 0;
  for (int n = 0; n < 8; ++n) {
    const Pattern pattern = make_pattern(testing::random_model(rng, {}));
    const StrokePlan plan = plan_strokes(pattern, prof.plan);
    auto cutter = std::make_shared<SimCutter>(prof);
    SimTransport t(cutter);
    ASSERT_TRUE(t.open().ok());
    ASSERT_TRUE(send_job(t, encode_hpgl(plan, prof.dialect, prof.tools), send_options(prof)).status.ok());
    ASSERT_TRUE(cutter->run_to_end());
    const auto planned = plan_in_plotter_units(plan, prof.dialect);
    EXPECT_FALSE(first_difference(planned, cutter->strokes()).has_value())
        << "model " << n << ": the simulator cuts the plan";
    ASSERT_EQ(cutter->strokes().size(), plan.strokes.size()) << "model " << n << ": no stroke below resolution here";
    std::vector<Segment> lines = kind_lines(pattern, PlanKind::outline, 0);
    for (const Segment& l : pattern.lines) lines.push_back(l);
    const Rect frame = plan.extent();
    for (std::size_t k = 0; k < plan.strokes.size(); ++k) {
      if (plan.strokes[k].precut) {
        ++precuts_seen;
        ASSERT_LT(k + 1, plan.strokes.size()) << "model " << n << ": a precut comes before its stroke";
        EXPECT_FALSE(plan.strokes[k + 1].precut) << "model " << n << " stroke " << k;
        EXPECT_EQ(plan.strokes[k + 1].kind, plan.strokes[k].kind) << "model " << n << " stroke " << k;
      }
      for (const auto& q : cutter->strokes()[k].points_pu) {
        const Point2 mm{
            frame.min.x_mm + static_cast<double>(q[0] - prof.dialect.area_min_x_pu) / prof.dialect.units_per_mm_x,
            frame.min.v_mm + static_cast<double>(q[1] - prof.dialect.area_min_y_pu) / prof.dialect.units_per_mm_y};
        double d = 1e9;
        for (const Segment& l : lines) d = std::min(d, dist_to_segment(mm, l.a, l.b));
        EXPECT_LE(d, offset_mm + 1.0 / 40)
            << "model " << n << " stroke " << k << (plan.strokes[k].precut ? " (precut)" : "") << ": cut point ("
            << mm.x_mm << ", " << mm.v_mm << ") lies off every line";
      }
    }
    EXPECT_EQ(plan.total().precuts, plan.total().strokes) << "model " << n << ": one precut per stroke";
  }
  EXPECT_GT(precuts_seen, 50) << "the property was checked on many precuts";
}

TEST(SimCutter, SvgHasOnePolylinePerStrokeColouredByPen) {
  auto cutter = std::make_shared<SimCutter>(sim_profile());
  SimTransport t(cutter);
  ASSERT_TRUE(t.open().ok());
  const std::string job = "IN;SP1;PU0,0;PD40,0;PU;SP2;PU0,40;PD40,40;PU;";
  t.write({reinterpret_cast<const std::uint8_t*>(job.data()), job.size()}, std::chrono::milliseconds(100));
  ASSERT_TRUE(cutter->run_to_end());
  std::ostringstream svg;
  cutter->write_svg(svg);
  const std::string s = svg.str();
  std::size_t count = 0;
  for (std::size_t at = 0; (at = s.find("<polyline", at)) != std::string::npos; ++at) ++count;
  EXPECT_EQ(count, 2u) << s;
  EXPECT_NE(s.find("data-pen=\"1\" data-force=\"0\" data-speed=\"0\" stroke=\"#d62728\""), std::string::npos) << s;
  EXPECT_NE(s.find("stroke=\"#1f77b4\""), std::string::npos) << "pen 2 has its own colour: " << s;
}

// The pace time pacing assumes is the simulator's own: the schedule ends when the device's motion
// does, reads the job in order, and frees a long coordinate command pair by pair.
TEST(SimCutter, MotionScheduleIsTheDevicesOwnPace) {
  DeviceProfile p = sim_profile();
  std::string job = "IN;SP1;VS10;";
  for (int i = 0; i < 40; ++i) job += "PU" + std::to_string(i * 40) + ",0;PD" + std::to_string(i * 40) + ",400;";
  job += "PU0,0;PD";
  for (int i = 1; i <= 30; ++i)
    job += std::to_string(i * 100) + "," + std::to_string(i % 2 * 100) + (i < 30 ? "," : ";");
  job += "PU;SP0;";
  const std::vector<MotionMark> marks = motion_schedule(job, p);
  ASSERT_GE(marks.size(), 2u);
  for (std::size_t i = 1; i < marks.size(); ++i) {
    EXPECT_GT(marks[i].start_s, marks[i - 1].start_s) << "one mark per moment";
    EXPECT_GE(marks[i].bytes_read, marks[i - 1].bytes_read) << "read in order";
  }
  EXPECT_EQ(marks.back().bytes_read, job.size());
  p.transport.flow = FlowControl::rts_cts;  // nothing lost
  p.transport.buffer_bytes = 1 << 20;
  SimCutter device(p);
  device.receive(reinterpret_cast<const std::uint8_t*>(job.data()), job.size(), 1e9);
  ASSERT_TRUE(device.run_to_end());
  // It ends when the device's motion does, plus a first travel across the whole usable area: the
  // device may start anywhere, the model starts at the origin.
  const double across_mm = std::hypot(600, 1000);  // sim.toml: 600 x 1000 mm
  EXPECT_DOUBLE_EQ(longest_first_travel_mm(p.dialect), across_mm);
  EXPECT_NEAR(marks.back().start_s - device.report().motion_time_s,
              move_time_s(across_mm, p.kinematics.travel_speed_mm_s, p.kinematics.accel_mm_s2), 1e-9)
      << "ends when the device's motion does, after the longest first travel";
  EXPECT_EQ(marks.front().start_s, 0) << "the set-up and the first travel are read at once";
  const std::size_t long_pd = job.rfind("PD");
  const auto inside = std::count_if(marks.begin(), marks.end(), [&](const MotionMark& m) {
    return m.bytes_read > long_pd + 2 && m.bytes_read < job.rfind("PU;");
  });
  EXPECT_GE(inside, 25) << "the 30-pair PD leaves the buffer pair by pair";
}

// A host that lets time pass without reading (nothing expected) must see the clock move even
// when the device has something to say: time pacing would otherwise wait forever.
TEST(SimCutter, AReplyNobodyReadsDoesNotStopTheClock) {
  SimCutter device(sim_profile());
  const std::string ask = "IN;OI;";
  device.receive(reinterpret_cast<const std::uint8_t*>(ask.data()), ask.size(), 1);
  device.advance(device.now_s() + 0.01);
  const double before = device.now_s();
  const IoResult r = device.reply(nullptr, 0, 0.5);
  EXPECT_EQ(r.bytes, 0u);
  EXPECT_NEAR(device.now_s(), before + 0.5, 1e-9) << "the wait passed";
  std::uint8_t buf[32];
  EXPECT_GT(device.reply(buf, sizeof buf, 0).bytes, 0u) << "the reply is still there for a host that reads";
}

}  // namespace
}  // namespace popcut::drivers
