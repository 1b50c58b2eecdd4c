// Face-mode design session: items drawn back to front into a live face model, webOAcard's automatic tops, undo and redo
// by item.
#include "popcut/design/face_design.h"

#include <algorithm>
#include <map>
#include <cmath>
#include <tuple>
#include <utility>

#include "popcut/error.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/text.h"

namespace popcut {

namespace {

using Outline = std::vector<std::array<double, 2>>;

EditOp op_of(DesignTool tool) {
  switch (tool) {
    case DesignTool::wall: return EditOp::add_vface;
    case DesignTool::opening: return EditOp::add_vhole;
    case DesignTool::roof: return EditOp::add_hface;
    case DesignTool::roof_opening: return EditOp::add_hhole;
  }
  return EditOp::add_vface;
}

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

bool crosses(const Outline& o, double x) {
  const auto [lo, hi] =
      std::minmax_element(o.begin(), o.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
  return lo != o.end() && (*lo)[0] < x && (*hi)[0] > x;
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

// The face edits one item makes, before tops: its outline (and mirror), or its letters.
// One face edit an item makes; tops are named as such in errors.
struct Step {
  FaceEdit edit;
  bool top = false;
};

void add_tops(std::vector<Step>& steps, const DesignItem& item, const Outline& outline, const std::vector<OAFace>& behind) {
  if (item.tool != DesignTool::wall || !item.top) return;
  for (FaceEdit& top : wall_tops(behind, item.t_mm, outline)) steps.push_back({std::move(top), true});
}

// A ring of set text moved to the item's place, `lift_mm` up from the plane's origin.
Outline placed(const Ring& ring, const DesignItem& item, double lift_mm) {
  const auto& at = item.outline.front();
  // In a roof the plane's second axis is depth y, growing towards the front: letters read from
  // the front lie with their tops towards the back board.
  const double up = item.tool == DesignTool::roof_opening ? -1 : 1;
  Outline o;
  o.reserve(ring.size());
  for (const Point2& p : ring) o.push_back({at[0] + p.x_mm, at[1] + up * (p.v_mm + lift_mm)});
  if (up < 0) std::reverse(o.begin(), o.end());  // the flip would turn the winding over
  return o;
}

// How far a wall of letters' bar reaches above the baseline, per mm of letter height: past the
// round letters' overshoot, so every letter stands on it.
constexpr double kTextBarAboveBaseline = 0.06;
// A framed wall of letters' frame beside and above them, per mm of letter height.
constexpr double kTextFrameMargin = 0.12;

// Letters standing free on their bar: the bar's top runs back as a top the whole length, then
// each letter's flat tops, and the letters are drawn over them all, so a top stays only where no
// letter's paper is (between and inside letters, as in "H", where paper would otherwise be cut
// free). Then the counters are cut back out. Letters close together can still close off paper
// that nothing holds; the pop-up check names it.
void free_letters(std::vector<Step>& steps, const DesignItem& item, const Outline& bar,
                  const std::vector<Outline>& letters, const std::vector<Outline>& counters,
                  const std::vector<OAFace>& behind) {
  steps.push_back({{EditOp::add_vface, item.t_mm, bar}});
  add_tops(steps, item, bar, behind);
  for (const Outline& o : letters) add_tops(steps, item, o, behind);
  for (const Outline& o : letters) steps.push_back({{EditOp::add_vface, item.t_mm, o}});
  for (const Outline& c : counters) steps.push_back({{EditOp::add_vhole, item.t_mm, c}});
}

Ring ring_of(const Outline& o) {
  Ring r;
  r.reserve(o.size());
  for (const auto& p : o) r.push_back({p[0], p[1]});
  return r;
}

Outline outline_of(const Ring& r, double v_offset_mm) {
  Outline o;
  o.reserve(r.size());
  for (const Point2& p : r) o.push_back({p.x_mm, p.v_mm + v_offset_mm});
  return o;
}

// Letters in a frame: a plate from the bar to a margin above the tallest letter and beside the
// first and last, drawn as a wall (its tops are a plain wall's), with the space around the
// letters inside it cut out as openings, and the counters. Every letter then hangs in one rigid
// piece of paper, whatever the font. The space around is the inner box minus the letters,
// worked out by the face model in a scratch card; paper it leaves apart from the letters (the
// dot of an "i", an accent) is cut out with it.
void framed_letters(std::vector<Step>& steps, const DesignItem& item, const Outline& inner, const Outline& plate,
                    const std::vector<Outline>& letters, const std::vector<Outline>& counters, const FaceModel& model,
                    const std::vector<OAFace>& behind, const std::string& where) {
  const Rect sheet = model.sheet();
  FaceModel scratch(sheet.max.x_mm - sheet.min.x_mm, sheet.max.v_mm, -sheet.min.v_mm);
  scratch.apply({EditOp::add_vface, item.t_mm, inner}, "", where);
  for (const Outline& o : letters) scratch.apply({EditOp::add_vface, item.t_mm, o}, "", where);
  std::vector<Ring> rings;
  for (const Outline& o : letters) rings.push_back(ring_of(o));
  add_tops(steps, item, plate, behind);
  steps.push_back({{EditOp::add_vface, item.t_mm, plate}});
  for (const OAFace& f : scratch.faces()) {
    if (f.kind != FaceKind::vertical || f.t_mm != item.t_mm) continue;
    Point2 p = interior_point(f.polygon.outer, f.polygon.holes);
    p.v_mm += item.t_mm;  // the face's sheet v back to the plane's z
    if (std::any_of(rings.begin(), rings.end(), [&](const Ring& r) { return inside_ring(p, r); })) continue;
    steps.push_back({{EditOp::add_vhole, item.t_mm, outline_of(f.polygon.outer, item.t_mm)}});
  }
  for (const Outline& c : counters) steps.push_back({{EditOp::add_vhole, item.t_mm, c}});
}

// Letters: a wall of letters (one line, framed or free, on a bar along the baseline that folds
// to the floor or roof below), or letters cut through a wall or roof, which lose their counters
// with them as a cut "O" does.
std::vector<Step> text_steps(const DesignItem& item, const FaceModel& model, const std::string& where,
                             const std::vector<OAFace>& behind) {
  if (item.tool == DesignTool::roof)
    throw Error(ErrorCode::invalid_input, "", where + ".tool",
                "letters lying in a roof would fall out: cut them through a roof (roof_opening) or stand them on a wall");
  const TextSetting set = set_text(*item.text, kTextToleranceMm, where + ".text");
  const bool wall = item.tool == DesignTool::wall;
  if (wall && set.line_boxes.size() > 1)
    throw Error(ErrorCode::invalid_input, "", where + ".text.string",
                "a wall of letters is one line (its letters stand on one bar): put the next line in a text of its own");
  // `at` is the lower left corner of the whole text, descenders included.
  const double lift = set.descent_mm + set.line_height_mm * static_cast<double>(set.line_boxes.size() - 1);
  std::vector<Step> steps;
  if (!wall) {
    for (const TextShape& s : set.shapes) steps.push_back({{op_of(item.tool), item.t_mm, placed(s.outer, item, lift)}});
    return steps;
  }
  std::vector<Outline> letters, counters;
  for (const TextShape& s : set.shapes) {
    letters.push_back(placed(s.outer, item, lift));
    for (const Ring& h : s.holes) counters.push_back(placed(h, item, lift));
  }
  const Rect& line = set.line_boxes.front();
  const double bottom = -set.descent_mm, bar_top = kTextBarAboveBaseline * item.text->size_mm;
  const auto box = [&](double x0, double v0, double x1, double v1) {
    return placed({{x0, v0}, {x1, v0}, {x1, v1}, {x0, v1}}, item, lift);
  };
  if (!item.text->frame) {
    free_letters(steps, item, box(line.min.x_mm, bottom, line.max.x_mm, bar_top), letters, counters, behind);
    return steps;
  }
  const double margin = kTextFrameMargin * item.text->size_mm;
  framed_letters(steps, item, box(line.min.x_mm, bar_top, line.max.x_mm, line.max.v_mm),
                 box(line.min.x_mm - margin, bottom, line.max.x_mm + margin, line.max.v_mm + margin), letters,
                 counters, model, behind, where);
  return steps;
}

// The face edits an item makes, in the order they are drawn.
std::vector<Step> steps_of(const DesignItem& item, const FaceModel& model, const std::string& where,
                           const std::vector<OAFace>& behind) {
  const double width_mm = model.sheet().max.x_mm - model.sheet().min.x_mm;
  if (item.text) {
    if (item.mirror)
      throw Error(ErrorCode::invalid_input, "", where + ".mirror",
                  "text is not mirrored (it would read backwards): add the text again on the other side");
    return text_steps(item, model, where, behind);
  }
  std::vector<Outline> outlines = {item.outline};
  if (item.mirror) {
    const bool opening = item.tool == DesignTool::opening || item.tool == DesignTool::roof_opening;
    if (opening && crosses(item.outline, width_mm / 2)) {
      throw Error(ErrorCode::invalid_input, "", where + ".outline",
                  "a mirrored opening must lie on one side of the centre line x = " + format_decimal(width_mm / 2, 3) +
                      " mm: draw an opening across it whole, without mirror");
    }
    outlines.push_back(mirrored(item.outline, width_mm));
  }
  std::vector<Step> steps;
  for (const Outline& o : outlines) steps.push_back({{op_of(item.tool), item.t_mm, o}});
  // The tops are found among the faces behind, before the wall is drawn: then the wall and its
  // tops are laid over the model in one step (one Boolean per face they touch).
  for (const Outline& o : outlines) add_tops(steps, item, o, behind);
  return steps;
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
  const std::vector<Step> steps = steps_of(item, model_, where, behind);
  std::size_t applied = 0;
  try {
    for (const Step& step : steps) {
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
