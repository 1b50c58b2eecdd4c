// Face model edits (polygon paper eq. 4–6) with CGAL's exact regularized Booleans, and input checks.
#include "popcut/model/face_model.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/Polygon_set_2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "model/face_model_state.h"
#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
using namespace detail;

namespace {

using PolygonSet = CGAL::Polygon_set_2<Kernel>;

std::string point_text(double x, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "(%g, %g)", x, v);
  return buf;
}

[[noreturn]] void fail(const std::string& source, const std::string& where, const std::string& message) {
  throw Error(ErrorCode::invalid_input, source, where, message);
}

// An exact, simple, counter-clockwise polygon from pattern points, or an error naming `where`.
// `exact` holds the same points exactly; when empty they are read from `ring` as decimals.
ExactPolygon exact_polygon(const Ring& ring, const std::string& source, const std::string& where,
                           std::vector<ExactPoint> exact = {}) {
  if (ring.size() > kMaxOutlinePoints) {
    fail(source, where, "has " + std::to_string(ring.size()) + " points; the limit is " + std::to_string(kMaxOutlinePoints));
  }
  std::vector<ExactPoint> pts;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point2& p = ring[i];
    if (!std::isfinite(p.x_mm) || !std::isfinite(p.v_mm) || std::abs(p.x_mm) > kMaxFaceCoordinateMm ||
        std::abs(p.v_mm) > kMaxFaceCoordinateMm) {
      fail(source, where, "point " + point_text(p.x_mm, p.v_mm) + " is not a finite coordinate within ±100000 mm");
    }
    const ExactPoint q = exact.empty() ? ExactPoint(exact_decimal(p.x_mm), exact_decimal(p.v_mm)) : exact[i];
    if (pts.empty() || pts.back() != q) pts.push_back(q);
  }
  while (pts.size() > 1 && pts.front() == pts.back()) pts.pop_back();
  if (pts.size() < 3) fail(source, where, "needs at least 3 distinct points");
  ExactPolygon poly(pts.begin(), pts.end());
  const bool collinear = std::all_of(pts.begin() + 2, pts.end(), [&](const ExactPoint& p) { return CGAL::collinear(pts[0], pts[1], p); });
  if (collinear) fail(source, where, "has zero area: all its points lie on one line");
  if (!poly.is_simple()) fail(source, where, "crosses or touches itself: an outline must be a simple polygon");
  if (poly.is_clockwise_oriented()) poly.reverse_orientation();
  return poly;
}



bool inside_sheet(const ExactPolygon& poly, const FaceModelState& s) {
  for (const ExactPoint& p : poly.vertices()) {
    if (p.x() < s.min_x || p.x() > s.max_x || p.y() < s.min_v || p.y() > s.max_v) return false;
  }
  return true;
}

// A Boolean result whose outer ring pinches at a vertex holds lobes that touch only at a point:
// separate pieces of paper, so separate faces (as the voxel path's 4-connected regions are).
// Clockwise loops split off the outer ring are holes touching it; each hole goes to its lobe.
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
    if (poly.is_counterclockwise_oriented()) lobes.emplace_back(poly);
    else holes.push_back(poly);
  }
  for (ExactPolygon& h : holes) {
    for (ExactPolygonWithHoles& lobe : lobes) {
      const auto inside = [&](const ExactPoint& p) { return lobe.outer_boundary().bounded_side(p) != CGAL::ON_UNBOUNDED_SIDE; };
      if (std::all_of(h.vertices_begin(), h.vertices_end(), inside)) {
        lobe.add_hole(h);
        break;
      }
    }
  }
  return lobes;
}

std::shared_ptr<const ExactFace> make_face(FaceKind kind, const FT& t, ExactPolygonWithHoles polygon) {
  auto f = std::make_shared<ExactFace>(ExactFace{kind, t, std::move(polygon), {}});
  f->bbox = f->polygon.outer_boundary().bbox();
  return f;
}

ExactPolygon rectangle(const FT& x0, const FT& v0, const FT& x1, const FT& v1) {
  const ExactPoint pts[] = {{x0, v0}, {x1, v0}, {x1, v1}, {x0, v1}};
  return ExactPolygon(std::begin(pts), std::end(pts));
}

double checked_size(double value, const char* what) {
  if (!std::isfinite(value) || value <= 0 || value > kMaxFaceCoordinateMm) {
    fail("", std::string("sheet.") + what, "must be a length in mm from 0 (exclusive) to 100000");
  }
  return value;
}

