// Face model edits (polygon paper eq. 5–6): each edit a polygon drawn over the ones before, with undo and redo.
#include "popcut/model/face_model.h"

#include <CGAL/Boolean_set_operations_2.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "model/exact_faces.h"
#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
using namespace detail;

namespace {

// An edit's outline in pattern coordinates (eq. 1): in the plane y = t, (x, z) → (x, z - t); in
// z = t, (x, y) → (x, t - y). `exact` holds the same points exactly when every input was finite
// and in range (else exact_polygon reports the bad point); `min_second` is the lowest z or y.
struct PatternOutline {
  Ring ring;
  std::vector<ExactPoint> exact;
  double min_second = 0;
};

PatternOutline pattern_outline(const std::vector<std::array<double, 2>>& points, const FaceEdit& edit,
                               bool vertical_plane, const FT& t_exact, const std::string& source,
                               const std::string& field) {
  PatternOutline out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& [x, second] = points[i];
    if (std::isfinite(second) && second < 0) {
      fail(source, field + "[" + std::to_string(i) + "]",
           vertical_plane ? "z is below the floor (z must be ≥ 0)" : "y is behind the back wall (y must be ≥ 0)");
    }
    out.ring.push_back({x, vertical_plane ? second - edit.t_mm : edit.t_mm - second});
    if (std::isfinite(x) && std::isfinite(second) && std::abs(x) <= kMaxFaceCoordinateMm &&
        std::abs(second) <= kMaxFaceCoordinateMm) {
      const FT s2 = exact_nm(second);
      out.exact.emplace_back(exact_nm(x), vertical_plane ? s2 - t_exact : t_exact - s2);
    }
    out.min_second = i == 0 ? second : std::min(out.min_second, second);
  }
  if (out.exact.size() != out.ring.size()) out.exact.clear();
  return out;
}

// The ring as the exact path has it (z − t worked out on the nm grid, not in doubles), so a face
// with holes meets a face drawn without them corner for corner. A point that is not a number in
// range keeps the ring as given: the checks name it.
Ring on_nm_grid(const PatternOutline& outline) {
  if (outline.exact.empty()) return outline.ring;
  Ring ring;
  for (const ExactPoint& p : outline.exact)
    ring.push_back({CGAL::to_double(p.x()) / kNmPerMm, CGAL::to_double(p.y()) / kNmPerMm});  // whole nm: exact
  return ring;
}

// An add_vface or add_hface with holes: its rings in pattern coordinates, oriented and checked as
// a face read from a file is (pinches split, holes inside the outline and apart).
std::shared_ptr<const ExactFace> face_with_holes(const FaceEdit& edit, const PatternOutline& outline,
                                                 bool vertical_plane, const FT& t_exact, const FaceModelState& sheet,
                                                 const std::string& source, const std::string& where) {
  if (edit.op != EditOp::add_vface && edit.op != EditOp::add_hface)
    fail(source, where + ".holes", "only add_vface and add_hface have holes (a hole's outline is its own edit)");
  const auto oriented = [](Ring r, bool want_ccw) {
    if ((signed_area_mm2(r) > 0) != want_ccw) std::reverse(r.begin(), r.end());
    return r;
  };
  OAFace face{
      vertical_plane ? FaceKind::vertical : FaceKind::horizontal, edit.t_mm, {oriented(on_nm_grid(outline), true), {}}};
  for (std::size_t k = 0; k < edit.holes.size(); ++k) {
    const std::string field = where + ".holes[" + std::to_string(k) + "]";
    face.polygon.holes.push_back(
        oriented(on_nm_grid(pattern_outline(edit.holes[k], edit, vertical_plane, t_exact, source, field)), false));
  }
  return given_face(face, sheet, source, where, false, ".outline");
}

// Eq. 6: a hole must lie in faces of its plane (kind at t). What shows at a point is the last
// polygon drawn over it, so walk down from the top through the polygons near the hole until all
// of it is accounted for.
void check_hole_inside(const ExactPolygon& q, FaceKind kind, const FT& t, const ExactFaces& drawn, const FaceEdit& edit,
                       const std::string& source, const std::string& where) {
  PolygonSet rest(q);
  const CGAL::Bbox_2 qbox = q.bbox();
  for (std::size_t j = drawn.size(); j-- > 0 && !rest.is_empty();) {
    const ExactFace& d = *drawn[j];
    if (!CGAL::do_overlap(qbox, d.bbox)) continue;
    if (d.kind != kind || d.t != t) {
      PolygonSet shown = rest;
      shown.intersection(d.polygon);
      if (!shown.is_empty()) {
        fail(source, where + ".outline",
             std::string("the hole is not inside ") +
                 (kind == FaceKind::vertical ? "a VFace at depth y = " : "an HFace at height z = ") +
                 format_decimal(edit.t_mm, 3) + " mm");
      }
    }
    rest.difference(d.polygon);
  }
}

