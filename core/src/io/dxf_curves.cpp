// DXF's curves as chords within a tolerance: bulges, elliptic arcs and NURBS (de Boor in homogeneous form).
#include "io/dxf_curves.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace popcut::dxf {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxStepsPerCurve = 1'000'000;

// Chords for a sweep of `sweep` radians on a circle of `radius` within `tolerance`.
int arc_steps(double radius, double sweep, double tolerance) {
  const double step = radius > tolerance ? 2 * std::acos(1 - tolerance / radius) : kPi / 2;
  const double n = std::ceil(std::abs(sweep) / step);
  return static_cast<int>(std::clamp(n, 1.0, static_cast<double>(kMaxStepsPerCurve)));
}

double distance_to_chord(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, len = std::hypot(dx, dv);
  if (len == 0) return std::hypot(p.x_mm - a.x_mm, p.v_mm - a.v_mm);
  return std::abs((p.x_mm - a.x_mm) * dv - (p.v_mm - a.v_mm) * dx) / len;
}

struct Homogeneous {
  double x = 0, y = 0, w = 0;
};

class Nurbs {
 public:
  Nurbs(int degree, const std::vector<double>& knots, const std::vector<Point2>& control,
        const std::vector<double>& weights)
      : p_(degree), knots_(knots) {
    for (std::size_t i = 0; i < control.size(); ++i) {
      const double w = weights.empty() ? 1 : weights[i];
      ctrl_.push_back({control[i].x_mm * w, control[i].v_mm * w, w});
    }
  }

  // de Boor's algorithm at u in [knots[p], knots[n]]; the last span also takes its own end.
  Point2 at(double u) const {
    const std::size_t n = ctrl_.size(), p = static_cast<std::size_t>(p_);
    std::size_t k = p;
    while (k + 1 < n && knots_[k + 1] <= u) ++k;
    std::vector<Homogeneous> d(ctrl_.begin() + static_cast<std::ptrdiff_t>(k - p),
                               ctrl_.begin() + static_cast<std::ptrdiff_t>(k + 1));
    for (std::size_t r = 1; r <= p; ++r)
      for (std::size_t j = p; j >= r; --j) {
        const double lo = knots_[j + k - p], hi = knots_[j + 1 + k - r];
        const double a = hi > lo ? (u - lo) / (hi - lo) : 0;
        d[j] = {(1 - a) * d[j - 1].x + a * d[j].x, (1 - a) * d[j - 1].y + a * d[j].y,
                (1 - a) * d[j - 1].w + a * d[j].w};
      }
    return {d[p].x / d[p].w, d[p].y / d[p].w};
  }

  // Halves [u0, u1] until its quarter, middle and three-quarter points lie within tolerance of
  // the chord, at least three times, so an S-bend whose middle sits on the chord, or a bend
  // off-centre in its interval, is still followed.
  void flatten(double u0, Point2 a, double u1, Point2 b, double tolerance, int depth, std::vector<Point2>& out) const {
    const double um = (u0 + u1) / 2;
    const Point2 m = at(um);
    const double off = std::max({distance_to_chord(at(u0 + (u1 - u0) / 4), a, b), distance_to_chord(m, a, b),
                                 distance_to_chord(at(u1 - (u1 - u0) / 4), a, b)});
    if (depth >= 3 && (depth >= 24 || off <= tolerance)) {
      out.push_back(b);
      return;
    }
    if (out.size() > static_cast<std::size_t>(kMaxStepsPerCurve)) throw std::length_error("too many points");
    flatten(u0, a, um, m, tolerance, depth + 1, out);
    flatten(um, m, u1, b, tolerance, depth + 1, out);
  }

 private:
  int p_;
  const std::vector<double>& knots_;
  std::vector<Homogeneous> ctrl_;
};