std::shared_ptr<FaceModelState> initial_state(double width_mm, double back_mm, double floor_mm) {
  auto s = std::make_shared<FaceModelState>();
  s->min_x = 0;
  s->max_x = exact_decimal(checked_size(width_mm, "width"));
  s->max_v = exact_decimal(checked_size(back_mm, "back"));
  s->min_v = -exact_decimal(checked_size(floor_mm, "floor"));
  return s;
}

// Runs CGAL work, turning any CGAL failure into an internal error: none may reach the user raw.
template <typename Body>
auto guarded(const std::string& source, const std::string& where, Body body) {
  try {
    return body();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(ErrorCode::internal, source, where, std::string("geometry kernel failure: ") + e.what());
  }
}

FT polygon_area(const ExactPolygonWithHoles& p) {
  FT area = p.outer_boundary().area();
  for (const ExactPolygon& h : p.holes()) area += h.area();  // holes run clockwise: negative
  return area;
}

// Calls visit(i, j), i < j, for every pair of faces whose bounding boxes meet (CGAL's box sweep).
template <typename Visit>
void for_overlapping_boxes(const std::vector<std::shared_ptr<const ExactFace>>& faces, Visit visit) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::size_t>;
  std::vector<Box> boxes;
  boxes.reserve(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) boxes.emplace_back(faces[i]->bbox, i);
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    visit(std::min(a.info(), b.info()), std::max(a.info(), b.info()));
  });
}

// Eq. 5 for the whole history at once: face i is drawn polygon i minus the union of the
// polygons drawn after it that come near it (one aggregated union each). A polygon nothing
// covers is shared as it is; pieces that touch only at a corner become separate faces.
std::shared_ptr<const FaceModelState> work_out_faces(const FaceModelState& sheet,
                                                     const std::vector<std::shared_ptr<const ExactFace>>& drawn,
                                                     std::size_t given) {
  return guarded("", "faces", [&] {
    std::vector<std::vector<std::size_t>> above(drawn.size());
    for_overlapping_boxes(drawn, [&](std::size_t i, std::size_t j) {
      if (j >= given) above[i].push_back(j);  // faces given as final are disjoint already
    });
    auto s = std::make_shared<FaceModelState>();
    s->min_x = sheet.min_x;
    s->max_x = sheet.max_x;
    s->min_v = sheet.min_v;
    s->max_v = sheet.max_v;
    for (std::size_t i = 0; i < drawn.size(); ++i) {
      const ExactFace& d = *drawn[i];
      if (above[i].empty()) {
        s->faces.push_back(drawn[i]);
        continue;
      }
      std::vector<ExactPolygonWithHoles> cover;
      cover.reserve(above[i].size());
      for (std::size_t j : above[i]) cover.push_back(drawn[j]->polygon);
      PolygonSet rest(d.polygon);
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
        for (ExactPolygonWithHoles& lobe : split_lobes(piece)) s->faces.push_back(make_face(d.kind, d.t, std::move(lobe)));
      }
      if (s->faces.size() > kMaxFaces) fail("", "edits", "the model would have more than " + std::to_string(kMaxFaces) + " faces");
    }
    return std::shared_ptr<const FaceModelState>(std::move(s));
  });
}

}  // namespace

const char* to_string(EditOp op) {
  switch (op) {
    case EditOp::add_vface: return "add_vface";
    case EditOp::add_hface: return "add_hface";
    case EditOp::add_vhole: return "add_vhole";
    case EditOp::add_hhole: return "add_hhole";
  }
  return "add_vface";
}

FaceModel::FaceModel(double width_mm, double back_mm, double floor_mm) {
  auto s = initial_state(width_mm, back_mm, floor_mm);
  drawn_.push_back(make_face(FaceKind::vertical, 0, ExactPolygonWithHoles(rectangle(s->min_x, 0, s->max_x, s->max_v))));
  drawn_.push_back(make_face(FaceKind::horizontal, 0, ExactPolygonWithHoles(rectangle(s->min_x, s->min_v, s->max_x, 0))));
  given_ = drawn_.size();  // the boards do not overlap
  sheet_ = std::move(s);
  changed();
}

