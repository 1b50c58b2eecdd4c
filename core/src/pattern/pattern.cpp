// Small geometric helpers shared by every pattern: the face map to 3D, edge classification, areas.
#include "popcut/pattern/pattern.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace popcut {

const char* to_string(LineKind kind) { return kLineKindNames.name(kind).data(); }

const char* to_string(FaceKind kind) { return kFaceKindNames.name(kind).data(); }

Point3 to_card(FaceKind kind, double t_mm, Point2 p) {
  if (kind == FaceKind::vertical) return {p.x_mm, t_mm, p.v_mm + t_mm};
  return {p.x_mm, t_mm - p.v_mm, t_mm};
}

bool classify_x_edge(FaceKind upper_kind, double upper_t, FaceKind lower_kind, double lower_t, double v,
                     double tolerance, LineKind& out) {
  if (upper_kind == lower_kind && std::abs(upper_t - lower_t) <= tolerance) return false;
  // The edge is the 3D line through to_card(face, (0, v)) for each face; they meet when equal.
  const Point3 a = to_card(upper_kind, upper_t, {0, v});
  const Point3 b = to_card(lower_kind, lower_t, {0, v});
  const bool meet = std::abs(a.y_mm - b.y_mm) <= tolerance && std::abs(a.z_mm - b.z_mm) <= tolerance;
  if (!meet || upper_kind == lower_kind) {
    out = LineKind::cut;
  } else {
    out = upper_kind == FaceKind::vertical ? LineKind::valley : LineKind::mountain;
  }
  return true;
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
  std::vector<Ring> out;
  split_into(ring, out);
  return out;
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

LineCounts count_lines(const Pattern& pattern) {
  LineCounts c;
  for (const Segment& s : pattern.lines) {
    const double len = std::hypot(s.b.x_mm - s.a.x_mm, s.b.v_mm - s.a.v_mm);
    switch (s.kind) {
      case LineKind::cut: ++c.cut; c.cut_mm += len; break;
      case LineKind::mountain: ++c.mountain; c.mountain_mm += len; break;
      case LineKind::valley: ++c.valley; c.valley_mm += len; break;
    }
  }
  return c;
}

}  // namespace popcut