// A face made from a hole may reach past the back wall (an HFace with y < 0, i.e. v > t) or
// below the floor (a VFace with z < 0, i.e. v < -t). As with windows in the voxel paper (§2.3)
// that part lies on the back wall or the floor instead, with the same pattern polygon.
ExactFaces placed_faces(const ExactPolygon& q, FaceKind kind, const FT& t, bool from_hole, bool drop,
                        const FaceModelState& sheet) {
  const FT limit = kind == FaceKind::horizontal ? t : -t;
  const bool spills = from_hole && std::any_of(q.vertices_begin(), q.vertices_end(), [&](const ExactPoint& p) {
                        return kind == FaceKind::horizontal ? p.y() > limit : p.y() < limit;
                      });
  if (!spills) return {make_face(kind, t, ExactPolygonWithHoles(q), from_hole, drop)};
  const ExactPolygon stays = kind == FaceKind::horizontal ? rectangle(sheet.min_x, sheet.min_v, sheet.max_x, limit)
                                                          : rectangle(sheet.min_x, limit, sheet.max_x, sheet.max_v);
  std::vector<ExactPolygonWithHoles> kept, moved;
  CGAL::intersection(q, stays, std::back_inserter(kept));
  CGAL::difference(q, stays, std::back_inserter(moved));
  const FaceKind board = kind == FaceKind::horizontal ? FaceKind::vertical : FaceKind::horizontal;
  ExactFaces added;
  for (auto& piece : kept) added.push_back(make_face(kind, t, std::move(piece), true, drop));
  for (auto& piece : moved) added.push_back(make_face(board, 0, std::move(piece), true, drop));
  return added;
}

}  // namespace

// Faces are worked out at most once per state; copies of a model share the result.
struct detail::FaceCache {
  std::once_flag once;
  std::shared_ptr<const FaceModelState> state;
  // Until worked out: the last worked-out state before it and the polygons of the edits since,
  // so the faces come from laying those over it (one Boolean per face they touch).
  std::shared_ptr<const FaceModelState> root;
  ExactFaces added_since;
  std::size_t edits_since = 0;
};

namespace {

// Edits laid over a worked-out state before the whole history is worked out instead: a file
// read edit by edit has no state to start from, an editor's edit a few.
constexpr std::size_t kMaxEditsSince = 64;

}  // namespace

const char* to_string(EditOp op) { return kEditOpNames.name(op).data(); }

FaceModel::FaceModel(double width_mm, double back_mm, double floor_mm) {
  auto s = initial_state(width_mm, back_mm, floor_mm);
  drawn_.push_back(make_face(FaceKind::vertical, 0, ExactPolygonWithHoles(rectangle(s->min_x, 0, s->max_x, s->max_v))));
  drawn_.push_back(
      make_face(FaceKind::horizontal, 0, ExactPolygonWithHoles(rectangle(s->min_x, s->min_v, s->max_x, 0))));
  given_ = drawn_.size();  // the boards do not overlap
  sheet_ = std::move(s);
  changed();
}

void FaceModel::apply(const FaceEdit& edit, const std::string& source, const std::string& where) {
  if (edits_.size() >= kMaxEdits)
    fail(source, where, "a model may have at most " + std::to_string(kMaxEdits) + " edits");
  if (!std::isfinite(edit.t_mm) || edit.t_mm < 0 || edit.t_mm > kMaxFaceCoordinateMm) {
    fail(source, where + ".t",
         "must be from 0 to 100000 mm (a depth in front of the back wall or a height above the floor)");
  }
  const bool vertical_plane = edit.op == EditOp::add_vface || edit.op == EditOp::add_vhole;
  const FT t_exact = exact_nm(edit.t_mm);
  const PatternOutline outline =
      pattern_outline(edit.outline, edit, vertical_plane, t_exact, source, where + ".outline");
  Drawn added;
  guarded(source, where, [&] {
    if (edit.drop && (edit.op == EditOp::add_vface || edit.op == EditOp::add_hface))
      fail(source, where + ".drop", "only an opening's paper drops out (add_vhole, add_hhole)");
    if (!edit.holes.empty()) {
      added = {face_with_holes(edit, outline, vertical_plane, t_exact, *sheet_, source, where)};
      return 0;
    }
    const ExactPolygon q = exact_polygon(outline.ring, source, where + ".outline", outline.exact);
    if (!inside_sheet(q, *sheet_)) fail(source, where + ".outline", "leaves the sheet");
    FaceKind kind = vertical_plane ? FaceKind::vertical : FaceKind::horizontal;
    FT t = t_exact;
    const bool from_hole = edit.op == EditOp::add_vhole || edit.op == EditOp::add_hhole;
    if (from_hole) {
      // The hole becomes the face of the other kind at its lowest z (in a VFace) or nearest y
      // (in an HFace), with the same pattern polygon.
      check_hole_inside(q, kind, t, drawn_, edit, source, where);
      kind = vertical_plane ? FaceKind::horizontal : FaceKind::vertical;
      t = exact_nm(outline.min_second);
    }
    added = placed_faces(q, kind, t, from_hole, edit.drop, *sheet_);
    return 0;
  });
  if (!undone_.empty()) {
    undone_.clear();
    redo_drawn_.clear();
    redo_cache_.clear();
  }
  for (const auto& d : added) drawn_.push_back(d);
  edits_.push_back(edit);
  edit_end_.push_back(drawn_.size());
  std::shared_ptr<FaceCache> before = cache_;
  keep(undo_cache_, cache_);
  changed();
  // An editor asks for the faces after every edit (or every few): then the next state is the
  // last worked-out one with the edits since laid over it, not the whole history worked out
  // again. No reader runs during an edit, so the state is read without the once flag.
  if (before->state) {
    cache_->root = before->state;
    cache_->added_since = std::move(added);
    cache_->edits_since = 1;
  } else if (before->root && before->edits_since < kMaxEditsSince) {
    cache_->root = before->root;
    cache_->added_since = before->added_since;
    cache_->added_since.insert(cache_->added_since.end(), added.begin(), added.end());
    cache_->edits_since = before->edits_since + 1;
  }
}

