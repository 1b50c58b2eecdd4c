// Face-mode design session: items drawn back to front into a live face model, webOAcard's automatic tops, undo and redo
// by item.
#include "popcut/design/face_design.h"

#include <algorithm>
#include <map>
#include <cmath>
#include <tuple>
#include <utility>

#include "design/design_steps.h"
#include "popcut/error.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/text.h"

namespace popcut {

namespace {

using Outline = std::vector<std::array<double, 2>>;

// Where an item goes in drawing order: walls and their openings by depth, roofs and their
// openings by their front edge (largest y), each after the walls at that depth.
// Items of one key keep the order they were added in (their ids), so undoing a removal puts an
// item back exactly where it was.
std::tuple<double, int, std::uint64_t> order_key(const DesignItem& item, std::uint64_t id) {
  if (item.tool == DesignTool::wall || item.tool == DesignTool::opening)
    return {item.t_mm, item.tool == DesignTool::wall ? 0 : 1, id};
  double front = 0;
  for (const auto& p : item.outline) front = std::max(front, std::isfinite(p[1]) ? p[1] : 0.0);
  return {front, item.tool == DesignTool::roof ? 2 : 3, id};
}

double signed_area(const Outline& o) {
  double a = 0;
  for (std::size_t i = 0; i < o.size(); ++i) {
    const auto& p = o[i];
    const auto& q = o[(i + 1) % o.size()];
    a += p[0] * q[1] - q[0] * p[1];
  }
  return a / 2;
}

struct Stretch {
  double x0, x1, depth;
};

// Where the line v = c crosses the rings of a face: the x-intervals inside it (even-odd).
void crossings(const OAFace& f, double c, double depth, std::vector<Stretch>& out) {
  std::vector<double> xs;
  const auto ring = [&](const Ring& r) {
    for (std::size_t i = 0; i < r.size(); ++i) {
      const Point2& p = r[i];
      const Point2& q = r[(i + 1) % r.size()];
      if ((p.v_mm > c) == (q.v_mm > c)) continue;
      xs.push_back(p.x_mm + (c - p.v_mm) * (q.x_mm - p.x_mm) / (q.v_mm - p.v_mm));
    }
  };
  ring(f.polygon.outer);
  for (const Ring& h : f.polygon.holes) ring(h);
  std::sort(xs.begin(), xs.end());
  for (std::size_t i = 0; i + 1 < xs.size(); i += 2) out.push_back({xs[i], xs[i + 1], depth});
}

// One top edge at height h over [x0, x1]: the stretches of x and the depth each runs back to.
std::vector<Stretch> stops_behind(const std::vector<OAFace>& faces, double t_mm, double h, double x0, double x1) {
  // Just above the edge, off the 1 nm grid every vertex lies on, so no vertex sits on the probe.
  constexpr double kAboveMm = 0.25e-6;
  std::vector<Stretch> cover;
  for (const OAFace& f : faces) {
    if (f.kind != FaceKind::vertical || f.t_mm >= t_mm) continue;
    crossings(f, h + kAboveMm - f.t_mm, f.t_mm, cover);
  }
  std::vector<double> cuts = {x0, x1};
  for (const Stretch& s : cover) {
    if (s.x0 > x0 && s.x0 < x1) cuts.push_back(s.x0);
    if (s.x1 > x0 && s.x1 < x1) cuts.push_back(s.x1);
  }
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  std::vector<Stretch> out;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double mid = (cuts[i] + cuts[i + 1]) / 2;
    double depth = -1;
    for (const Stretch& s : cover) {
      if (s.x0 < mid && mid < s.x1) depth = std::max(depth, s.depth);
    }
    if (depth < 0) continue;  // nothing behind to hold a top
    if (!out.empty() && out.back().x1 == cuts[i] && out.back().depth == depth)
      out.back().x1 = cuts[i + 1];
    else
      out.push_back({cuts[i], cuts[i + 1], depth});
  }
  return out;
}

}  // namespace

