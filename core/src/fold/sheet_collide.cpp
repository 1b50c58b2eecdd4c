// Regions of a folded sheet passing through each other: CGAL's box intersection, then exact triangle tests.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "popcut/error.h"
#include "popcut/fold/sheet_fold.h"

namespace popcut {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

struct Placed {
  K::Triangle_3 tri;
  K::Vector_3 normal;  // unit
  int region;
};

K::Point_3 to_cgal(Point3 p) { return {p.x_mm, p.y_mm, p.z_mm}; }

// The triangle with every edge moved inward by `inset` (at most half its inradius): a homothety
// about the incentre, so hinge and corner contacts fall apart while crossings stay.
std::array<Point2, 3> shrunk(const std::array<Point2, 3>& t, double inset) {
  const auto side = [&](int i, int j) {
    return std::hypot(t[static_cast<std::size_t>(i)].x_mm - t[static_cast<std::size_t>(j)].x_mm,
                      t[static_cast<std::size_t>(i)].v_mm - t[static_cast<std::size_t>(j)].v_mm);
  };
  const double a = side(1, 2), b = side(2, 0), c = side(0, 1), perimeter = a + b + c;
  const double area2 =
      std::abs((t[1].x_mm - t[0].x_mm) * (t[2].v_mm - t[0].v_mm) - (t[2].x_mm - t[0].x_mm) * (t[1].v_mm - t[0].v_mm));
  if (perimeter <= 0 || area2 <= 0) return t;
  const double inradius = area2 / perimeter;
  const Point2 centre{(a * t[0].x_mm + b * t[1].x_mm + c * t[2].x_mm) / perimeter,
                      (a * t[0].v_mm + b * t[1].v_mm + c * t[2].v_mm) / perimeter};
  const double scale = 1 - std::min(inset, inradius / 2) / inradius;
  std::array<Point2, 3> out;
  for (std::size_t k = 0; k < 3; ++k)
    out[k] = {centre.x_mm + (t[k].x_mm - centre.x_mm) * scale, centre.v_mm + (t[k].v_mm - centre.v_mm) * scale};
  return out;
}

// Both in one plane, every corner of q within 0.1 µm of p's: stacked (a tab glued flat on a
// wall, the layers of a flat fold), not crossing. Poses are exact at ±180°, so true stacks are
// far inside this, and a tilt shows at q's far corners.
bool coplanar(const Placed& p, const Placed& q) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(p.normal * (q.tri.vertex(k) - p.tri.vertex(0))) > 1e-4) return false;
  return true;
}

// CGAL 5 (Debian 12) answers with a boost::variant.
K::Point_3 crossing_point(const Placed& p, const Placed& q) {
  const auto hit = CGAL::intersection(p.tri, q.tri);
  if (hit) {
    if (const auto* s = boost::get<K::Segment_3>(&*hit)) return CGAL::midpoint(s->source(), s->target());
    if (const auto* pt = boost::get<K::Point_3>(&*hit)) return *pt;
  }
  return CGAL::centroid(p.tri);
}

}  // namespace

std::vector<SheetCollision> find_collisions(const FoldableSheet& s, const SheetState& state, double inset_mm) {
  try {
    std::vector<Placed> placed;
    std::vector<Box> boxes;
    for (std::size_t r = 0; r < s.triangles.size(); ++r) {
      for (const auto& flat : s.triangles[r]) {
        const std::array<Point2, 3> t = shrunk(flat, inset_mm);
        const K::Triangle_3 tri(to_cgal(apply(state.poses[r], t[0])), to_cgal(apply(state.poses[r], t[1])),
                                to_cgal(apply(state.poses[r], t[2])));
        if (tri.is_degenerate()) continue;
        K::Vector_3 n = CGAL::normal(tri.vertex(0), tri.vertex(1), tri.vertex(2));
        n = n / std::sqrt(n.squared_length());
        boxes.emplace_back(tri.bbox(), placed.size());
        placed.push_back({tri, n, static_cast<int>(r)});
      }
    }
    std::set<std::pair<int, int>> pairs;
    std::vector<SheetCollision> out;
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
      const Placed& p = placed[x.info()];
      const Placed& q = placed[y.info()];
      if (p.region == q.region) return;
      const std::pair<int, int> key{std::min(p.region, q.region), std::max(p.region, q.region)};
      if (pairs.count(key) || coplanar(p, q) || !CGAL::do_intersect(p.tri, q.tri)) return;
      pairs.insert(key);
      const K::Point_3 at = crossing_point(p, q);
      out.push_back({key.first, key.second, {at.x(), at.y(), at.z()}});
    });
    std::sort(out.begin(), out.end(), [](const SheetCollision& a, const SheetCollision& b) {
      return std::pair(a.region_a, a.region_b) < std::pair(b.region_a, b.region_b);
    });
    return out;
  } catch (const std::exception& e) {
    throw Error(ErrorCode::internal, s.source, "collisions", std::string("geometry kernel failure: ") + e.what());
  }
}

}  // namespace popcut
