// Infers each region's plane from the folds (t_h − t_v = v), the centre fold's place, and checks the result.
#include "popcut/pattern/card_from_sheet.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <unordered_map>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
namespace {

constexpr double kEps = 1e-6;  // mm: far below the 1e-4 mm of written files, far above rounding

Point2 mid(const SheetEdge& e) { return {(e.a.x_mm + e.b.x_mm) / 2, (e.a.v_mm + e.b.v_mm) / 2}; }
bool is_fold(DrawnKind k) { return k == DrawnKind::mountain || k == DrawnKind::valley || k == DrawnKind::fold; }

// A region's plane while the centre fold's height c is unknown: t = a + b·c.
struct Plane {
  bool known = false;
  FaceKind kind = FaceKind::vertical;
  double a = 0;
  int b = 0;
};

class Inference {
 public:
  Inference(const LineDrawing& d, const SheetMap& m) : d_(d), m_(m), planes_(m.regions.size()) {}
  InferredCard run();

 private:
  void conflict(std::string what, Point2 at, std::vector<int> regions, int drawn = -1) {
    out_.conflicts.push_back({std::move(what), at, std::move(regions),
                              drawn >= 0 ? d_.lines[static_cast<std::size_t>(drawn)].where : std::string()});
  }
  Plane& plane(int region) { return planes_[static_cast<std::size_t>(region)]; }
  // A region's offset once the centre fold lies at c: a rounding from zero is zero.
  double offset_mm(int region, double c) {
    const double t = plane(region).a + plane(region).b * c;
    return std::abs(t) < kEps ? 0 : t;
  }
  bool sheet_is_rectangle();
  void anchor_boards();
  void check_edges();
  void propagate();
  void check_pieces();
  void check_folds(double c);
  std::optional<double> solve_centre();
  void build_model(double c);
  void compare_lines(double c);