Outline mirrored(const Outline& outline, double width_mm) {
  Outline out(outline.rbegin(), outline.rend());  // reflection reverses the winding: read backwards
  for (auto& p : out) p[0] = width_mm - p[0];
  return out;
}

std::vector<FaceEdit> wall_tops(const FaceModel& model, double t_mm, const Outline& outline) {
  return wall_tops(model.faces(), t_mm, outline);
}

std::vector<FaceEdit> wall_tops(const std::vector<OAFace>& faces, double t_mm, const Outline& outline) {
  if (outline.size() < 3) return {};
  Outline ccw = outline;
  if (signed_area(ccw) < 0) std::reverse(ccw.begin(), ccw.end());
  std::vector<FaceEdit> tops;
  for (std::size_t i = 0; i < ccw.size(); ++i) {
    const auto& a = ccw[i];
    const auto& b = ccw[(i + 1) % ccw.size()];
    // Counter-clockwise, an edge running towards -x has the wall below it: a top edge.
    if (a[1] != b[1] || b[0] >= a[0] || a[1] <= 0) continue;
    for (const Stretch& s : stops_behind(faces, t_mm, a[1], b[0], a[0])) {
      tops.push_back({EditOp::add_hface, a[1], {{s.x0, s.depth}, {s.x1, s.depth}, {s.x1, t_mm}, {s.x0, t_mm}}});
    }
  }
  return tops;
}

FaceDesign::FaceDesign(double width_mm, double back_mm, double floor_mm)
    : width_mm_(width_mm), model_(width_mm, back_mm, floor_mm) {}

std::size_t FaceDesign::draw(const DesignItem& item, const std::string& where, const std::vector<OAFace>& behind) {
  const std::vector<detail::Step> steps = detail::steps_of(item, model_, where, behind);
  std::size_t applied = 0;
  try {
    for (const detail::Step& step : steps) {
      model_.apply(step.edit, "",
                   step.top ? where + " (its top face at z = " + format_decimal(step.edit.t_mm, 3) + " mm)" : where);
      ++applied;
    }
  } catch (...) {
    for (std::size_t k = 0; k < applied; ++k) model_.undo();
    throw;
  }
  return applied;
}

std::size_t FaceDesign::position_for(const Placed& placed) const {
  const auto key = order_key(placed.item, placed.id);
  std::size_t pos = placed_.size();
  while (pos > 0 && key < order_key(placed_[pos - 1].item, placed_[pos - 1].id)) --pos;
  return pos;
}

std::size_t FaceDesign::edits_before(std::size_t pos) const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < pos; ++i) n += placed_[i].edits;
  return n;
}

namespace {

// The x ranges an item's faces (and its mirror's, and its tops) cover: pattern x is card x, so
// an edit changes no face outside them.
std::vector<std::array<double, 2>> x_ranges(const DesignItem& item, double width_mm) {
  if (item.text) return {{0, width_mm}};  // its letters' extent is known only once they are set
  double lo = item.outline.front()[0], hi = lo;
  for (const auto& p : item.outline) {
    lo = std::min(lo, p[0]);
    hi = std::max(hi, p[0]);
  }
  if (!item.mirror) return {{lo, hi}};
  return {{lo, hi}, {width_mm - hi, width_mm - lo}};
}

bool overlaps(const std::vector<std::array<double, 2>>& a, const std::vector<std::array<double, 2>>& b) {
  constexpr double kTouchMm = 1e-6;  // touching ranges count: a shared edge may change a face's boundary
  for (const auto& r : a) {
    for (const auto& q : b) {
      if (r[0] <= q[1] + kTouchMm && q[0] <= r[1] + kTouchMm) return true;
    }
  }
  return false;
}

}  // namespace