// The faces of the last few states stay at hand, so stepping back and forth in an editor does
// not work them out again; older states recompute on demand.
void FaceModel::keep(std::vector<std::shared_ptr<FaceCache>>& stack, std::shared_ptr<FaceCache> cache) {
  constexpr std::size_t kKeptStates = 128;  // states share their faces: each costs a vector of pointers
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

void FaceModel::changed() { cache_ = std::make_shared<FaceCache>(); }

const FaceModelState& FaceModel::state() const {
  std::call_once(cache_->once, [&] {
    cache_->state =
        cache_->root ? cover_faces(*cache_->root, cache_->added_since) : work_out_faces(*sheet_, drawn_, given_);
    cache_->root.reset();
    cache_->added_since.clear();
  });
  return *cache_->state;
}

std::string FaceModel::drawn_by(Point2 p) const {
  const FT nm_per_mm(kNmPerMm);
  const ExactPoint q(FT(p.x_mm) * nm_per_mm, FT(p.v_mm) * nm_per_mm);  // doubles convert exactly
  const double x_nm = p.x_mm * kNmPerMm, v_nm = p.v_mm * kNmPerMm;     // for the boxes only
  for (std::size_t j = drawn_.size(); j-- > 0;) {
    const ExactFace& d = *drawn_[j];
    if (x_nm < d.bbox.xmin() || x_nm > d.bbox.xmax() || v_nm < d.bbox.ymin() || v_nm > d.bbox.ymax()) continue;
    if (d.polygon.outer_boundary().bounded_side(q) == CGAL::ON_UNBOUNDED_SIDE) continue;
    if (std::any_of(d.polygon.holes_begin(), d.polygon.holes_end(),
                    [&](const ExactPolygon& h) { return h.bounded_side(q) != CGAL::ON_UNBOUNDED_SIDE; })) {
      continue;
    }
    if (j >= given_) {
      const auto k = std::upper_bound(edit_end_.begin(), edit_end_.end(), j) - edit_end_.begin();
      return "edits[" + std::to_string(k) + "]";
    }
    if (!from_edits_)
      return given_names_ && j < given_names_->size() ? (*given_names_)[j] : "faces[" + std::to_string(j) + "]";
    return j == 0 ? "the back board" : "the floor";
  }
  return "the sheet";
}

void FaceModel::name_given_faces(std::vector<std::string> names) {
  given_names_ = std::make_shared<const std::vector<std::string>>(std::move(names));
}

Rect FaceModel::sheet() const {
  return {{to_mm(sheet_->min_x), to_mm(sheet_->min_v)}, {to_mm(sheet_->max_x), to_mm(sheet_->max_v)}};
}

std::size_t FaceModel::face_count() const { return state().faces.size(); }

std::vector<OAFace> FaceModel::faces() const {
  std::vector<OAFace> out;
  out.reserve(state().faces.size());
  for (const auto& f : state().faces) {
    OAFace o{f->kind, to_mm(f->t), {to_ring(f->polygon.outer_boundary()), {}}, f->opening_paper, f->drops_out};
    for (const ExactPolygon& h : f->polygon.holes()) o.polygon.holes.push_back(to_ring(h));
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace popcut
