// Point and polyline helpers every planning unit shares: distance, sameness, closed loops and their starts.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut::plan_detail {

inline constexpr double kEps = 1e-7;  // mm: pattern coordinates are exact to far better than this
inline constexpr double kPi = 3.14159265358979323846;

// Not std::hypot: its overflow care costs several times more, and millimetres never overflow.
inline double dist(Point2 a, Point2 b) {
  const double dx = a.x_mm - b.x_mm, dv = a.v_mm - b.v_mm;
  return std::sqrt(dx * dx + dv * dv);
}
inline bool same(Point2 a, Point2 b) { return dist(a, b) <= kEps; }

inline Point2 lerp(Point2 a, Point2 b, double t) {
  return {a.x_mm + (b.x_mm - a.x_mm) * t, a.v_mm + (b.v_mm - a.v_mm) * t};
}

inline std::vector<Point2> reversed(std::vector<Point2> p) {
  std::reverse(p.begin(), p.end());
  return p;
}

inline bool is_closed(const std::vector<Point2>& p) { return p.size() > 2 && same(p.front(), p.back()); }

// Where a closed loop starts and ends: on its segment `seg` (from vertex seg to seg + 1), the
// fraction t of the way along (t = 0: at the vertex).
struct LoopStart {
  std::size_t seg = 0;
  double t = 0;
  friend bool operator==(const LoopStart&, const LoopStart&) = default;
};

inline Point2 loop_point(const std::vector<Point2>& p, LoopStart at) {
  return at.t == 0 ? p[at.seg] : lerp(p[at.seg], p[at.seg + 1], at.t);
}

// Rotates a closed loop to start (and end) at vertex i.
inline void rotate_loop(std::vector<Point2>& p, std::size_t i) {
  if (i == 0 || i + 1 >= p.size()) return;
  std::vector<Point2> r(p.begin() + static_cast<long>(i), p.end() - 1);
  r.insert(r.end(), p.begin(), p.begin() + static_cast<long>(i) + 1);
  p = std::move(r);
}

// Rotates a closed loop to start (and end) at `at`, which becomes a vertex when mid-segment.
inline void rotate_loop(std::vector<Point2>& p, LoopStart at) {
  if (at.t == 0) return rotate_loop(p, at.seg);
  const Point2 q = loop_point(p, at);
  std::vector<Point2> r{q};
  r.insert(r.end(), p.begin() + static_cast<long>(at.seg) + 1, p.end() - 1);
  r.insert(r.end(), p.begin(), p.begin() + static_cast<long>(at.seg) + 1);
  r.push_back(q);
  p = std::move(r);
}

}  // namespace popcut::plan_detail