// Takes back every face edit from item `pos` on and draws `tail` there instead; on failure puts
// the old items back (they drew before, so they draw again) and rethrows. `name_of(i)` names
// tail[i] in errors.
//
// A wall's tops are read off the faces behind it. Those faces are read once and reused for the
// next walls as long as nothing drawn since covers any x of theirs: faces at an x depend only
// on the polygons at that x. Redrawing (or reading) a street of walls then reads the faces a few
// times instead of once per wall, and gives the same edits as drawing the items one by one.
void FaceDesign::redraw_from(std::size_t pos, std::vector<Placed> tail,
                             const std::function<std::string(std::size_t)>& name_of) {
  const std::size_t keep = edits_before(pos);
  model_redo_depth_ = 0;  // applying anything, even on the way to a failure, clears the model's redo
  std::vector<Placed> old(placed_.begin() + static_cast<std::ptrdiff_t>(pos), placed_.end());
  const auto back_to = [&] {
    while (model_.edits().size() > keep) model_.undo();
    placed_.resize(pos);
  };
  back_to();
  last_work_ = 0;
  std::vector<OAFace> behind;
  bool read = false;
  std::vector<std::array<double, 2>> since;  // x ranges drawn after `behind` was read
  const auto faces_for = [&](const DesignItem& item) -> const std::vector<OAFace>& {
    if (item.tool != DesignTool::wall || !item.top) return behind;
    const auto ranges = x_ranges(item, width_mm_);
    if (!read || overlaps(since, ranges)) {
      behind = model_.faces();
      read = true;
      since.clear();
    }
    return behind;
  };
  try {
    for (std::size_t i = 0; i < tail.size(); ++i) {
      tail[i].edits = draw(tail[i].item, name_of(i), faces_for(tail[i].item));
      const auto ranges = x_ranges(tail[i].item, width_mm_);
      since.insert(since.end(), ranges.begin(), ranges.end());
      last_work_ += tail[i].edits;
      placed_.push_back(std::move(tail[i]));
    }
  } catch (...) {
    back_to();
    for (Placed& p : old) {
      p.edits = draw(p.item, "item " + std::to_string(p.id), model_.faces());
      placed_.push_back(std::move(p));
    }
    changed();
    throw;
  }
  changed();
}

std::string FaceDesign::default_name(const Placed& p) {
  return "the " + std::string(kDesignToolNames.name(p.item.tool)) + " drawn as item " + std::to_string(p.id);
}

void FaceDesign::insert(std::size_t pos, Placed placed, const std::string& where) {
  std::vector<Placed> tail = {std::move(placed)};
  tail.insert(tail.end(), placed_.begin() + static_cast<std::ptrdiff_t>(pos), placed_.end());
  redraw_from(pos, tail, [&](std::size_t i) { return i == 0 ? where : default_name(tail[i]); });
}

void FaceDesign::erase(std::size_t pos) {
  std::vector<Placed> tail(placed_.begin() + static_cast<std::ptrdiff_t>(pos) + 1, placed_.end());
  redraw_from(pos, tail, [&](std::size_t i) { return default_name(tail[i]); });
}

void FaceDesign::add(const DesignItem& item, const std::string& where) {
  if (placed_.size() >= kMaxDesignItems)
    throw Error(ErrorCode::limit, "", where, "a design may have at most " + std::to_string(kMaxDesignItems) + " items");
  Placed placed{next_id_, item, 0};
  insert(position_for(placed), placed, where);
  ++next_id_;
  undo_.push_back({true, std::move(placed)});
  redo_.clear();
  model_redo_depth_ = 0;
}