FaceModel FaceModel::from_faces(double width_mm, double back_mm, double floor_mm, const std::vector<OAFace>& faces,
                                const std::string& source) {
  auto s = initial_state(width_mm, back_mm, floor_mm);
  if (faces.size() > kMaxFaces) fail(source, "faces", "has " + std::to_string(faces.size()) + " faces; the limit is " + std::to_string(kMaxFaces));
  Drawn given;
  guarded(source, "faces", [&] {
    for (std::size_t i = 0; i < faces.size(); ++i) {
      const std::string where = "faces[" + std::to_string(i) + "]";
      const OAFace& f = faces[i];
      if (!std::isfinite(f.t_mm) || f.t_mm < 0 || f.t_mm > kMaxFaceCoordinateMm) fail(source, where + ".t", "must be from 0 to 100000 mm");
      // A region may touch itself at a corner: its rings then split into one counter-clockwise
      // outer loop and clockwise holes that touch it there.
      // Rings written the other way round (outer clockwise) are read as the writer meant them.
      const bool flipped = signed_area_mm2(f.polygon.outer) < 0;
      const auto oriented = [&](const Ring& r) { return flipped ? Ring(r.rbegin(), r.rend()) : r; };
      std::vector<Ring> loops = split_at_repeated_vertices(oriented(f.polygon.outer));
      for (const Ring& h : f.polygon.holes) {
        for (Ring& loop : split_at_repeated_vertices(oriented(h))) loops.push_back(std::move(loop));
      }
      std::vector<ExactPolygon> outers, holes;
      for (std::size_t k = 0; k < loops.size(); ++k) {
        const bool ccw = signed_area_mm2(loops[k]) > 0;
        ExactPolygon poly = exact_polygon(loops[k], source, where + (k == 0 ? ".outer" : ".holes"));
        if (ccw) outers.push_back(std::move(poly));
        else holes.push_back(std::move(poly));
      }
      if (outers.size() != 1) {
        fail(source, where + ".outer", "must enclose one connected region: give the outer ring counter-clockwise and holes clockwise");
      }
      ExactPolygonWithHoles pwh(outers.front());
      if (!inside_sheet(pwh.outer_boundary(), *s)) fail(source, where + ".outer", "leaves the sheet");
      for (ExactPolygon& hole : holes) {
        hole.reverse_orientation();  // holes run clockwise
        pwh.add_hole(std::move(hole));
      }
      if (!CGAL::is_valid_polygon_with_holes(pwh, CGAL::Gps_segment_traits_2<Kernel>())) {
        fail(source, where + ".holes", "holes must lie inside the outer ring without crossing it or each other");
      }
      given.push_back(make_face(f.kind, exact_decimal(f.t_mm), std::move(pwh)));
    }
    // Eq. 4: no two faces overlap, and together they cover the sheet exactly. One aggregated
    // union (a sweep, O(n log n)) proves both: its area equals the sum of the faces' areas only
    // when nothing overlaps. Only on failure are pairs searched, to name the two faces.
    FT area = 0;
    std::vector<ExactPolygonWithHoles> polygons;
    for (const auto& fp : given) {
      area += polygon_area(fp->polygon);
      polygons.push_back(fp->polygon);
    }
    PolygonSet all;
    all.join(polygons.begin(), polygons.end());
    std::vector<ExactPolygonWithHoles> united;
    all.polygons_with_holes(std::back_inserter(united));
    FT union_area = 0;
    for (const ExactPolygonWithHoles& u : united) union_area += polygon_area(u);
    if (union_area != area) {
      for_overlapping_boxes(given, [&](std::size_t i, std::size_t j) {
        if (CGAL::do_intersect(given[i]->polygon, given[j]->polygon)) {
          fail(source, "faces[" + std::to_string(i) + "]", "overlaps faces[" + std::to_string(j) + "]: faces must not overlap (eq. 4)");
        }
      });
      fail(source, "faces", "overlap: faces must not overlap (eq. 4)");
    }
    const FT sheet_area = (s->max_x - s->min_x) * (s->max_v - s->min_v);
    if (area != sheet_area) {
      fail(source, "faces", "cover " + format_decimal(CGAL::to_double(area), 2) + " mm² of a " +
                                format_decimal(CGAL::to_double(sheet_area), 2) + " mm² sheet: faces must cover it exactly (eq. 4)");
    }
    return 0;
  });
  FaceModel m;
  m.sheet_ = std::move(s);
  m.drawn_ = std::move(given);
  m.given_ = m.drawn_.size();
  m.from_edits_ = false;
  m.changed();
  return m;
}

