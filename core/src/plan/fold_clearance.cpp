// Fold clearance as a distance in the plane: the points of a fold closer than the gap to a cut lie in that cut's
// capsule.
#include "plan/fold_clearance.h"

#include <algorithm>
#include <cmath>

namespace popcut::plan_detail {
namespace {

struct Interval {
  double lo = 1, hi = 0;  // empty unless lo < hi
  bool empty() const { return !(lo < hi); }
};

Interval meet(Interval x, Interval y) { return {std::max(x.lo, y.lo), std::min(x.hi, y.hi)}; }

// {s : lo < c0 + s * c1 < hi}.
Interval linear_between(double c0, double c1, double lo, double hi) {
  if (c1 == 0) return (c0 > lo && c0 < hi) ? Interval{-INFINITY, INFINITY} : Interval{};
  const double s0 = (lo - c0) / c1, s1 = (hi - c0) / c1;
  return {std::min(s0, s1), std::max(s0, s1)};
}

// {s : |a + s d - c| < r} for a unit direction d.
Interval in_disc(Point2 a, Point2 d, Point2 c, double r) {
  const double fx = a.x_mm - c.x_mm, fv = a.v_mm - c.v_mm;
  const double b = d.x_mm * fx + d.v_mm * fv, k = fx * fx + fv * fv - r * r;
  const double disc = b * b - k;
  if (!(disc > 0)) return {};
  const double root = std::sqrt(disc);
  return {-b - root, -b + root};
}

// {s : the point a + s d is closer than r to segment pq}: the line through a crosses the
// capsule around pq (a convex set) in one interval, the union of its crossings with the two
// end discs and the rectangle between them.
Interval in_capsule(Point2 a, Point2 d, Point2 p, Point2 q, double r) {
  Interval out{INFINITY, -INFINITY};
  const auto join = [&](Interval x) {
    if (x.empty()) return;
    out.lo = std::min(out.lo, x.lo);
    out.hi = std::max(out.hi, x.hi);
  };
  join(in_disc(a, d, p, r));
  join(in_disc(a, d, q, r));
  const double ex = q.x_mm - p.x_mm, ev = q.v_mm - p.v_mm, len = std::sqrt(ex * ex + ev * ev);
  if (len > 0) {
    const double ux = ex / len, uv = ev / len;  // along the cut, and (-uv, ux) across it
    const double fx = a.x_mm - p.x_mm, fv = a.v_mm - p.v_mm;
    const Interval along = linear_between(fx * ux + fv * uv, d.x_mm * ux + d.v_mm * uv, 0, len);
    const Interval across = linear_between(-fx * uv + fv * ux, -d.x_mm * uv + d.v_mm * ux, -r, r);
    join(meet(along, across));
  }
  return out;
}

}  // namespace

std::vector<std::pair<double, double>> clear_pieces(Point2 a, Point2 b,
                                                    const std::vector<std::pair<Point2, Point2>>& cuts, double gap_mm,
                                                    double min_piece_mm) {
  const double len = std::hypot(b.x_mm - a.x_mm, b.v_mm - a.v_mm);
  std::vector<std::pair<double, double>> out;
  if (!(len > 0)) return out;
  const Point2 d{(b.x_mm - a.x_mm) / len, (b.v_mm - a.v_mm) / len};
  std::vector<Interval> blocked;
  for (const auto& [p, q] : cuts) {
    const Interval x = meet(in_capsule(a, d, p, q, gap_mm), {0, len});
    if (!x.empty()) blocked.push_back(x);
  }
  std::sort(blocked.begin(), blocked.end(), [](Interval x, Interval y) { return x.lo < y.lo; });
  double free_from = 0;  // arc length where the current unblocked stretch starts
  const auto keep = [&](double to) {
    if (to - free_from >= min_piece_mm) out.emplace_back(free_from / len, to / len);
  };
  for (const Interval& x : blocked) {
    if (x.lo > free_from) keep(x.lo);
    free_from = std::max(free_from, x.hi);
  }
  if (free_from < len) keep(len);
  return out;
}

}  // namespace popcut::plan_detail
