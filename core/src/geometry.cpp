// The shared geometry: the face map to 3D, ring areas, inside points, bounds, splits at repeated vertices.
#include "popcut/geometry.h"

#include <algorithm>
#include <map>
#include <utility>

namespace popcut {

const char* to_string(LineKind kind) { return kLineKindNames.name(kind).data(); }

const char* to_string(FaceKind kind) { return kFaceKindNames.name(kind).data(); }

Point3 to_card(FaceKind kind, double t_mm, Point2 p) {
  if (kind == FaceKind::vertical) return {p.x_mm, t_mm, p.v_mm + t_mm};
  return {p.x_mm, t_mm - p.v_mm, t_mm};
}

double signed_area_mm2(const Ring& ring) {
  double twice = 0;
  for (std::size_t i = 0, n = ring.size(); i < n; ++i) {
    const Point2& p = ring[i];
    const Point2& q = ring[(i + 1) % n];
    twice += p.x_mm * q.v_mm - q.x_mm * p.v_mm;
  }
  return twice / 2;
}

namespace {
void split_into(const Ring& ring, std::vector<Ring>& out) {
  std::map<std::pair<double, double>, std::size_t> seen;
  for (std::size_t j = 0; j < ring.size(); ++j) {
    auto [it, fresh] = seen.emplace(std::make_pair(ring[j].x_mm, ring[j].v_mm), j);
    if (fresh) continue;
    const std::size_t i = it->second;
    split_into(Ring(ring.begin() + static_cast<std::ptrdiff_t>(i), ring.begin() + static_cast<std::ptrdiff_t>(j)), out);
    Ring rest(ring.begin(), ring.begin() + static_cast<std::ptrdiff_t>(i));
    rest.insert(rest.end(), ring.begin() + static_cast<std::ptrdiff_t>(j), ring.end());
    split_into(rest, out);
    return;
  }
  out.push_back(ring);
}
}  // namespace

std::vector<Ring> split_at_repeated_vertices(const Ring& ring) {
  // Most rings repeat nothing: one sort says so, without a map node per vertex.
  Ring sorted = ring;
  std::sort(sorted.begin(), sorted.end(), lexicographic_less);
  if (std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end()) return {ring};
  std::vector<Ring> out;
  split_into(ring, out);
  return out;
}

Point2 interior_point(const Ring& outer, const std::vector<Ring>& holes) {
  std::vector<double> heights;
  const auto add = [&](const Ring& r) {
    for (const Point2& p : r) heights.push_back(p.v_mm);
  };
  add(outer);
  for (const Ring& h : holes) add(h);
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end()), heights.end());
  // Halfway across the tallest band between vertex heights: the line passes through no vertex and
  // keeps as far from them as a horizontal line can.
  double v = heights[0], tallest = 0;
  for (std::size_t i = 1; i < heights.size(); ++i)
    if (heights[i] - heights[i - 1] > tallest) {
      tallest = heights[i] - heights[i - 1];
      v = (heights[i] + heights[i - 1]) / 2;
    }
  std::vector<double> xs;
  const auto cross = [&](const Ring& r) {
    for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
      const Point2& a = r[i];
      const Point2& b = r[j];
      if ((a.v_mm > v) != (b.v_mm > v)) xs.push_back(a.x_mm + (v - a.v_mm) * (b.x_mm - a.x_mm) / (b.v_mm - a.v_mm));
    }
  };
  cross(outer);
  for (const Ring& h : holes) cross(h);
  std::sort(xs.begin(), xs.end());
  Point2 best = outer.front();
  double width = -1;
  for (std::size_t i = 0; i + 1 < xs.size(); i += 2) {
    if (xs[i + 1] - xs[i] > width) {
      width = xs[i + 1] - xs[i];
      best = {(xs[i] + xs[i + 1]) / 2, v};
    }
  }
  return best;
}

Rect bounds(const Ring& ring) {
  Rect r{ring.empty() ? Point2{} : ring.front(), ring.empty() ? Point2{} : ring.front()};
  for (const Point2& p : ring) {
    r.min.x_mm = std::min(r.min.x_mm, p.x_mm);
    r.min.v_mm = std::min(r.min.v_mm, p.v_mm);
    r.max.x_mm = std::max(r.max.x_mm, p.x_mm);
    r.max.v_mm = std::max(r.max.v_mm, p.v_mm);
  }
  return r;
}

bool inside_ring(Point2 p, const Ring& ring) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Point2 a = ring[i], b = ring[j];
    if ((a.v_mm > p.v_mm) != (b.v_mm > p.v_mm) &&
        p.x_mm < (b.x_mm - a.x_mm) * (p.v_mm - a.v_mm) / (b.v_mm - a.v_mm) + a.x_mm)
      in = !in;
  }
  return in;
}

}  // namespace popcut