void FaceModel::apply(const FaceEdit& edit, const std::string& source, const std::string& where) {
  if (edits_.size() >= kMaxEdits) fail(source, where, "a model may have at most " + std::to_string(kMaxEdits) + " edits");
  if (!std::isfinite(edit.t_mm) || edit.t_mm < 0 || edit.t_mm > kMaxFaceCoordinateMm) {
    fail(source, where + ".t", "must be from 0 to 100000 mm (a depth in front of the back wall or a height above the floor)");
  }
  const bool vertical_plane = edit.op == EditOp::add_vface || edit.op == EditOp::add_vhole;
  // Pattern coordinates (eq. 1): in the plane y = t, (x, z) → (x, z - t); in z = t, (x, y) → (x, t - y).
  Ring ring;
  std::vector<ExactPoint> exact;
  const FT t_exact = exact_decimal(edit.t_mm);
  double min_second = 0;
  for (std::size_t i = 0; i < edit.outline.size(); ++i) {
    const auto& [x, second] = edit.outline[i];
    if (std::isfinite(second) && second < 0) {
      fail(source, where + ".outline[" + std::to_string(i) + "]",
           vertical_plane ? "z is below the floor (z must be ≥ 0)" : "y is behind the back wall (y must be ≥ 0)");
    }
    ring.push_back({x, vertical_plane ? second - edit.t_mm : edit.t_mm - second});
    if (std::isfinite(x) && std::isfinite(second) && std::abs(x) <= kMaxFaceCoordinateMm && std::abs(second) <= kMaxFaceCoordinateMm) {
      const FT s2 = exact_decimal(second);
      exact.emplace_back(exact_decimal(x), vertical_plane ? s2 - t_exact : t_exact - s2);
    }
    min_second = i == 0 ? second : std::min(min_second, second);
  }
  Drawn added;
  guarded(source, where, [&] {
    // Exact points only when every input was finite and in range; else exact_polygon reports it.
    const ExactPolygon q = exact_polygon(ring, source, where + ".outline", exact.size() == ring.size() ? exact : std::vector<ExactPoint>{});
    const FaceModelState& sheet = *sheet_;
    if (!inside_sheet(q, sheet)) fail(source, where + ".outline", "leaves the sheet");

    FaceKind kind = vertical_plane ? FaceKind::vertical : FaceKind::horizontal;
    FT t = t_exact;
    const bool from_hole = edit.op == EditOp::add_vhole || edit.op == EditOp::add_hhole;
    if (from_hole) {
      // Eq. 6: a hole must lie in faces of its plane; it becomes the face of the other kind
      // at the hole's lowest z (in a VFace) or nearest y (in an HFace), with the same pattern polygon.
      // What shows at a point is the last polygon drawn over it, so walk down from the top
      // through the polygons near the hole until all of it is accounted for.
      PolygonSet rest(q);
      const CGAL::Bbox_2 qbox = q.bbox();
      for (std::size_t j = drawn_.size(); j-- > 0 && !rest.is_empty();) {
        const ExactFace& d = *drawn_[j];
        if (!CGAL::do_overlap(qbox, d.bbox)) continue;
        if (d.kind != kind || d.t != t) {
          PolygonSet shown = rest;
          shown.intersection(d.polygon);
          if (!shown.is_empty()) {
            fail(source, where + ".outline",
                 std::string("the hole is not inside ") + (vertical_plane ? "a VFace at depth y = " : "an HFace at height z = ") +
                     format_decimal(edit.t_mm, 3) + " mm");
          }
        }
        rest.difference(d.polygon);
      }
      kind = vertical_plane ? FaceKind::horizontal : FaceKind::vertical;
      t = exact_decimal(min_second);
    }

    // A face made from a hole may reach past the back wall (an HFace with y < 0, i.e. v > t) or
    // below the floor (a VFace with z < 0, i.e. v < -t). As with windows in the voxel paper (§2.3)
    // that part lies on the back wall or the floor instead, with the same pattern polygon.
    const FT limit = kind == FaceKind::horizontal ? t : -t;
    const bool spills = from_hole && std::any_of(q.vertices_begin(), q.vertices_end(), [&](const ExactPoint& p) {
      return kind == FaceKind::horizontal ? p.y() > limit : p.y() < limit;
    });
    if (!spills) {
      added.push_back(make_face(kind, t, ExactPolygonWithHoles(q)));
    } else {
      const ExactPolygon stays = kind == FaceKind::horizontal ? rectangle(sheet.min_x, sheet.min_v, sheet.max_x, limit)
                                                              : rectangle(sheet.min_x, limit, sheet.max_x, sheet.max_v);
      std::vector<ExactPolygonWithHoles> kept, moved;
      CGAL::intersection(q, stays, std::back_inserter(kept));
      CGAL::difference(q, stays, std::back_inserter(moved));
      const FaceKind board = kind == FaceKind::horizontal ? FaceKind::vertical : FaceKind::horizontal;
      for (auto& piece : kept) added.push_back(make_face(kind, t, std::move(piece)));
      for (auto& piece : moved) added.push_back(make_face(board, 0, std::move(piece)));
    }
    return 0;
  });
  if (!undone_.empty()) {
    undone_.clear();
    redo_drawn_.clear();
    redo_cache_.clear();
  }
  for (auto& d : added) drawn_.push_back(std::move(d));
  edits_.push_back(edit);
  edit_end_.push_back(drawn_.size());
  keep(undo_cache_, std::move(cache_));
  changed();
}

