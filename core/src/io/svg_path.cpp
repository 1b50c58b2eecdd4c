// SVG path data, transforms and curve flattening (SVG 1.1 §8.3 grammar, §F.6 arc conversion).
#include "io/svg_path.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace popcut::svg {
namespace {

constexpr double kPi = std::numbers::pi;

// A cursor over path data or a transform list: numbers in SVG's compact forms ("1.5.5", "-1-2").
class Scanner {
 public:
  explicit Scanner(const std::string& text) : s_(text) {}
  void skip_separators() {
    while (i_ < s_.size() && (std::isspace(static_cast<unsigned char>(s_[i_])) || s_[i_] == ',')) ++i_;
  }
  bool done() {
    skip_separators();
    return i_ >= s_.size();
  }
  char peek() { return done() ? '\0' : s_[i_]; }
  char take() { return s_[i_++]; }
  bool at_number() {
    const char c = peek();
    return c == '-' || c == '+' || c == '.' || std::isdigit(static_cast<unsigned char>(c));
  }
  double number() {
    skip_separators();
    std::size_t j = i_;
    if (j < s_.size() && (s_[j] == '+' || s_[j] == '-')) ++j;
    bool dot = false;
    while (j < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[j])) || (s_[j] == '.' && !dot)))
      dot |= s_[j++] == '.';
    if (j < s_.size() && (s_[j] == 'e' || s_[j] == 'E')) {
      std::size_t k = j + 1;
      if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) ++k;
      if (k < s_.size() && std::isdigit(static_cast<unsigned char>(s_[k]))) {
        j = k;
        while (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) ++j;
      }
    }
    const std::size_t start = s_[i_] == '+' ? i_ + 1 : i_;
    double value = 0;
    const auto r = std::from_chars(s_.data() + start, s_.data() + j, value);
    if (r.ec != std::errc() || r.ptr != s_.data() + j || j == i_)
      throw std::invalid_argument("expected a number at character " + std::to_string(i_ + 1) + ", got \"" +
                                  s_.substr(i_, 12) + "\"");
    if (!std::isfinite(value))
      throw std::invalid_argument("number out of range at character " + std::to_string(i_ + 1));
    i_ = j;
    return value;
  }
  bool flag() {  // arc flags may be written without separators: "a1 1 0 00 1 1"
    skip_separators();
    if (i_ < s_.size() && (s_[i_] == '0' || s_[i_] == '1')) return s_[i_++] == '1';
    throw std::invalid_argument("expected an arc flag 0 or 1 at character " + std::to_string(i_ + 1));
  }
  std::size_t position() const { return i_ + 1; }

 private:
  const std::string& s_;
  std::size_t i_ = 0;
};

Point2 lerp(Point2 a, Point2 b, double t) { return {a.x_mm + (b.x_mm - a.x_mm) * t, a.v_mm + (b.v_mm - a.v_mm) * t}; }

// Chord count for a cubic so the flattening error stays within tolerance (the second-difference
// bound: error ≤ n⁻² · ¾ · max |P0 − 2P1 + P2|, |P1 − 2P2 + P3|).
int cubic_steps(const std::array<Point2, 4>& p, double tolerance) {
  const auto dd = [&](std::size_t i) {
    return std::hypot(p[i].x_mm - 2 * p[i + 1].x_mm + p[i + 2].x_mm, p[i].v_mm - 2 * p[i + 1].v_mm + p[i + 2].v_mm);
  };
  const double m = std::max(dd(0), dd(1));
  return std::clamp(static_cast<int>(std::ceil(std::sqrt(0.75 * m / tolerance))), 1, 100000);
}

}  // namespace

std::vector<Point2> cubic_points(const std::array<Point2, 4>& p, double tolerance) {
  const int n = cubic_steps(p, tolerance);
  std::vector<Point2> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 1; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    const Point2 a = lerp(p[0], p[1], t), b = lerp(p[1], p[2], t), c = lerp(p[2], p[3], t);
    out.push_back(lerp(lerp(a, b, t), lerp(b, c, t), t));
  }
  return out;
}

std::vector<Point2> quadratic_points(Point2 p0, Point2 q, Point2 p2, double tolerance) {
  return cubic_points({p0, lerp(p0, q, 2.0 / 3), lerp(p2, q, 2.0 / 3), p2}, tolerance);
}

namespace {

class PathBuilder {
 public:
  PathBuilder(double tolerance, std::size_t max_points) : tol_(tolerance), max_(max_points) {}
  void move(Point2 p) {
    finish();
    current_.points = {p};
    start_ = p;
  }
  void line(Point2 p) {
    if (current_.points.empty()) current_.points = {cursor()};
    current_.points.push_back(p);
    if (++count_ > max_) throw std::length_error("more than " + std::to_string(max_) + " points");
  }
  void cubic(Point2 p1, Point2 p2, Point2 p3) {
    for (Point2 q : cubic_points({cursor(), p1, p2, p3}, tol_)) line(q);
  }
  void quadratic(Point2 p1, Point2 p2) {
    for (Point2 q : quadratic_points(cursor(), p1, p2, tol_)) line(q);
  }
  void arc(double rx, double ry, double phi_deg, bool large, bool sweep, Point2 to);
  void close() {
    if (current_.points.empty()) return;
    current_.closed = true;
    finish();
    current_.points = {start_};  // a command after Z starts at the subpath's start
    pending_start_ = true;
  }
  Point2 cursor() const { return current_.points.empty() ? start_ : current_.points.back(); }
  std::vector<Subpath> take() {
    finish();
    return std::move(out_);
  }

