// Device checks: the test cut's and the calibration frame's patterns, and the axis correction a measured frame gives.
#include "popcut/lang/device_check.h"

#include <cmath>
#include <string>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
namespace {

constexpr double kTriangleToSquare = 2.8;
constexpr double kTickMm = 5;

double deg(double rad) { return rad * 180 / std::acos(-1.0); }
double rad(double deg) { return deg * std::acos(-1.0) / 180; }

void add_ring(Pattern& p, const std::vector<Point2>& ring, LineKind kind) {
  for (std::size_t i = 0; i < ring.size(); ++i) p.lines.push_back({kind, ring[i], ring[(i + 1) % ring.size()]});
}

[[noreturn]] void refuse(const std::string& location, const std::string& message) {
  throw Error(ErrorCode::invalid_input, "", location, message);
}

std::string mm(double v) { return format_decimal(v, 2) + " mm"; }

// A measured side against the side meant: positive and within the plausible ratio.
double side_ratio(double measured_mm, double meant_mm, const char* location, const char* which) {
  if (!std::isfinite(measured_mm) || measured_mm <= 0)
    refuse(location, format_significant(measured_mm) + " is not a length: enter the " + which + " in mm");
  const double ratio = measured_mm / meant_mm;
  if (ratio < kMinCalibrationRatio || ratio > kMaxCalibrationRatio) {
    refuse(location, mm(measured_mm) + " for the " + which + " (cut as " + mm(meant_mm) + ") is " +
                         format_decimal(ratio, 3) + " times its length, outside " +
                         format_decimal(kMinCalibrationRatio, 1) + "–" + format_decimal(kMaxCalibrationRatio, 1) +
                         ": measure that side of the frame, corner to corner, in mm");
  }
  return ratio;
}

// The skew (radians) a diagonal gives for sides lx, ly whose plotter directions have signs whose
// product is `sign`: d² = lx² + ly² + 2·sign·lx·ly·sin(skew).
double skew_from_diagonal(double d, double lx, double ly, double sign, const FrameSize& size) {
  if (!std::isfinite(d) || d <= 0)
    refuse("measured diagonal", format_significant(d) + " is not a length: enter the diagonal in mm");
  if (d <= std::abs(lx - ly) || d >= lx + ly) {
    refuse("measured diagonal", "a diagonal of " + mm(d) + " is impossible for sides of " + mm(lx) + " and " + mm(ly) +
                                    ": it must lie between " + mm(std::abs(lx - ly)) + " and " + mm(lx + ly));
  }
  const double ratio = d / size.diagonal_mm();
  if (ratio < kMinCalibrationRatio || ratio > kMaxCalibrationRatio) {
    refuse("measured diagonal", mm(d) + " for the diagonal (cut as " + mm(size.diagonal_mm()) + ") is " +
                                    format_decimal(ratio, 3) +
                                    " times its length, outside 0.9–1.1: measure it "
                                    "corner to corner, in mm");
  }
  const double s = (d * d - lx * lx - ly * ly) / (2 * sign * lx * ly);
  const double skew = std::asin(s);
  if (std::abs(deg(skew)) > kMaxSkewDeg) {
    refuse("measured diagonal", "a diagonal of " + mm(d) + " with sides of " + mm(lx) + " and " + mm(ly) +
                                    " means the corner is " + format_decimal(90 - deg(skew), 2) + "°, more than " +
                                    format_decimal(kMaxSkewDeg, 0) +
                                    "° off square: a cutter is not that far off; measure the diagonal again");
  }
  return skew;
}

// The correction matrix [[sx, -sx·tan],[0, sy/cos]] (desired device mm → commanded device mm).
struct Upper {
  double m11, m12, m22;
};

Upper matrix_of(const AxisCorrection& c) {
  const double t = std::tan(rad(c.skew_deg)), k = std::cos(rad(c.skew_deg));
  return {c.scale_x, -c.scale_x * t, c.scale_y / k};
}

AxisCorrection correction_of(const Upper& m) {
  const double skew = std::atan(-m.m12 / m.m11);
  return {m.m11, m.m22 * std::cos(skew), deg(skew)};
}

void check_correction(const AxisCorrection& c) {
  const auto check = [](double v, const char* key) {
    if (v < kMinCalibrationRatio || v > kMaxCalibrationRatio) {
      refuse("correction", std::string(key) + " would be " + format_decimal(v, 4) +
                               " with the correction already in effect, outside 0.9–1.1: was the frame cut with "
                               "another calibration than the one now in effect?");
    }
  };
  check(c.scale_x, "scale_x");
  check(c.scale_y, "scale_y");
  if (std::abs(c.skew_deg) > kMaxSkewDeg) {
    refuse("correction", "skew_deg would be " + format_decimal(c.skew_deg, 3) + "°, more than " +
                             format_decimal(kMaxSkewDeg, 0) + "° with the correction already in effect");
  }
}

}  // namespace

