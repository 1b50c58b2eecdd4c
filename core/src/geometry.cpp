// The shared geometry's functions: the face map to 3D, ring areas, bounds and splitting at repeated vertices.
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

}  // namespace popcut
