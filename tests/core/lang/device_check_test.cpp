// Device checks: test-cut and frame patterns, the plotter frame's skew, and calibration maths against known
// distortions.
#include <gtest/gtest.h>

#include <cmath>

#include "popcut/error.h"
#include "popcut/lang/device_check.h"
#include "popcut/lang/plotter_frame.h"

namespace popcut {
namespace {

const double kPi = std::acos(-1.0);

// The turns a profile may make (swap_axes, flip_x, flip_y): none, a quarter each way, a half.
struct Turn {
  bool swap, fx, fy;
};
constexpr Turn kTurns[] = {{false, false, false}, {true, true, false}, {true, false, true}, {false, true, true}};

// A device whose axes are off: along its x it moves kx mm per mm asked, along y ky, and its y axis
// leans toward +x by skew_deg. Maps a commanded displacement (plotter mm) to where the knife goes.
struct Distortion {
  double kx = 1, ky = 1, skew_deg = 0;
  std::array<double, 2> apply(double x, double y) const {
    const double g = skew_deg * kPi / 180;
    return {x * kx + y * ky * std::sin(g), y * ky * std::cos(g)};
  }
};

PlotterFrame frame_of(bool swap, bool fx, bool fy, const AxisCorrection& c = {}) {
  PlotterFrame f;
  f.swap_axes = swap;
  f.flip_x = fx;
  f.flip_y = fy;
  f.units_per_mm_x = 40 * c.scale_x;
  f.units_per_mm_y = 40 * c.scale_y;
  f.skew_deg = c.skew_deg;
  f.area_max_x_pu = 40 * 600;
  f.area_max_y_pu = 40 * 600;
  return f;
}

// Where a pattern point lands on the distorted device, in mm, for a frame whose nominal units are 40/mm.
std::array<double, 2> landed(Point2 p, const Rect& sheet, const PlotterFrame& f, const Distortion& d) {
  const Placement pl = place_sheet(sheet, f);
  const auto q = to_plotter(p, sheet, pl, f);
  return d.apply(static_cast<double>(q[0]) / 40, static_cast<double>(q[1]) / 40);
}

double dist(std::array<double, 2> a, std::array<double, 2> b) { return std::hypot(a[0] - b[0], a[1] - b[1]); }

// The frame's corners as the device cuts them, measured as a user would: the three lengths.
FrameMeasurement measure(const FrameSize& size, const PlotterFrame& f, const Distortion& d) {
  const Rect sheet{{0, 0}, {size.width_mm, size.height_mm}};
  const auto c00 = landed({0, 0}, sheet, f, d), c10 = landed({size.width_mm, 0}, sheet, f, d);
  const auto c01 = landed({0, size.height_mm}, sheet, f, d), c11 = landed({size.width_mm, size.height_mm}, sheet, f, d);
  return {dist(c00, c10), dist(c00, c01), dist(c00, c11)};
}

double corner_deg(const FrameSize& size, const PlotterFrame& f, const Distortion& d) {
  const Rect sheet{{0, 0}, {size.width_mm, size.height_mm}};
  const auto o = landed({0, 0}, sheet, f, d), a = landed({size.width_mm, 0}, sheet, f, d),
             b = landed({0, size.height_mm}, sheet, f, d);
  const double ax = a[0] - o[0], ay = a[1] - o[1], bx = b[0] - o[0], by = b[1] - o[1];
  return std::acos((ax * bx + ay * by) / (std::hypot(ax, ay) * std::hypot(bx, by))) * 180 / kPi;
}

PlotterFrame corrected(const PlotterFrame& base, const AxisCorrection& c) {
  return frame_of(base.swap_axes, base.flip_x, base.flip_y, c);
}

TEST(TestCutShape, SquareSitsInTheTriangleWithEqualGaps) {
  const TestCutShape s = test_cut_shape(10);
  EXPECT_DOUBLE_EQ(s.triangle_mm, 28);
  EXPECT_NEAR(s.gap_mm, 1.8637, 1e-3);
  const Pattern p = test_cut_pattern(s, {5, 7}, 1, LineKind::valley);
  ASSERT_EQ(p.lines.size(), 7u);
  EXPECT_EQ(p.sheet.min, (Point2{0, 0}));
  EXPECT_NEAR(p.sheet.max.x_mm, 5 + 28 + 1, 1e-9);
  EXPECT_NEAR(p.sheet.max.v_mm, 7 + s.height_mm() + 1, 1e-9);
  // Triangle sides: valley lines of 28 mm; square: cut lines of 10 mm, every corner `gap` from
  // the nearest triangle side.
  int valley = 0, cut = 0;
  for (const Segment& l : p.lines) {
    const double len = std::hypot(l.b.x_mm - l.a.x_mm, l.b.v_mm - l.a.v_mm);
    if (l.kind == LineKind::valley) {
      ++valley;
      EXPECT_NEAR(len, 28, 1e-9);
    }
    if (l.kind == LineKind::cut) {
      ++cut;
      EXPECT_NEAR(len, 10, 1e-9);
    }
  }
  EXPECT_EQ(valley, 3);
  EXPECT_EQ(cut, 4);
  const auto distance_to_side = [&](Point2 q, const Segment& l) {
    const double ex = l.b.x_mm - l.a.x_mm, ev = l.b.v_mm - l.a.v_mm;
    return std::abs(ex * (q.v_mm - l.a.v_mm) - ev * (q.x_mm - l.a.x_mm)) / std::hypot(ex, ev);
  };
  double nearest = 1e9;
  for (const Segment& sq : p.lines) {
    if (sq.kind != LineKind::cut) continue;
    for (const Segment& tri : p.lines) {
      if (tri.kind == LineKind::valley) nearest = std::min(nearest, distance_to_side(sq.a, tri));
    }
  }
  EXPECT_NEAR(nearest, s.gap_mm, 1e-9) << "no square corner nearer a side than the gap";
}

TEST(CalibrationFrame, RectangleDiagonalAndTick) {
  const Pattern p = calibration_frame_pattern({100, 150}, 2);
  ASSERT_EQ(p.lines.size(), 6u);
  EXPECT_EQ(p.sheet.max, (Point2{104, 154}));
  EXPECT_EQ(p.lines[4].a, (Point2{2, 2}));
  EXPECT_EQ(p.lines[4].b, (Point2{102, 152})) << "the diagonal from the min corner to the max corner";
  EXPECT_EQ(p.lines[5].a, (Point2{52, 2})) << "the tick on the width side";
  EXPECT_NEAR(FrameSize{}.diagonal_mm(), 180.2776, 1e-4);
}

TEST(PlotterFrameSkew, ZeroSkewLeavesEveryPointAsItWas) {
  for (const auto& [swap, fx, fy] : kTurns) {
    const PlotterFrame f = frame_of(swap, fx, fy);
    const Rect sheet{{-3, 1}, {97, 151}};
    const Placement pl = place_sheet(sheet, f);
    const auto q = to_plotter({10.01, 20.03}, sheet, pl, f);
    // Without skew: round(local mm × 40) from the origin corner, flipped as asked.
    const double lx = swap ? 19.03 : 13.01, ly = swap ? 13.01 : 19.03;
    EXPECT_EQ(q[0], fx ? 40 * 600 - std::llround(lx * 40) : std::llround(lx * 40));
    EXPECT_EQ(q[1], fy ? 40 * 600 - std::llround(ly * 40) : std::llround(ly * 40));
  }
}

TEST(PlotterFrameSkew, ShearStaysInsideTheAreaAndRefusesWhatDoesNotFit) {
  // A lean toward the origin corner moves the sheet in; it never leaves the area.
  for (double skew : {-2.0, 2.0}) {
    for (const auto& [swap, fx, fy] : kTurns) {
      PlotterFrame f = frame_of(swap, fx, fy, {1, 1, skew});
      const Rect sheet{{0, 0}, {100, 150}};
      StrokePlan plan;
      plan.sheet = sheet;
      plan.strokes = {{PlanKind::cut, {{0, 0}, {100, 0}, {100, 150}, {0, 150}, {0, 0}}}};
      EXPECT_NO_THROW(plan_in_plotter_units(plan, f)) << skew << " " << swap << fx << fy;
    }
  }
  PlotterFrame f = frame_of(false, false, false, {1, 1, 2});
  f.area_max_x_pu = 40 * 102;  // 100 mm wide plus 150·tan 2° = 5.2 mm does not fit 102 mm
  EXPECT_THROW(place_sheet({{0, 0}, {100, 150}}, f), Error);
  f.skew_deg = 0;
  EXPECT_NO_THROW(place_sheet({{0, 0}, {100, 150}}, f));
}

TEST(CalibrateAxes, KnownDistortionGivesItsInverse) {
  const Distortion d{1.01, 0.995, 0.3};
  const FrameSize size;
  const double lx = 100 * d.kx, ly = 150 * d.ky, g = d.skew_deg * kPi / 180;
  const FrameMeasurement m{lx, ly, std::sqrt(lx * lx + ly * ly + 2 * lx * ly * std::sin(g))};
  const AxisCalibration c = calibrate_axes(size, m, frame_of(false, false, false), {});
  EXPECT_NEAR(c.correction.scale_x, 1 / 1.01, 1e-12);
  EXPECT_NEAR(c.correction.scale_y, 1 / 0.995, 1e-12);
  EXPECT_NEAR(c.correction.skew_deg, 0.3, 1e-9);
  EXPECT_NEAR(c.error.off_x_mm, 1.0, 1e-9);
  EXPECT_NEAR(c.error.off_y_mm, -0.75, 1e-9);
  EXPECT_NEAR(c.error.skew_mm, ly * std::sin(g), 1e-9);
  // swap_axes: the width side ran along the plotter's y.
  const AxisCalibration s = calibrate_axes(size, m, frame_of(true, true, false), {});
  EXPECT_NEAR(s.correction.scale_x, 150 / ly, 1e-12);
  EXPECT_NEAR(s.correction.scale_y, 100 / lx, 1e-12);
  EXPECT_NEAR(s.correction.skew_deg, -c.correction.skew_deg, 0.01) << "one flip: the diagonal ran the other way";
}

TEST(CalibrateAxes, RoundTripEveryTurnLandsWithinRounding) {
  const FrameSize size;
  for (const Distortion& d : {Distortion{1.008, 0.993, 0.4}, Distortion{0.97, 1.02, -0.8}}) {
    for (const auto& [swap, fx, fy] : kTurns) {
      const PlotterFrame plain = frame_of(swap, fx, fy);
      const FrameMeasurement before = measure(size, plain, d);
      const AxisCalibration c = calibrate_axes(size, before, plain, {});
      const PlotterFrame fixed = corrected(plain, c.correction);
      const FrameMeasurement after = measure(size, fixed, d);
      const std::string what = std::to_string(swap) + std::to_string(fx) + std::to_string(fy);
      EXPECT_NEAR(after.width_mm, 100, 0.03) << what;
      EXPECT_NEAR(after.height_mm, 150, 0.03) << what;
      EXPECT_NEAR(after.diagonal_mm, size.diagonal_mm(), 0.03) << what;
      EXPECT_NEAR(corner_deg(size, fixed, d), 90, 0.02) << what;
      EXPECT_GT(std::abs(corner_deg(size, plain, d) - 90), 0.3) << what << ": the distortion was visible before";
      // Calibrating again with the correction in effect changes it by no more than the rounding.
      const AxisCalibration again = calibrate_axes(size, after, fixed, c.correction);
      EXPECT_NEAR(again.correction.scale_x, c.correction.scale_x, 4e-4) << what;
      EXPECT_NEAR(again.correction.skew_deg, c.correction.skew_deg, 0.02) << what;
    }
  }
}

TEST(CalibrateAxes, ComposesWithTheCorrectionInEffect) {
  // The frame was cut with a wrong correction in effect; what it measures corrects both.
  const Distortion d{1.01, 0.99, 0.5};
  const PlotterFrame plain = frame_of(false, false, false);
  const AxisCorrection wrong{1.02, 0.98, -0.4};
  const FrameMeasurement m = measure({}, corrected(plain, wrong), d);
  const AxisCalibration c = calibrate_axes({}, m, plain, wrong);
  EXPECT_NEAR(c.correction.scale_x, 1 / 1.01, 2e-4);
  EXPECT_NEAR(c.correction.scale_y, 1 / 0.99, 2e-4);
  EXPECT_NEAR(c.correction.skew_deg, 0.5, 0.01);
}

TEST(CalibrateAxes, RefusesAbsurdMeasurementsPrecisely) {
  const PlotterFrame f = frame_of(false, false, false);
  const auto message = [&](FrameMeasurement m, const AxisCorrection& in_effect = {}) -> std::string {
    try {
      calibrate_axes({}, m, f, in_effect);
    } catch (const Error& e) {
      return e.location() + ": " + e.message();
    }
    return "accepted";
  };
  EXPECT_EQ(message({-100, 150, 180}).rfind("measured width: -100 is not a length", 0), 0u);
  EXPECT_NE(message({100, 170, 180}).find("measured height: 170 mm for the height side (cut as 150 mm) is 1.133 times"),
            std::string::npos);
  EXPECT_NE(message({100, 150, 300})
                .find("a diagonal of 300 mm is impossible for sides of 100 mm and 150 mm: it "
                      "must lie between 50 mm and 250 mm"),
            std::string::npos);
  EXPECT_NE(message({100, 150, 170}).find("off square"), std::string::npos);
  EXPECT_EQ(message({100, 150, std::nan("")}).rfind("measured diagonal", 0), 0u);
  EXPECT_NE(message({93, 150, 176.5}, {1.05, 1, 0}).find("scale_x would be 1.129"), std::string::npos)
      << "a side within range whose composed correction is not";
  EXPECT_EQ(message({100.2, 149.9, 180.3}), "accepted");
}

}  // namespace
}  // namespace popcut
