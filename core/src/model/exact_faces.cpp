// The exact face operations behind FaceModel: checked polygons from input rings, lobes, and eq. 5's overlay.
#include "model/exact_faces.h"

#include <CGAL/Boolean_set_operations_2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "popcut/text.h"

namespace popcut::detail {
namespace {

std::string point_text(double x, double v) { return "(" + format_significant(x) + ", " + format_significant(v) + ")"; }

double checked_size(double value, const char* what) {
  if (!std::isfinite(value) || value <= 0 || value > kMaxFaceCoordinateMm) {
    fail("", std::string("sheet.") + what, "must be a length in mm from 0 (exclusive) to 100000");
  }
  return value;
}

}  // namespace

[[noreturn]] void fail(const std::string& source, const std::string& where, const std::string& message) {
  throw Error(ErrorCode::invalid_input, source, where, message);
}

ExactPolygon exact_polygon(const Ring& ring, const std::string& source, const std::string& where,
                           std::vector<ExactPoint> exact, bool known_simple) {
  if (ring.size() > kMaxOutlinePoints) {
    fail(source, where,
         "has " + std::to_string(ring.size()) + " points; the limit is " + std::to_string(kMaxOutlinePoints));
  }
  std::vector<ExactPoint> pts;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point2& p = ring[i];
    if (!std::isfinite(p.x_mm) || !std::isfinite(p.v_mm) || std::abs(p.x_mm) > kMaxFaceCoordinateMm ||
        std::abs(p.v_mm) > kMaxFaceCoordinateMm) {
      fail(source, where, "point " + point_text(p.x_mm, p.v_mm) + " is not a finite coordinate within ±100000 mm");
    }
    const ExactPoint q = exact.empty() ? exact_point_nm(p) : exact[i];
    if (pts.empty() || pts.back() != q) pts.push_back(q);
  }
  while (pts.size() > 1 && pts.front() == pts.back()) pts.pop_back();
  if (pts.size() < 3) fail(source, where, "needs at least 3 distinct points");
  ExactPolygon poly(pts.begin(), pts.end());
  const bool collinear =
      std::all_of(pts.begin() + 2, pts.end(), [&](const ExactPoint& p) { return CGAL::collinear(pts[0], pts[1], p); });
  if (collinear) fail(source, where, "has zero area: all its points lie on one line");
  if (!known_simple && !poly.is_simple())
    fail(source, where, "crosses or touches itself: an outline must be a simple polygon");
  if (poly.is_clockwise_oriented()) poly.reverse_orientation();
  return poly;
}

bool inside_sheet(const ExactPolygon& poly, const FaceModelState& s) {
  // Predicates on points, not coordinates: reading p.x() of a lazy point builds a number.
  const ExactPoint lo(s.min_x, s.min_v), hi(s.max_x, s.max_v);
  return std::none_of(poly.vertices_begin(), poly.vertices_end(), [&](const ExactPoint& p) {
    return CGAL::compare_x(p, lo) == CGAL::SMALLER || CGAL::compare_x(p, hi) == CGAL::LARGER ||
           CGAL::compare_y(p, lo) == CGAL::SMALLER || CGAL::compare_y(p, hi) == CGAL::LARGER;
  });
}

Ring to_ring(const ExactPolygon& poly) {
  const auto& v = poly.container();
  const std::size_t n = v.size();
  // Pinches found by one sort of the vertices (a map of exact points costs a node per vertex).
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t i, std::size_t j) { return CGAL::compare_xy(v[i], v[j]) == CGAL::SMALLER; });
  std::vector<char> pinch(n, 0);
  for (std::size_t k = 1; k < n; ++k)
    if (v[order[k]] == v[order[k - 1]]) pinch[order[k]] = pinch[order[k - 1]] = 1;
  Ring r;
  r.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (n > 3 && !pinch[i] && CGAL::collinear(v[(i + n - 1) % n], v[i], v[(i + 1) % n])) continue;
    r.push_back(to_point2(v[i]));
  }
  return r;
}

std::vector<ExactPolygonWithHoles> split_lobes(const ExactPolygonWithHoles& pwh) {
  const auto& v = pwh.outer_boundary().container();
  std::map<ExactPoint, int> visits;
  for (const ExactPoint& p : v) ++visits[p];
  if (std::all_of(visits.begin(), visits.end(), [](const auto& kv) { return kv.second == 1; })) return {pwh};
  std::vector<std::vector<ExactPoint>> loops;
  // Walk the ring; each time a vertex repeats, the stretch since its first visit closes a loop.
  std::vector<ExactPoint> stack;
  for (const ExactPoint& p : v) {
    const auto at = std::find(stack.begin(), stack.end(), p);
    if (at != stack.end()) {
      loops.emplace_back(at, stack.end());
      stack.erase(at + 1, stack.end());
    } else {
      stack.push_back(p);
    }
  }
  loops.push_back(stack);
  std::vector<ExactPolygonWithHoles> lobes;
  std::vector<ExactPolygon> holes(pwh.holes_begin(), pwh.holes_end());
  for (auto& loop : loops) {
    if (loop.size() < 3) continue;
    ExactPolygon poly(loop.begin(), loop.end());
    if (poly.is_counterclockwise_oriented())
      lobes.emplace_back(poly);
    else
      holes.push_back(poly);
  }
  for (ExactPolygon& h : holes) {
    for (ExactPolygonWithHoles& lobe : lobes) {
      const auto inside = [&](const ExactPoint& p) {
        return lobe.outer_boundary().bounded_side(p) != CGAL::ON_UNBOUNDED_SIDE;
      };
      if (std::all_of(h.vertices_begin(), h.vertices_end(), inside)) {
        lobe.add_hole(h);
        break;
      }
    }
  }
  return lobes;
}