 private:
  void finish() {
    if (pending_start_ && current_.points.size() == 1) current_.points.clear();
    pending_start_ = false;
    if (current_.points.size() >= 2) out_.push_back(std::move(current_));
    current_ = {};
  }
  double tol_;
  std::size_t max_, count_ = 0;
  Subpath current_;
  Point2 start_;
  bool pending_start_ = false;
  std::vector<Subpath> out_;
};

// Endpoint to centre parameterisation (SVG 1.1 §F.6.5), radii scaled up when too small (§F.6.6).
void PathBuilder::arc(double rx, double ry, double phi_deg, bool large, bool sweep, Point2 to) {
  const Point2 from = cursor();
  rx = std::abs(rx);
  ry = std::abs(ry);
  if (rx == 0 || ry == 0 || (from.x_mm == to.x_mm && from.v_mm == to.v_mm)) {
    if (!(from == to)) line(to);
    return;
  }
  const double phi = phi_deg * kPi / 180, cs = std::cos(phi), sn = std::sin(phi);
  const double dx = (from.x_mm - to.x_mm) / 2, dy = (from.v_mm - to.v_mm) / 2;
  const double x1 = cs * dx + sn * dy, y1 = -sn * dx + cs * dy;
  const double lambda = x1 * x1 / (rx * rx) + y1 * y1 / (ry * ry);
  if (lambda > 1) {
    rx *= std::sqrt(lambda);
    ry *= std::sqrt(lambda);
  }
  const double num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1;
  const double den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
  double k = std::sqrt(std::max(0.0, num / den));
  if (large == sweep) k = -k;
  const double cx1 = k * rx * y1 / ry, cy1 = -k * ry * x1 / rx;
  const double cx = cs * cx1 - sn * cy1 + (from.x_mm + to.x_mm) / 2;
  const double cy = sn * cx1 + cs * cy1 + (from.v_mm + to.v_mm) / 2;
  const auto angle = [](double ux, double uy, double vx, double vy) {
    return std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
  };
  const double theta1 = angle(1, 0, (x1 - cx1) / rx, (y1 - cy1) / ry);
  double dtheta = angle((x1 - cx1) / rx, (y1 - cy1) / ry, (-x1 - cx1) / rx, (-y1 - cy1) / ry);
  if (!sweep && dtheta > 0) dtheta -= 2 * kPi;
  if (sweep && dtheta < 0) dtheta += 2 * kPi;
  const double r = std::max(rx, ry);
  const double step = r > tol_ ? 2 * std::acos(1 - tol_ / r) : kPi / 2;
  const int n = std::clamp(static_cast<int>(std::ceil(std::abs(dtheta) / step)), 1, 100000);
  for (int i = 1; i < n; ++i) {
    const double t = theta1 + dtheta * i / n;
    line({cx + rx * std::cos(t) * cs - ry * std::sin(t) * sn, cy + rx * std::cos(t) * sn + ry * std::sin(t) * cs});
  }
  line(to);
}

}  // namespace

Affine Affine::then(const Affine& o) const {
  return {o.a * a + o.c * b, o.b * a + o.d * b,       o.a * c + o.c * d,
          o.b * c + o.d * d, o.a * e + o.c * f + o.e, o.b * e + o.d * f + o.f};
}

double Affine::max_scale() const {
  // The largest singular value of [[a c] [b d]].
  const double s1 = a * a + b * b + c * c + d * d, det = a * d - b * c;
  return std::sqrt((s1 + std::sqrt(std::max(0.0, s1 * s1 - 4 * det * det))) / 2);
}