double TestCutShape::height_mm() const { return triangle_mm * std::sqrt(3.0) / 2; }

TestCutShape test_cut_shape(double square_mm) {
  TestCutShape s;
  s.square_mm = square_mm;
  s.triangle_mm = kTriangleToSquare * square_mm;
  // Equal gaps: a top corner of the square lies gap from the slanted side when its bottom lies
  // gap above the base: (√3 (T − s) / 2 − s) / 3.
  s.gap_mm = (std::sqrt(3.0) * (s.triangle_mm - square_mm) / 2 - square_mm) / 3;
  return s;
}

Pattern test_cut_pattern(const TestCutShape& shape, Point2 offset, double edge_mm, LineKind triangle_kind) {
  Pattern p;
  const double x0 = offset.x_mm, v0 = offset.v_mm, t = shape.triangle_mm, h = shape.height_mm();
  p.sheet = {{0, 0}, {x0 + t + edge_mm, v0 + h + edge_mm}};
  add_ring(p, {{x0, v0}, {x0 + t, v0}, {x0 + t / 2, v0 + h}}, triangle_kind);
  const double sx = x0 + (t - shape.square_mm) / 2, sv = v0 + shape.gap_mm, s = shape.square_mm;
  add_ring(p, {{sx, sv}, {sx + s, sv}, {sx + s, sv + s}, {sx, sv + s}}, LineKind::cut);
  return p;
}

double FrameSize::diagonal_mm() const { return std::hypot(width_mm, height_mm); }

Pattern calibration_frame_pattern(const FrameSize& size, double edge_mm) {
  Pattern p;
  const double e = edge_mm, w = size.width_mm, h = size.height_mm;
  p.sheet = {{0, 0}, {w + 2 * e, h + 2 * e}};
  add_ring(p, {{e, e}, {e + w, e}, {e + w, e + h}, {e, e + h}}, LineKind::cut);
  p.lines.push_back({LineKind::cut, {e, e}, {e + w, e + h}});
  p.lines.push_back({LineKind::cut, {e + w / 2, e}, {e + w / 2, e + std::min(kTickMm, h / 4)}});
  return p;
}

AxisCalibration calibrate_axes(const FrameSize& size, const FrameMeasurement& m, const PlotterFrame& frame,
                               const AxisCorrection& in_effect) {
  const double rw = side_ratio(m.width_mm, size.width_mm, "measured width", "width side (the one with the tick)");
  const double rh = side_ratio(m.height_mm, size.height_mm, "measured height", "height side");
  // Which frame side ran along which plotter axis; the diagonal ran from the sheet's corner away
  // from it along both axes, so its plotter components' signs follow the flips.
  AxisError e;
  e.side_x_mm = frame.swap_axes ? size.height_mm : size.width_mm;
  e.side_y_mm = frame.swap_axes ? size.width_mm : size.height_mm;
  e.ratio_x = frame.swap_axes ? rh : rw;
  e.ratio_y = frame.swap_axes ? rw : rh;
  const double lx = e.side_x_mm * e.ratio_x, ly = e.side_y_mm * e.ratio_y;
  e.off_x_mm = lx - e.side_x_mm;
  e.off_y_mm = ly - e.side_y_mm;
  const double sign = frame.flip_x == frame.flip_y ? 1 : -1;
  const double skew = skew_from_diagonal(m.diagonal_mm, lx, ly, sign, size);
  e.skew_deg = deg(skew);
  e.skew_mm = ly * std::sin(skew);
  // The frame came out as E·M(in effect) on the plotter's axes, E = [[kx, ky·sin],[0, ky·cos]]
  // the device's own error: the next cut is right with M(in effect)·(what was measured)⁻¹.
  const Upper old = matrix_of(in_effect);
  const double r11 = 1 / e.ratio_x, r12 = -std::tan(skew) / e.ratio_x, r22 = 1 / (e.ratio_y * std::cos(skew));
  const Upper next{old.m11 * r11, old.m11 * r12 + old.m12 * r22, old.m22 * r22};
  AxisCalibration out{e, correction_of(next)};
  check_correction(out.correction);
  return out;
}

}  // namespace popcut