void check_spline(int degree, const std::vector<double>& knots, const std::vector<Point2>& control,
                  const std::vector<double>& weights) {
  if (degree < 1 || degree > 11) throw std::invalid_argument("degree " + std::to_string(degree) + ": expected 1 to 11");
  if (control.size() <= static_cast<std::size_t>(degree))
    throw std::invalid_argument(std::to_string(control.size()) + " control points: a degree " + std::to_string(degree) +
                                " spline needs at least " + std::to_string(degree + 1));
  if (knots.size() != control.size() + static_cast<std::size_t>(degree) + 1)
    throw std::invalid_argument(std::to_string(knots.size()) + " knots: expected control points + degree + 1 = " +
                                std::to_string(control.size() + static_cast<std::size_t>(degree) + 1));
  for (std::size_t i = 1; i < knots.size(); ++i)
    if (knots[i] < knots[i - 1])
      throw std::invalid_argument("knot " + std::to_string(i) + " decreases: knots must not decrease");
  if (!weights.empty() && weights.size() != control.size())
    throw std::invalid_argument(std::to_string(weights.size()) + " weights for " + std::to_string(control.size()) +
                                " control points");
  for (const double w : weights)
    if (!(w > 0)) throw std::invalid_argument("a weight is not positive");
  if (!(knots[control.size()] > knots[static_cast<std::size_t>(degree)]))
    throw std::invalid_argument("the knots leave the curve no length (an empty domain)");
}

}  // namespace

std::vector<Point2> bulge_points(Point2 a, Point2 b, double bulge, double tolerance) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, chord = std::hypot(dx, dv);
  if (bulge == 0 || chord == 0) return {b};
  const double sweep = 4 * std::atan(bulge);  // signed: + counter-clockwise
  const double radius = chord / (2 * std::abs(std::sin(sweep / 2)));
  // From the chord's middle to the centre, along the chord's left normal.
  const double h = chord / 2 * (1 - bulge * bulge) / (2 * bulge);
  const Point2 c{(a.x_mm + b.x_mm) / 2 - dv / chord * h, (a.v_mm + b.v_mm) / 2 + dx / chord * h};
  const double start = std::atan2(a.v_mm - c.v_mm, a.x_mm - c.x_mm);
  const int n = arc_steps(radius, sweep, tolerance);
  std::vector<Point2> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 1; i < n; ++i) {
    const double t = start + sweep * i / n;
    out.push_back({c.x_mm + radius * std::cos(t), c.v_mm + radius * std::sin(t)});
  }
  out.push_back(b);
  return out;
}

std::vector<Point2> ellipse_points(Point2 c, Point2 major, double ratio, double t0, double t1, bool clockwise,
                                   double tolerance) {
  const double s = clockwise ? -1 : 1;
  const Point2 minor{-major.v_mm * ratio * s, major.x_mm * ratio * s};
  const int n = arc_steps(std::hypot(major.x_mm, major.v_mm), t1 - t0, tolerance);
  std::vector<Point2> out;
  out.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    const double t = t0 + (t1 - t0) * i / n;
    out.push_back({c.x_mm + major.x_mm * std::cos(t) + minor.x_mm * std::sin(t),
                   c.v_mm + major.v_mm * std::cos(t) + minor.v_mm * std::sin(t)});
  }
  return out;
}

std::vector<Point2> spline_points(int degree, const std::vector<double>& knots, const std::vector<Point2>& control,
                                  const std::vector<double>& weights, double tolerance) {
  check_spline(degree, knots, control, weights);
  const Nurbs curve(degree, knots, control, weights);
  const std::size_t p = static_cast<std::size_t>(degree);
  std::vector<Point2> out{curve.at(knots[p])};
  // Span by span, so a knot where the curve turns sharply (a repeated knot) is always a point.
  for (std::size_t k = p; k < control.size(); ++k) {
    const double u0 = knots[k], u1 = knots[k + 1];
    if (u1 <= u0) continue;
    curve.flatten(u0, out.back(), u1, curve.at(u1), tolerance, 0, out);
  }
  return out;
}

}  // namespace popcut::dxf