// The faces of the last few states stay at hand, so stepping back and forth in an editor does
// not work them out again; older states recompute on demand.
void FaceModel::keep(std::vector<std::shared_ptr<FaceCache>>& stack, std::shared_ptr<FaceCache> cache) {
  constexpr std::size_t kKeptStates = 16;
  if (stack.size() == kKeptStates) stack.erase(stack.begin());
  stack.push_back(std::move(cache));
}

void FaceModel::restore(std::vector<std::shared_ptr<FaceCache>>& stack) {
  if (stack.empty()) {
    changed();
  } else {
    cache_ = std::move(stack.back());
    stack.pop_back();
  }
}

bool FaceModel::undo() {
  if (edits_.empty()) return false;
  const std::size_t begin = edits_.size() > 1 ? edit_end_[edits_.size() - 2] : given_;
  redo_drawn_.emplace_back(std::make_move_iterator(drawn_.begin() + static_cast<std::ptrdiff_t>(begin)),
                           std::make_move_iterator(drawn_.end()));
  drawn_.resize(begin);
  undone_.push_back(edits_.back());
  edits_.pop_back();
  edit_end_.pop_back();
  keep(redo_cache_, std::move(cache_));
  restore(undo_cache_);
  return true;
}

bool FaceModel::redo() {
  if (undone_.empty()) return false;
  for (auto& d : redo_drawn_.back()) drawn_.push_back(std::move(d));
  redo_drawn_.pop_back();
  edits_.push_back(undone_.back());
  undone_.pop_back();
  edit_end_.push_back(drawn_.size());
  keep(undo_cache_, std::move(cache_));
  restore(redo_cache_);
  return true;
}

// Faces are worked out at most once per state; copies of a model share the result.
struct detail::FaceCache {
  std::once_flag once;
  std::shared_ptr<const FaceModelState> state;
};

void FaceModel::changed() { cache_ = std::make_shared<FaceCache>(); }

const FaceModelState& FaceModel::state() const {
  std::call_once(cache_->once, [&] { cache_->state = work_out_faces(*sheet_, drawn_, given_); });
  return *cache_->state;
}

std::string FaceModel::drawn_by(Point2 p) const {
  const ExactPoint q(p.x_mm, p.v_mm);  // doubles convert exactly
  for (std::size_t j = drawn_.size(); j-- > 0;) {
    const ExactFace& d = *drawn_[j];
    if (p.x_mm < d.bbox.xmin() || p.x_mm > d.bbox.xmax() || p.v_mm < d.bbox.ymin() || p.v_mm > d.bbox.ymax()) continue;
    if (d.polygon.outer_boundary().bounded_side(q) == CGAL::ON_UNBOUNDED_SIDE) continue;
    if (std::any_of(d.polygon.holes_begin(), d.polygon.holes_end(),
                    [&](const ExactPolygon& h) { return h.bounded_side(q) != CGAL::ON_UNBOUNDED_SIDE; })) {
      continue;
    }
    if (j >= given_) {
      const auto k = std::upper_bound(edit_end_.begin(), edit_end_.end(), j) - edit_end_.begin();
      return "edits[" + std::to_string(k) + "]";
    }
    if (!from_edits_) return "faces[" + std::to_string(j) + "]";
    return j == 0 ? "the back board" : "the floor";
  }
  return "the sheet";
}

Rect FaceModel::sheet() const {
  return {{CGAL::to_double(sheet_->min_x), CGAL::to_double(sheet_->min_v)},
          {CGAL::to_double(sheet_->max_x), CGAL::to_double(sheet_->max_v)}};
}

std::size_t FaceModel::face_count() const { return state().faces.size(); }

std::vector<OAFace> FaceModel::faces() const {
  std::vector<OAFace> out;
  out.reserve(state().faces.size());
  for (const auto& f : state().faces) {
    OAFace o{f->kind, CGAL::to_double(f->t), {to_ring(f->polygon.outer_boundary()), {}}};
    for (const ExactPolygon& h : f->polygon.holes()) o.polygon.holes.push_back(to_ring(h));
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace popcut