void FaceDesign::add_all(const std::vector<DesignItem>& items, const std::vector<std::string>& where,
                         const std::vector<std::uint64_t>& ids) {
  if (placed_.size() + items.size() > kMaxDesignItems)
    throw Error(ErrorCode::limit, "", "items",
                "a design may have at most " + std::to_string(kMaxDesignItems) + " items");
  // The order adding them one by one would give: by key, ties in the order given (ids rise).
  std::vector<Placed> tail(placed_.begin(), placed_.end());
  const std::uint64_t first = next_id_;
  const std::uint64_t given_from = ids.empty() ? 0 : *std::min_element(ids.begin(), ids.end());
  if (!ids.empty() && (ids.size() != items.size() || given_from < first))
    throw Error(ErrorCode::invalid_input, "", "items", "item ids must be new, one per item");
  std::map<std::uint64_t, std::string> named;  // id -> where
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::uint64_t id = ids.empty() ? next_id_ : ids[i];
    if (!named.emplace(id, i < where.size() ? where[i] : "item").second)
      throw Error(ErrorCode::invalid_input, "", i < where.size() ? where[i] + ".id" : "id",
                  "repeats an earlier item's id");
    tail.push_back({id, items[i], 0});
    next_id_ = std::max(next_id_, id + 1);
  }
  std::stable_sort(tail.begin(), tail.end(),
                   [](const Placed& a, const Placed& b) { return order_key(a.item, a.id) < order_key(b.item, b.id); });
  try {
    redraw_from(0, tail, [&](std::size_t i) {
      const auto it = named.find(tail[i].id);
      return it != named.end() ? it->second : default_name(tail[i]);
    });
  } catch (...) {
    next_id_ = first;
    throw;
  }
  for (const auto& entry : named) {
    const std::uint64_t id = entry.first;  // a lambda may not capture a structured binding (clang)
    const auto it = std::find_if(placed_.begin(), placed_.end(), [&](const Placed& p) { return p.id == id; });
    undo_.push_back({true, *it});
  }
  redo_.clear();
  model_redo_depth_ = 0;
}

bool FaceDesign::remove(std::uint64_t id) {
  const auto it = std::find_if(placed_.begin(), placed_.end(), [&](const Placed& p) { return p.id == id; });
  if (it == placed_.end()) return false;
  Placed gone = *it;
  erase(static_cast<std::size_t>(it - placed_.begin()));
  undo_.push_back({false, std::move(gone)});
  redo_.clear();
  model_redo_depth_ = 0;
  return true;
}

void FaceDesign::clear_history() {
  undo_.clear();
  redo_.clear();
  model_redo_depth_ = 0;
}

bool FaceDesign::undo() {
  if (undo_.empty()) return false;
  Action a = undo_.back();
  if (a.added) {
    const auto it = std::find_if(placed_.begin(), placed_.end(), [&](const Placed& p) { return p.id == a.placed.id; });
    const bool last = it + 1 == placed_.end();
    const std::size_t depth = model_redo_depth_;
    a.placed.edits = it->edits;
    erase(static_cast<std::size_t>(it - placed_.begin()));
    // The last item's edits were only taken back: the model can redo them as they were.
    if (last) model_redo_depth_ = depth + 1;
  } else {
    insert(position_for(a.placed), a.placed, "undo");
    model_redo_depth_ = 0;
  }
  undo_.pop_back();
  redo_.push_back(std::move(a));
  return true;
}

bool FaceDesign::redo() {
  if (redo_.empty()) return false;
  Action a = redo_.back();
  if (a.added && model_redo_depth_ > 0 && position_for(a.placed) == placed_.size()) {
    // Back in front of everything, over the same faces: the model's own redo restores the kept
    // state instead of drawing the item again.
    for (std::size_t k = 0; k < a.placed.edits; ++k) {
      if (!model_.redo())
        throw Error(ErrorCode::internal, "", "redo", "the face model has fewer edits to redo than the item made");
    }
    placed_.push_back(a.placed);
    last_work_ = a.placed.edits;
    --model_redo_depth_;
    changed();
  } else if (a.added) {
    insert(position_for(a.placed), a.placed, "redo");
    model_redo_depth_ = 0;
  } else {
    model_redo_depth_ = 0;
    const auto it = std::find_if(placed_.begin(), placed_.end(), [&](const Placed& p) { return p.id == a.placed.id; });
    erase(static_cast<std::size_t>(it - placed_.begin()));
  }
  redo_.pop_back();
  undo_.push_back(std::move(a));
  return true;
}

void FaceDesign::changed() { have_view_ = false; }

const Pattern& FaceDesign::pattern() const {
  if (!have_view_) {
    pattern_ = make_pattern(model_);
    report_ = check_popup(pattern_);
    have_view_ = true;
  }
  return pattern_;
}

const PopupReport& FaceDesign::report() const {
  pattern();
  return report_;
}

}  // namespace popcut