Affine parse_transform(const std::string& text) {
  Affine m;
  Scanner in(text);
  while (!in.done()) {
    std::string name;
    while (!in.done() && std::isalpha(static_cast<unsigned char>(in.peek()))) name += in.take();
    if (in.peek() != '(')
      throw std::invalid_argument("expected a transform such as translate(x y), got \"" + text + "\"");
    in.take();
    std::vector<double> v;
    while (in.at_number()) v.push_back(in.number());
    if (in.peek() != ')') throw std::invalid_argument("expected \")\" after " + name + "(…) in \"" + text + "\"");
    in.take();
    const auto want = [&](std::size_t lo, std::size_t hi) {
      if (v.size() < lo || v.size() > hi)
        throw std::invalid_argument(name + "() takes " + std::to_string(lo) +
                                    (lo == hi ? "" : "–" + std::to_string(hi)) + " numbers, got " +
                                    std::to_string(v.size()));
    };
    Affine t;
    if (name == "matrix") {
      want(6, 6);
      t = {v[0], v[1], v[2], v[3], v[4], v[5]};
    } else if (name == "translate") {
      want(1, 2);
      t.e = v[0];
      t.f = v.size() > 1 ? v[1] : 0;
    } else if (name == "scale") {
      want(1, 2);
      t.a = v[0];
      t.d = v.size() > 1 ? v[1] : v[0];
    } else if (name == "rotate") {
      want(1, 3);
      const double r = v[0] * kPi / 180, cx = v.size() == 3 ? v[1] : 0, cy = v.size() == 3 ? v[2] : 0;
      if (v.size() == 2) throw std::invalid_argument("rotate() takes 1 or 3 numbers, got 2");
      t = Affine{1, 0, 0, 1, -cx, -cy}
              .then({std::cos(r), std::sin(r), -std::sin(r), std::cos(r), 0, 0})
              .then({1, 0, 0, 1, cx, cy});
    } else if (name == "skewX") {
      want(1, 1);
      t.c = std::tan(v[0] * kPi / 180);
    } else if (name == "skewY") {
      want(1, 1);
      t.b = std::tan(v[0] * kPi / 180);
    } else {
      throw std::invalid_argument("unknown transform \"" + name +
                                  "\": expected matrix, translate, scale, rotate, skewX or skewY");
    }
    m = t.then(m);  // the list applies right to left: the last one touches the points first
  }
  return m;
}

std::vector<double> parse_number_list(const std::string& text) {
  Scanner in(text);
  std::vector<double> out;
  while (!in.done()) out.push_back(in.number());
  return out;
}

std::vector<Point2> ellipse_points(Point2 c, double rx, double ry, double tolerance) {
  const double r = std::max(rx, ry);
  const double step = r > tolerance ? 2 * std::acos(1 - tolerance / r) : kPi / 2;
  const int n = std::clamp(static_cast<int>(std::ceil(2 * kPi / step)), 4, 100000);
  std::vector<Point2> out;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * kPi * i / n;
    out.push_back({c.x_mm + rx * std::cos(t), c.v_mm + ry * std::sin(t)});
  }
  return out;
}

std::vector<Subpath> parse_path_data(const std::string& d, double tolerance, std::size_t max_points) {
  Scanner in(d);
  PathBuilder out(tolerance, max_points);
  char command = 0;
  Point2 last_control;  // reflected by S and T
  char last = 0;
  while (!in.done()) {
    if (!in.at_number()) {
      command = in.take();
      if (!std::strchr("MmLlHhVvCcSsQqTtAaZz", command) || command == '\0')
        throw std::invalid_argument(std::string("unknown path command \"") + command + "\" at character " +
                                    std::to_string(in.position() - 1));
    } else if (command == 0) {
      throw std::invalid_argument("path data must start with a moveto (M or m)");
    }
    const bool rel = std::islower(static_cast<unsigned char>(command));
    const Point2 at = out.cursor();
    const auto pt = [&] {
      const double x = in.number(), y = in.number();
      return rel ? Point2{at.x_mm + x, at.v_mm + y} : Point2{x, y};
    };
    const auto reflected = [&](const char* kinds) {
      return std::strchr(kinds, last) && last ? Point2{2 * at.x_mm - last_control.x_mm, 2 * at.v_mm - last_control.v_mm}
                                              : at;
    };
    switch (std::toupper(static_cast<unsigned char>(command))) {
      case 'M':
        out.move(pt());
        command = rel ? 'l' : 'L';  // further pairs are implicit linetos
        break;
      case 'L': out.line(pt()); break;
      case 'H': out.line({(rel ? at.x_mm : 0) + in.number(), at.v_mm}); break;
      case 'V': out.line({at.x_mm, (rel ? at.v_mm : 0) + in.number()}); break;
      case 'C': {
        const Point2 p1 = pt(), p2 = pt(), p3 = pt();
        out.cubic(p1, p2, p3);
        last_control = p2;
        break;
      }
      case 'S': {
        const Point2 p1 = reflected("CcSs"), p2 = pt(), p3 = pt();
        out.cubic(p1, p2, p3);
        last_control = p2;
        break;
      }
      case 'Q': {
        const Point2 p1 = pt(), p2 = pt();
        out.quadratic(p1, p2);
        last_control = p1;
        break;
      }
      case 'T': {
        const Point2 p1 = reflected("QqTt"), p2 = pt();
        out.quadratic(p1, p2);
        last_control = p1;
        break;
      }
      case 'A': {
        const double rx = in.number(), ry = in.number(), phi = in.number();
        const bool large = in.flag(), sweep = in.flag();
        out.arc(rx, ry, phi, large, sweep, pt());
        break;
      }
      case 'Z': out.close(); break;
    }
    last = command;
    if (std::toupper(static_cast<unsigned char>(command)) == 'Z') command = 0;
    if (command == 0 && in.at_number()) throw std::invalid_argument("numbers after Z need a command first");
  }
  return out.take();
}

}  // namespace popcut::svg