std::shared_ptr<const ExactFace> make_face(FaceKind kind, const FT& t, ExactPolygonWithHoles polygon,
                                           bool opening_paper, bool drops_out) {
  auto f = std::make_shared<ExactFace>(ExactFace{kind, t, std::move(polygon), {}, opening_paper, drops_out});
  f->bbox = f->polygon.outer_boundary().bbox();
  return f;
}

ExactPolygon rectangle(const FT& x0, const FT& v0, const FT& x1, const FT& v1) {
  const ExactPoint pts[] = {{x0, v0}, {x1, v0}, {x1, v1}, {x0, v1}};
  return ExactPolygon(std::begin(pts), std::end(pts));
}

FT polygon_area(const ExactPolygonWithHoles& p) {
  FT area = p.outer_boundary().area();
  for (const ExactPolygon& h : p.holes()) area += h.area();  // holes run clockwise: negative
  return area;
}

std::shared_ptr<FaceModelState> initial_state(double width_mm, double back_mm, double floor_mm) {
  auto s = std::make_shared<FaceModelState>();
  s->min_x = 0;
  s->max_x = exact_nm(checked_size(width_mm, "width"));
  s->max_v = exact_nm(checked_size(back_mm, "back"));
  s->min_v = -exact_nm(checked_size(floor_mm, "floor"));
  return s;
}

namespace {

std::shared_ptr<FaceModelState> empty_like(const FaceModelState& sheet) {
  auto s = std::make_shared<FaceModelState>();
  s->min_x = sheet.min_x;
  s->max_x = sheet.max_x;
  s->min_v = sheet.min_v;
  s->max_v = sheet.max_v;
  return s;
}

// Appends what of `d` the polygons in `cover` leave showing: d itself when nothing covers it,
// else each piece of the difference, split where it pinches.
void add_uncovered(const std::shared_ptr<const ExactFace>& d, const std::vector<ExactPolygonWithHoles>& cover,
                   ExactFaces& out) {
  if (cover.empty()) {
    out.push_back(d);
    return;
  }
  PolygonSet rest(d->polygon);
  if (cover.size() == 1) {
    rest.difference(cover.front());
  } else {
    PolygonSet covered;
    covered.join(cover.begin(), cover.end());
    rest.difference(covered);
  }
  std::vector<ExactPolygonWithHoles> pieces;
  rest.polygons_with_holes(std::back_inserter(pieces));
  for (const ExactPolygonWithHoles& piece : pieces) {
    for (ExactPolygonWithHoles& lobe : split_lobes(piece))
      out.push_back(make_face(d->kind, d->t, std::move(lobe), d->opening_paper, d->drops_out));
  }
}

void check_face_count(const FaceModelState& s) {
  if (s.faces.size() > kMaxFaces)
    fail("", "edits", "the model would have more than " + std::to_string(kMaxFaces) + " faces");
}

}  // namespace

std::shared_ptr<const FaceModelState> work_out_faces(const FaceModelState& sheet, const ExactFaces& drawn,
                                                     std::size_t given) {
  return guarded("", "faces", [&] {
    std::vector<std::vector<std::size_t>> above(drawn.size());
    if (given < drawn.size())  // faces given as final are disjoint already
      for_overlapping_boxes(drawn, [&](std::size_t i, std::size_t j) {
        if (j >= given) above[i].push_back(j);
      });
    auto s = empty_like(sheet);
    std::vector<ExactPolygonWithHoles> cover;
    for (std::size_t i = 0; i < drawn.size(); ++i) {
      cover.clear();
      for (std::size_t j : above[i]) cover.push_back(drawn[j]->polygon);
      add_uncovered(drawn[i], cover, s->faces);
      check_face_count(*s);
    }
    return std::shared_ptr<const FaceModelState>(std::move(s));
  });
}

std::shared_ptr<const FaceModelState> cover_faces(const FaceModelState& before, const ExactFaces& added) {
  return guarded("", "faces", [&] {
    auto s = empty_like(before);
    s->faces.reserve(before.faces.size() + added.size());
    std::vector<ExactPolygonWithHoles> cover;
    const auto add = [&](const std::shared_ptr<const ExactFace>& d, std::size_t first_above) {
      cover.clear();
      for (std::size_t k = first_above; k < added.size(); ++k) {
        if (CGAL::do_overlap(d->bbox, added[k]->bbox)) cover.push_back(added[k]->polygon);
      }
      add_uncovered(d, cover, s->faces);
    };
    for (const auto& f : before.faces) add(f, 0);
    for (std::size_t k = 0; k < added.size(); ++k) add(added[k], k + 1);
    check_face_count(*s);
    return std::shared_ptr<const FaceModelState>(std::move(s));
  });
}

}  // namespace popcut::detail
