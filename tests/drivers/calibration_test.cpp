// Calibration overlays: written, read strictly, merged by load_profile; the time factor; a distorted sim corrected.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "popcut/drivers/calibration.h"
#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/motion_model.h"
#include "popcut/error.h"
#include "popcut/lang/device_check.h"

namespace popcut::drivers {
namespace {

const std::string kSim = std::string(POPCUT_SOURCE_DIR) + "/configs/devices/sim.toml";
const double kPi = std::acos(-1.0);

// A scratch POPCUT_CALIBRATION_DIR for one test, restored after it.
class OverlayDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("popcut-cal-" + std::to_string(::getpid()) + "-" +
                                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
    if (const char* old = std::getenv("POPCUT_CALIBRATION_DIR")) old_ = old;
    ::setenv("POPCUT_CALIBRATION_DIR", dir_.c_str(), 1);
  }
  void TearDown() override {
    if (old_)
      ::setenv("POPCUT_CALIBRATION_DIR", old_->c_str(), 1);
    else
      ::unsetenv("POPCUT_CALIBRATION_DIR");
    std::filesystem::remove_all(dir_);
  }
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
  std::string error_of(const std::string& overlay_text) const {
    write("sim.toml", overlay_text);
    try {
      load_profile(kSim);
    } catch (const Error& e) {
      return e.source() + ": " + e.location() + ": " + e.message();
    }
    return "loaded";
  }
  std::filesystem::path dir_;
  std::optional<std::string> old_;
};

TEST_F(OverlayDir, PathFollowsTheEnvironment) {
  EXPECT_EQ(calibration_overlay_path("/x/configs/devices/silhouette-cameo4.toml"),
            (dir_ / "silhouette-cameo4.toml").string());
  ::unsetenv("POPCUT_CALIBRATION_DIR");
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  const std::string keep_xdg = xdg ? xdg : "";
  ::setenv("XDG_CONFIG_HOME", "/cfg", 1);
  EXPECT_EQ(calibration_overlay_path("a/b.toml"), "/cfg/popcut/calibration/b.toml");
  ::unsetenv("XDG_CONFIG_HOME");
  ::setenv("HOME", std::getenv("HOME") ? std::getenv("HOME") : "/home/u", 1);
  EXPECT_EQ(calibration_overlay_path("b.toml"),
            std::string(std::getenv("HOME")) + "/.config/popcut/calibration/b.toml");
  if (xdg) ::setenv("XDG_CONFIG_HOME", keep_xdg.c_str(), 1);
}

TEST_F(OverlayDir, WrittenOverlayReadsBackAndEveryLoadUsesIt) {
  const DeviceProfile plain = load_profile(kSim);
  EXPECT_TRUE(plain.calibration.overlay.empty()) << "no overlay: the profile's own values";
  CalibrationOverlay o;
  o.profile = kSim;
  o.measured_at = "2026-01-02T03:04:05Z";
  o.scale_x = 0.996;
  o.scale_y = 1.002;
  o.skew_deg = 0.12;
  o.time_factor = 1.15;
  o.timed_by = "status";
  save_calibration_overlay((dir_ / "sim.toml").string(), o);
  const CalibrationOverlay back = parse_calibration_overlay(format_calibration_overlay(o), "x.toml");
  EXPECT_DOUBLE_EQ(*back.scale_x, 0.996);
  EXPECT_DOUBLE_EQ(*back.skew_deg, 0.12);
  EXPECT_DOUBLE_EQ(*back.time_factor, 1.15);
  EXPECT_EQ(back.measured_at, o.measured_at);
  const DeviceProfile p = load_profile(kSim);
  EXPECT_EQ(p.calibration.overlay, (dir_ / "sim.toml").string());
  EXPECT_EQ(p.calibration.measured_at, o.measured_at);
  EXPECT_DOUBLE_EQ(p.dialect.units_per_mm_x, 40 * 0.996);
  EXPECT_DOUBLE_EQ(p.dialect.units_per_mm_y, 40 * 1.002);
  EXPECT_DOUBLE_EQ(p.dialect.skew_deg, 0.12);
  EXPECT_DOUBLE_EQ(p.calibration.time_factor, 1.15);
  const nlohmann::json j = calibration_json(p.calibration);
  EXPECT_TRUE(j["calibrated"].get<bool>());
  EXPECT_FALSE(calibration_json(plain.calibration)["calibrated"].get<bool>());
  EXPECT_TRUE(load_profile_with_overlay(kSim, "").calibration.overlay.empty()) << "asked for none";
}

TEST_F(OverlayDir, MalformedOverlayIsAnErrorNamingItsFileAndKey) {
  const std::string file = (dir_ / "sim.toml").string();
  EXPECT_EQ(error_of("[device]\nscale_x = 1.5\n"), file + ": [device] scale_x: 1.5 is out of range 0.9 to 1.1");
  EXPECT_EQ(error_of("[device]\nskew_deg = \"a\"\n"), file + ": [device] skew_deg: expected a number");
  EXPECT_EQ(error_of("[device]\nunits_per_mm = 41\n"), file + ": [device] units_per_mm: unknown key");
  EXPECT_EQ(error_of("[kinematics]\ntime_factor = 9\n"),
            file + ": [kinematics] time_factor: 9 is out of range 0.5 to 5");
  EXPECT_EQ(error_of("[tool.cut]\nforce_g = 9\n"),
            file + ": [tool]: unknown section in a calibration overlay (expected calibration, device, kinematics)");
  EXPECT_EQ(error_of("[calibration]\nreal_s = -1\n"), file + ": [calibration] real_s: -1 is out of range 0 to 1e+07");
  EXPECT_NE(error_of("[device\n").find(file + ": line 1"), std::string::npos) << "syntax errors name line and column";
  EXPECT_EQ(error_of("[device]\nscale_x = 1.01\n"), "loaded");
}

TEST(ProfileCalibrationKeys, SkewAndTimeFactorAreRangeChecked) {
  const auto error_of = [](const std::string& extra) -> std::string {
    try {
      parse_profile("[device]\nname = \"x\"\n" + extra, "p.toml");
    } catch (const Error& e) {
      return e.location() + ": " + e.message();
    }
    return "ok";
  };
  EXPECT_EQ(error_of("skew_deg = 6\n"), "[device] skew_deg: 6 is out of range -5 to 5");
  EXPECT_EQ(error_of("skew_deg = -0.3\n"), "ok");
  EXPECT_EQ(error_of("[kinematics]\ntime_factor = 0.2\n"), "[kinematics] time_factor: 0.2 is out of range 0.5 to 5");
  const DeviceProfile p =
      parse_profile("[device]\nname = \"x\"\nskew_deg = -0.3\n[kinematics]\ntime_factor = 1.3\n", "p");
  EXPECT_DOUBLE_EQ(p.dialect.skew_deg, -0.3);
  EXPECT_DOUBLE_EQ(p.calibration.time_factor, 1.3);
  EXPECT_TRUE(p.calibration.overlay.empty());
}

TEST(MotionSchedule, TimeFactorScalesEveryMark) {
  DeviceProfile p = parse_profile("[device]\nname = \"x\"\n", "p");
  const std::string job = "IN;SP1;VS10;PU;PA400,400;PD;PA4400,400,4400,4400;PU;SP0;";
  const std::vector<MotionMark> plain = motion_schedule(job, p);
  p.calibration.time_factor = 1.25;
  const std::vector<MotionMark> slow = motion_schedule(job, p);
  ASSERT_EQ(plain.size(), slow.size());
  for (std::size_t i = 0; i < plain.size(); ++i) {
    EXPECT_NEAR(slow[i].start_s, plain[i].start_s * 1.25, 1e-9);
    EXPECT_EQ(slow[i].bytes_read, plain[i].bytes_read);
  }
  EXPECT_GT(modelled_motion_s(job, p), 200.0 / 100) << "two 100 mm cuts at 10 cm/s take over 2 s";
  EXPECT_LT(modelled_motion_s(job, p), plain.back().start_s) << "no first-travel allowance, no factor";
}

// The device of the round trip: its x runs 0.7 % long, its y 0.4 % short, its y axis leans 0.35°;
// `units_per_mm` is its nominal resolution.
std::array<double, 2> on_paper(const std::array<std::int64_t, 2>& pu, double units_per_mm) {
  const double x = static_cast<double>(pu[0]) / units_per_mm, y = static_cast<double>(pu[1]) / units_per_mm;
  const double g = 0.35 * kPi / 180;
  return {x * 1.007 + y * 0.996 * std::sin(g), y * 0.996 * std::cos(g)};
}

using Pu = std::array<std::int64_t, 2>;

// The frame's corners as the simulator cut them: the extreme points of everything cut (a
// parallelogram with its diagonal and tick), named by where they lie on the plotter's axes.
struct Corners {
  Pu lo_lo{}, hi_hi{}, hi_lo{}, lo_hi{};  // (x, y) smallest/largest
};

Corners corners_of(const std::vector<SimStroke>& strokes) {
  Corners c;
  bool first = true;
  const auto sum = [](const Pu& a) { return a[0] + a[1]; };
  const auto diff = [](const Pu& a) { return a[0] - a[1]; };
  for (const SimStroke& s : strokes) {
    for (const Pu& pt : s.points_pu) {
      if (first || sum(pt) < sum(c.lo_lo)) c.lo_lo = pt;
      if (first || sum(pt) > sum(c.hi_hi)) c.hi_hi = pt;
      if (first || diff(pt) > diff(c.hi_lo)) c.hi_lo = pt;
      if (first || diff(pt) < diff(c.lo_hi)) c.lo_hi = pt;
      first = false;
    }
  }
  return c;
}

// Whether some stroke runs straight from a to b (either way).
bool joined(const std::vector<SimStroke>& strokes, const Pu& a, const Pu& b) {
  for (const SimStroke& s : strokes) {
    for (std::size_t i = 1; i < s.points_pu.size(); ++i) {
      const Pu& p = s.points_pu[i - 1];
      const Pu& q = s.points_pu[i];
      if ((p == a && q == b) || (p == b && q == a)) return true;
    }
  }
  return false;
}

double distance_on_paper(const Pu& a, const Pu& b, double units_per_mm) {
  const auto u = on_paper(a, units_per_mm), v = on_paper(b, units_per_mm);
  return std::hypot(u[0] - v[0], u[1] - v[1]);
}

// Cuts the frame on the simulator and measures it on paper as a user would: the side the tick
// stands on is the width, the diagonal is the one that was cut. Also the corner's angle.
FrameMeasurement cut_and_measure(const DeviceProfile& p, double* corner_deg) {
  DeviceProfile q = p;
  q.plan.kinds[index_of(PlanKind::outline)].mode = ToolMode::skip;
  const DevicePlan job = plan_for_device(calibration_frame_pattern({100, 150}, 1), q, q.source);
  CutSession session("sim", q);
  const CutResult r = session.run(job.encoded, planned_paths(job.plan, q.dialect, 1), {});
  EXPECT_TRUE(r.sim && r.sim->cut_exactly_the_plan());
  const std::vector<SimStroke>& strokes = session.simulator()->strokes();
  const Corners c = corners_of(strokes);
  const double upm = q.dialect.units_per_mm_x / q.calibration.scale_x;  // the device's own, uncalibrated
  const auto paper = [&](const Pu& a, const Pu& b) { return distance_on_paper(a, b, upm); };
  // The tick: a stroke end at a side's midpoint (within a unit of rounding).
  const auto mid = [](const Pu& a, const Pu& b) { return Pu{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2}; };
  const auto near = [](const Pu& a, const Pu& b) { return std::abs(a[0] - b[0]) <= 1 && std::abs(a[1] - b[1]) <= 1; };
  const auto tick_on = [&](const Pu& a, const Pu& b) {
    for (const SimStroke& s : strokes) {
      for (const Pu& e : {s.points_pu.front(), s.points_pu.back()}) {
        if (near(e, mid(a, b))) return true;
      }
    }
    return false;
  };
  const bool width_along_x = tick_on(c.lo_lo, c.hi_lo) || tick_on(c.lo_hi, c.hi_hi);
  const double along_x = paper(c.lo_lo, c.hi_lo), along_y = paper(c.lo_lo, c.lo_hi);
  const bool main_diagonal = joined(strokes, c.lo_lo, c.hi_hi);
  EXPECT_NE(main_diagonal, joined(strokes, c.hi_lo, c.lo_hi)) << "one diagonal is cut";
  const auto a = on_paper(c.lo_lo, upm), b = on_paper(c.hi_lo, upm), d = on_paper(c.lo_hi, upm);
  const double ux = b[0] - a[0], uy = b[1] - a[1], vx = d[0] - a[0], vy = d[1] - a[1];
  *corner_deg = std::acos((ux * vx + uy * vy) / (std::hypot(ux, uy) * std::hypot(vx, vy))) * 180 / kPi;
  return {width_along_x ? along_x : along_y, width_along_x ? along_y : along_x,
          main_diagonal ? paper(c.lo_lo, c.hi_hi) : paper(c.hi_lo, c.lo_hi)};
}

TEST_F(OverlayDir, DistortedSimulatorIsCorrectedByItsOwnMeasurement) {
  // sim: HP-GL's frame; the Cameo 4: GP-GL, turned a quarter (swap_axes, flip_x, sheet_at_origin).
  for (const std::string name : {"sim", "silhouette-cameo4"}) {
    const std::string profile = std::string(POPCUT_SOURCE_DIR) + "/configs/devices/" + name + ".toml";
    double corner = 0;
    const DeviceProfile before = load_profile(profile);
    const FrameMeasurement m = cut_and_measure(before, &corner);
    EXPECT_NEAR(corner, 90 - 0.35, 0.03) << name;
    EXPECT_GT(std::abs(m.width_mm - 100) + std::abs(m.height_mm - 150), 0.5) << name << ": visibly off before";
    const DeviceCalibration& now = before.calibration;
    const AxisCalibration cal = calibrate_axes({100, 150}, m, before.dialect, {now.scale_x, now.scale_y, now.skew_deg});
    CalibrationOverlay o;
    o.scale_x = cal.correction.scale_x;
    o.scale_y = cal.correction.scale_y;
    o.skew_deg = cal.correction.skew_deg;
    save_calibration_overlay(calibration_overlay_path(profile), o);
    // The next job on the profile picks the overlay up and lands right on paper (a 0.05 mm GP-GL
    // step rounds coarser than HP-GL's 0.025 mm).
    const DeviceProfile after = load_profile(profile);
    ASSERT_FALSE(after.calibration.overlay.empty()) << name;
    const FrameMeasurement fixed = cut_and_measure(after, &corner);
    EXPECT_NEAR(fixed.width_mm, 100, 0.06) << name;
    EXPECT_NEAR(fixed.height_mm, 150, 0.06) << name;
    EXPECT_NEAR(fixed.diagonal_mm, std::hypot(100.0, 150.0), 0.06) << name;
    EXPECT_NEAR(corner, 90, 0.03) << name;
  }
}

}  // namespace
}  // namespace popcut::drivers