  const LineDrawing& d_;
  const SheetMap& m_;
  std::vector<Plane> planes_;
  std::vector<std::vector<int>> folds_of_;  // region → indices of its fold edges
  InferredCard out_;
};

bool Inference::sheet_is_rectangle() {
  const Rect& r = m_.bounds;
  const double box = (r.max.x_mm - r.min.x_mm) * (r.max.v_mm - r.min.v_mm);
  const bool on_box = std::all_of(m_.outline.begin(), m_.outline.end(), [&](Point2 p) {
    return std::abs(p.x_mm - r.min.x_mm) < kEps || std::abs(p.x_mm - r.max.x_mm) < kEps ||
           std::abs(p.v_mm - r.min.v_mm) < kEps || std::abs(p.v_mm - r.max.v_mm) < kEps;
  });
  if (on_box && std::abs(signed_area_mm2(m_.outline) - box) < 1e-3) return true;
  conflict("the sheet's edge is not a rectangle: an OA card folds a rectangular sheet (import it with --as sheet)",
           m_.outline.front(), {});
  return false;
}

// The back board is the region holding the most of the sheet's top edge, the floor the one
// holding the most of its bottom edge; other regions on those edges hang from folds like any face
// (the sheet's edge holds nothing, so a notch cut from it is a piece cut free).
void Inference::anchor_boards() {
  std::unordered_map<int, double> top, bottom;
  for (const SheetEdge& e : m_.edges) {
    if ((e.left >= 0) == (e.right >= 0)) continue;
    const int inside = e.left >= 0 ? e.left : e.right;
    const double len = std::abs(e.b.x_mm - e.a.x_mm);
    const auto on = [&](double v) { return std::abs(e.a.v_mm - v) < kEps && std::abs(e.b.v_mm - v) < kEps; };
    if (on(m_.bounds.max.v_mm)) top[inside] += len;
    if (on(m_.bounds.min.v_mm)) bottom[inside] += len;
  }
  const auto most = [](const std::unordered_map<int, double>& m) {
    int best = -1;
    for (const auto& [r, len] : m)
      if (best < 0 || len > m.at(best) || (len == m.at(best) && r < best)) best = r;
    return best;
  };
  const int back = most(top), floor = most(bottom);
  if (back < 0 || floor < 0) return;  // a rectangle always has both edges
  if (back == floor) {
    conflict("one region holds both the sheet's top and bottom edges: no fold separates the back board from the floor",
             m_.regions[static_cast<std::size_t>(back)].label, {back});
    return;
  }
  plane(back) = {true, FaceKind::vertical, 0, 0};
  plane(floor) = {true, FaceKind::horizontal, 0, 0};
}

void Inference::check_edges() {
  folds_of_.assign(m_.regions.size(), {});
  for (std::size_t i = 0; i < m_.edges.size(); ++i) {
    const SheetEdge& e = m_.edges[i];
    if (e.left == e.right && e.left >= 0) {
      conflict(std::string("a ") + to_string(e.kind) +
                   " line ends inside one face (a slit): an OA card's face model has no slits",
               mid(e), {e.left}, e.drawn);
      continue;
    }
    if (!is_fold(e.kind)) continue;
    if (std::abs(e.a.v_mm - e.b.v_mm) > kEps) {
      conflict("a fold not parallel to the centre fold: every fold of an OA card runs along x", mid(e),
               {e.left, e.right}, e.drawn);
      continue;
    }
    folds_of_[static_cast<std::size_t>(e.left)].push_back(static_cast<int>(i));
    folds_of_[static_cast<std::size_t>(e.right)].push_back(static_cast<int>(i));
  }
}

// Walks the fold graph from the boards: across a fold at height v the other face is of the
// other kind, and t_h − t_v = v − c.
void Inference::propagate() {
  std::deque<int> queue;
  for (std::size_t r = 0; r < planes_.size(); ++r)
    if (planes_[r].known) queue.push_back(static_cast<int>(r));
  while (!queue.empty()) {
    const int r = queue.front();
    queue.pop_front();
    const Plane from = plane(r);
    for (const int ei : folds_of_[static_cast<std::size_t>(r)]) {
      const SheetEdge& e = m_.edges[static_cast<std::size_t>(ei)];
      const int other = e.left == r ? e.right : e.left;
      if (plane(other).known) continue;
      const double v = e.a.v_mm - m_.bounds.min.v_mm;
      plane(other) = from.kind == FaceKind::vertical ? Plane{true, FaceKind::horizontal, from.a + v, from.b - 1}
                                                     : Plane{true, FaceKind::vertical, from.a - v, from.b + 1};
      queue.push_back(other);
    }
  }
}

std::optional<double> Inference::solve_centre() {
  std::optional<double> c;
  for (const SheetEdge& e : m_.edges) {  // the first fold whose residual depends on c fixes it
    if (!is_fold(e.kind) || e.left == e.right || std::abs(e.a.v_mm - e.b.v_mm) > kEps) continue;
    const Plane &u = plane(e.left), &l = plane(e.right);
    if (!u.known || !l.known || u.kind == l.kind) continue;
    const Plane &h = u.kind == FaceKind::horizontal ? u : l, &vf = u.kind == FaceKind::horizontal ? l : u;
    const double alpha = h.a - vf.a - (e.a.v_mm - m_.bounds.min.v_mm);
    const int beta = h.b - vf.b + 1;
    if (beta != 0) {
      c = -alpha / beta;
      break;
    }
  }
  if (!c) conflict("no fold joins the back board to the floor: the sheet has no centre fold", m_.outline.front(), {});
  return c;
}

// Each fold once the planes are known: two kinds, planes that meet (t_h − t_v = v), and the
// drawn direction where one was drawn.
void Inference::check_folds(double c) {
  for (const SheetEdge& e : m_.edges) {
    if (!is_fold(e.kind) || e.left == e.right || std::abs(e.a.v_mm - e.b.v_mm) > kEps) continue;
    const Plane &u = plane(e.left), &l = plane(e.right);
    if (!u.known || !l.known) continue;
    const double v = e.a.v_mm - m_.bounds.min.v_mm - c;
    if (u.kind == l.kind) {
      conflict(std::string("a fold between two ") + (u.kind == FaceKind::vertical ? "vertical" : "horizontal") +
                   " faces: folds join a vertical and a horizontal face",
               mid(e), {e.left, e.right}, e.drawn);
      continue;
    }
    const double tu = u.a + u.b * c, tl = l.a + l.b * c;
    const double th = u.kind == FaceKind::horizontal ? tu : tl, tv = u.kind == FaceKind::horizontal ? tl : tu;
    if (std::abs(th - tv - v) > 1e-4) {
      conflict("the faces around this fold disagree: the planes the other folds give them (t_h − t_v = " +
                   format_decimal(th - tv, 3) + " mm) do not meet at the fold's height " + format_decimal(v, 3) + " mm",
               mid(e), {e.left, e.right}, e.drawn);
      continue;
    }
    const DrawnKind made = u.kind == FaceKind::vertical ? DrawnKind::valley : DrawnKind::mountain;
    if (e.kind != DrawnKind::fold && e.kind != made)
      conflict(std::string("drawn as a ") + to_string(e.kind) + " fold, but the card folds it " + to_string(made),
               mid(e), {e.left, e.right}, e.drawn);
  }
}

void Inference::check_pieces() {
  for (std::size_t r = 0; r < planes_.size(); ++r) {
    if (planes_[r].known) continue;
    const SheetRegion& g = m_.regions[r];
    conflict(folds_of_[r].empty()
                 ? "a piece cut free of the sheet (" + format_decimal(g.area_mm2, 1) + " mm²): nothing holds it"
                 : "a piece held by folds to nothing joined to the back board or floor (" +
                       format_decimal(g.area_mm2, 1) + " mm²)",
             g.label, {static_cast<int>(r)});
  }
}

Ring shifted(const Ring& ring, Point2 origin) {
  Ring out;
  out.reserve(ring.size());
  for (const Point2& p : ring) out.push_back({p.x_mm - origin.x_mm, p.v_mm - origin.v_mm});
  return out;
}

void Inference::build_model(double c) {
  const Rect& b = m_.bounds;
  const Point2 origin{b.min.x_mm, b.min.v_mm + c};
  const double width = b.max.x_mm - b.min.x_mm, back = b.max.v_mm - origin.v_mm, floor = c;
  if (!(back > 0) || !(floor > 0)) {
    conflict("the centre fold lies at " + format_decimal(c, 3) + " mm, outside the sheet", m_.outline.front(), {});
    return;
  }
  std::vector<OAFace> faces;
  for (std::size_t r = 0; r < planes_.size(); ++r) {
    const SheetRegion& g = m_.regions[r];
    OAFace f;
    f.kind = planes_[r].kind;
    f.t_mm = offset_mm(static_cast<int>(r), c);
    f.polygon.outer = shifted(g.outer, origin);
    for (const Ring& h : g.holes) f.polygon.holes.push_back(shifted(h, origin));
    faces.push_back(std::move(f));
  }
  out_.model = FaceModel::from_subdivision(width, back, floor, faces, d_.source, m_.vertices_on_grid);
  out_.centre_fold_v_mm = c;
  compare_lines(c);
}

// Whole nanometres, as FaceModel holds every coordinate and offset (from_subdivision rounds so).
long long nm(double mm) { return std::llround(mm * 1e6); }

// Each drawn line between two regions against the line the card has there, typed by the rule
// make_pattern types a face model's lines with, on the nanometre values the model holds: no line
// inside one plane (the paper is one piece there), a fold where a vertical and a horizontal face
// meet along x at the edge's height (t_h − t_v = v exactly: a fold the drawing's 1e-4 mm let pass
// but the model's planes miss is a cut), else a cut. The map's edges are the model's face
// boundaries, so this is the model's pattern, compared edge by edge without making it.
void Inference::compare_lines(double c) {
  const double origin_v = m_.bounds.min.v_mm + c;
  for (const SheetEdge& e : m_.edges) {
    if (e.left < 0 || e.right < 0 || e.left == e.right) continue;
    const Plane &u = plane(e.left), &l = plane(e.right);
    const long long tu = nm(offset_mm(e.left, c)), tl = nm(offset_mm(e.right, c));
    const long long v = nm(e.a.v_mm - origin_v);
    const bool along_x = v == nm(e.b.v_mm - origin_v);
    const long long th = u.kind == FaceKind::horizontal ? tu : tl, tv = u.kind == FaceKind::horizontal ? tl : tu;
    const LineKind upper = u.kind == FaceKind::vertical ? LineKind::valley : LineKind::mountain;
    const bool one_plane = u.kind == l.kind && tu == tl;
    const LineKind card = along_x && u.kind != l.kind && th - tv == v ? upper : LineKind::cut;
    const LineKind drawn = is_fold(e.kind) ? upper : LineKind::cut;
    if (one_plane)
      conflict(std::string("a drawn ") + to_string(drawn) +
                   " line the card does not have: the faces on its two sides lie in one plane (a slit or a stray line)",
               mid(e), {e.left, e.right}, e.drawn);
    else if (card != drawn && card == LineKind::cut)
      conflict(std::string("a drawn ") + to_string(drawn) +
                   " fold the card cuts: its faces' planes miss each other by " +
                   std::to_string(std::llabs(th - tv - v)) + " nm at its height",
               mid(e), {e.left, e.right}, e.drawn);
    else if (card != drawn)
      conflict(
          std::string("the card needs a ") + to_string(card) + " line here that the drawing lacks (drawn as a cut)",
          mid(e), {e.left, e.right}, e.drawn);
  }
}

InferredCard Inference::run() {
  if (!sheet_is_rectangle()) return std::move(out_);
  anchor_boards();
  check_edges();
  propagate();
  check_pieces();
  const std::optional<double> c = solve_centre();
  if (c) check_folds(*c);
  if (c && out_.conflicts.empty()) build_model(*c);
  if (!out_.conflicts.empty()) out_.model.reset();
  return std::move(out_);
}

}  // namespace

InferredCard infer_card(const LineDrawing& drawing, const SheetMap& map) { return Inference(drawing, map).run(); }

CardConflictError::CardConflictError(const std::string& source, const InferredCard& card)
    : Error(ErrorCode::invalid_input, source, card.conflicts.empty() ? "" : card.conflicts.front().drawn,
            "no OA card folds from this sheet:\n" + describe_conflicts(card)),
      conflicts_(card.conflicts) {}

CardImport import_card(const std::string& path, const DrawingOptions& drawing, const SheetMapOptions& map) {
  CardImport out;
  out.drawing = load_drawing(path, drawing);
  if (path == "-") out.drawing.source = "<stdin>";
  out.map = build_sheet_map(out.drawing, map);
  out.card = infer_card(out.drawing, out.map);
  return out;
}

std::string describe_conflicts(const InferredCard& card, std::size_t max) {
  std::string out;
  for (std::size_t i = 0; i < card.conflicts.size() && i < max; ++i) {
    const CardConflict& c = card.conflicts[i];
    out += (i ? "\n" : "") + std::string("at (") + format_decimal(c.at.x_mm, 3) + ", " + format_decimal(c.at.v_mm, 3) +
           ") mm" + (c.drawn.empty() ? "" : ", " + c.drawn) + ": " + c.what;
  }
  if (card.conflicts.size() > max) out += "\n… and " + std::to_string(card.conflicts.size() - max) + " more";
  return out;
}

}  // namespace popcut
