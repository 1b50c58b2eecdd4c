// A sheet map's creases grouped into straight hinges with their angles, its pieces, and each region's triangles.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "popcut/error.h"
#include "popcut/fold/sheet_fold.h"
#include "popcut/text.h"

namespace popcut {
namespace {

// Map edges within this of a hinge's line lie on it (the map rounds its points far finer).
constexpr double kOnLineMm = 1e-3;
constexpr int kMaxStages = 100;

bool is_crease(DrawnKind k) { return k == DrawnKind::mountain || k == DrawnKind::valley || k == DrawnKind::fold; }

double length(Point2 a, Point2 b) { return std::hypot(b.x_mm - a.x_mm, b.v_mm - a.v_mm); }

double line_distance(Point2 a, Point2 b, Point2 p) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm;
  return std::abs(dx * (p.v_mm - a.v_mm) - dv * (p.x_mm - a.x_mm)) / std::hypot(dx, dv);
}

Point2 midpoint(Point2 a, Point2 b) { return {(a.x_mm + b.x_mm) / 2, (a.v_mm + b.v_mm) / 2}; }

// Does the selector name this drawn line: its SVG id, its DXF handle or its FOLD edge, or with
// a trailing '*' any id that starts so?
bool names_line(const std::string& selector, const DrawnLine& line) {
  const std::string& w = line.where;
  if (!selector.empty() && selector.back() == '*')
    return w.find("id=\"" + selector.substr(0, selector.size() - 1)) != std::string::npos;
  if (w.find("id=\"" + selector + "\"") != std::string::npos) return true;
  if (w.rfind(selector, 0) == 0 && (w.size() == selector.size() || w[selector.size()] == ' ')) return true;
  const auto handle = w.find("#" + selector);
  const auto after = handle + selector.size() + 1;
  return handle != std::string::npos && (after == w.size() || w[after] == ' ');
}

struct Turn {
  double angle_deg = 0;
  int stage = 1;
};

// How a drawn crease turns: by its own angle (FOLD), else the default; then as any selector
// naming it says, the last winning. Mountains turn negative, valleys positive.
Turn crease_turn(const DrawnLine& line, const SheetFoldOptions& o, std::vector<bool>& used) {
  Turn turn{line.fold_angle_deg.value_or(line.kind == DrawnKind::mountain ? -o.angle_deg : o.angle_deg), 1};
  bool signed_by_user = line.fold_angle_deg.has_value();
  for (std::size_t i = 0; i < o.angles.size(); ++i) {
    const CreaseAngle& c = o.angles[i];
    const auto kind = kDrawnKindNames.find(c.selector);
    if (kind ? *kind != line.kind : !names_line(c.selector, line)) continue;
    used[i] = true;
    turn = {c.angle_deg, c.stage};
    signed_by_user = true;
  }
  if (line.kind == DrawnKind::mountain && (!signed_by_user || turn.angle_deg > 0))
    turn.angle_deg = -std::abs(turn.angle_deg);
  if (line.kind == DrawnKind::valley) turn.angle_deg = std::abs(turn.angle_deg);
  return turn;
}

void check_options(const LineDrawing& d, const SheetFoldOptions& o, const SheetMap& map) {
  if (!(o.angle_deg >= 0 && o.angle_deg <= 180))
    throw Error(ErrorCode::invalid_input, d.source, "--angle",
                "the crease angle must be from 0 to 180 degrees, not " + format_significant(o.angle_deg, 15));
  for (const CreaseAngle& c : o.angles) {
    if (!(std::abs(c.angle_deg) <= 180))
      throw Error(ErrorCode::invalid_input, d.source, "--fold",
                  "\"" + c.selector + "\": the angle must be from -180 to 180 degrees, not " +
                      format_significant(c.angle_deg, 15));
    if (c.stage < 1 || c.stage > kMaxStages)
      throw Error(ErrorCode::invalid_input, d.source, "--fold",
                  "\"" + c.selector + "\": the stage must be from 1 to " + std::to_string(kMaxStages) + ", not " +
                      std::to_string(c.stage));
  }
  if (o.fixed_region >= static_cast<int>(map.regions.size()))
    throw Error(ErrorCode::invalid_input, d.source, "--fixed",
                "region " + std::to_string(o.fixed_region) + " does not exist: the sheet has " +
                    std::to_string(map.regions.size()) + " regions (0 to " + std::to_string(map.regions.size() - 1) +
                    ")");
}

// Adds the edge to the hinge of its two regions whose line it lies on, or starts one.
void add_to_hinge(FoldableSheet& s, int edge_index, const DrawnLine* line, Turn turn) {
  const double angle = turn.angle_deg;
  const SheetEdge& e = s.map.edges[static_cast<std::size_t>(edge_index)];
  for (std::size_t h = 0; h < s.hinges.size(); ++h) {
    SheetHinge& hinge = s.hinges[h];
    const bool same_pair =
        (hinge.left == e.left && hinge.right == e.right) || (hinge.left == e.right && hinge.right == e.left);
    if (!same_pair || line_distance(hinge.a, hinge.b, e.a) > kOnLineMm ||
        line_distance(hinge.a, hinge.b, e.b) > kOnLineMm)
      continue;
    hinge.edges.push_back(edge_index);
    if (std::abs(hinge.angle_deg - angle) > 1e-9 || hinge.kind != e.kind || hinge.stage != turn.stage)
      s.problems.push_back({"one hinge is drawn with two kinds or angles (" + std::string(to_string(hinge.kind)) + " " +
                                format_significant(hinge.angle_deg, 6) + "° and " + to_string(e.kind) + " " +
                                format_significant(angle, 6) + "°, " + (line ? line->where : "?") +
                                "): it folds by the first",
                            midpoint(e.a, e.b),
                            {e.left, e.right},
                            {static_cast<int>(h)}});
    // The hinge spans all of its edges, along its own line.
    const double dx = hinge.b.x_mm - hinge.a.x_mm, dv = hinge.b.v_mm - hinge.a.v_mm;
    const double len2 = dx * dx + dv * dv;
    for (Point2 p : {e.a, e.b}) {
      const double t = ((p.x_mm - hinge.a.x_mm) * dx + (p.v_mm - hinge.a.v_mm) * dv) / len2;
      if (t < 0) hinge.a = p;
      if (t > 1) hinge.b = p;
    }
    return;
  }
  s.hinges.push_back({e.left, e.right, e.a, e.b, e.kind, angle, turn.stage, {edge_index}, line ? line->where : ""});
}

void find_hinges(const LineDrawing& d, const SheetFoldOptions& o, FoldableSheet& s) {
  std::vector<int> order(s.map.edges.size());
  std::iota(order.begin(), order.end(), 0);
  // Longest first, so each hinge's line comes from its best-conditioned edge.
  std::stable_sort(order.begin(), order.end(), [&](int i, int j) {
    const SheetEdge &a = s.map.edges[static_cast<std::size_t>(i)], &b = s.map.edges[static_cast<std::size_t>(j)];
    return length(a.a, a.b) > length(b.a, b.b);
  });
  std::vector<bool> used(o.angles.size(), false);
  std::vector<bool> reported(d.lines.size(), false);
  for (int i : order) {
    const SheetEdge& e = s.map.edges[static_cast<std::size_t>(i)];
    if (!is_crease(e.kind)) continue;
    const bool drawn = e.drawn >= 0 && e.drawn < static_cast<int>(d.lines.size());
    const DrawnLine* line = drawn ? &d.lines[static_cast<std::size_t>(e.drawn)] : nullptr;
    const Turn turn = line ? crease_turn(*line, o, used) : Turn{};
    if (e.left >= 0 && e.right >= 0 && e.left != e.right) {
      add_to_hinge(s, i, line, turn);
    } else if (turn.angle_deg != 0 && !(drawn && reported[static_cast<std::size_t>(e.drawn)])) {
      if (drawn) reported[static_cast<std::size_t>(e.drawn)] = true;
      const int r = std::max(e.left, e.right);
      s.problems.push_back({std::string(line ? line->where : "a crease") + ": the crease ends inside region " +
                                std::to_string(r) +
                                " (it does not cross it from edge to edge), so the region cannot turn about it; it "
                                "stays flat",
                            midpoint(e.a, e.b),
                            {r},
                            {}});
    }
  }
  for (std::size_t i = 0; i < used.size(); ++i)
    if (!used[i])
      throw Error(ErrorCode::invalid_input, d.source, "--fold",
                  "\"" + o.angles[i].selector + "\" names no crease of the drawing (give a line's id, DXF handle, " +
                      "FOLD edge such as edges[3], ids by prefix such as tab-*, or mountain, valley or fold)");
}

// Pieces: regions joined through hinges; each piece's fixed region is the asked one or its largest.
void find_pieces(const SheetFoldOptions& o, FoldableSheet& s) {
  const int n = static_cast<int>(s.map.regions.size());
  std::vector<std::vector<int>> next(static_cast<std::size_t>(n));
  for (const SheetHinge& h : s.hinges) {
    next[static_cast<std::size_t>(h.left)].push_back(h.right);
    next[static_cast<std::size_t>(h.right)].push_back(h.left);
  }
  s.piece_of.assign(static_cast<std::size_t>(n), -1);
  for (int start = 0; start < n; ++start) {
    if (s.piece_of[static_cast<std::size_t>(start)] >= 0) continue;
    const int piece = static_cast<int>(s.piece_fixed.size());
    std::vector<int> stack{start};
    s.piece_of[static_cast<std::size_t>(start)] = piece;
    int fixed = start;
    while (!stack.empty()) {
      const int r = stack.back();
      stack.pop_back();
      const auto area = [&](int k) { return s.map.regions[static_cast<std::size_t>(k)].area_mm2; };
      if (r == o.fixed_region || (fixed != o.fixed_region && area(r) > area(fixed))) fixed = r;
      for (int m : next[static_cast<std::size_t>(r)])
        if (s.piece_of[static_cast<std::size_t>(m)] < 0) {
          s.piece_of[static_cast<std::size_t>(m)] = piece;
          stack.push_back(m);
        }
    }
    s.piece_fixed.push_back(fixed);
  }
  if (s.piece_fixed.size() > 1) {
    for (std::size_t p = 0; p < s.piece_fixed.size(); ++p) {
      double area = 0;
      for (int r = 0; r < n; ++r)
        if (s.piece_of[static_cast<std::size_t>(r)] == static_cast<int>(p))
          area += s.map.regions[static_cast<std::size_t>(r)].area_mm2;
      const SheetRegion& fixed = s.map.regions[static_cast<std::size_t>(s.piece_fixed[p])];
      s.notes.push_back("piece " + std::to_string(p) + " (" + format_decimal(area, 1) + " mm², around " +
                        describe_place(fixed.label) + ") is cut free of the others and folds on its own");
    }
  }
}

}  // namespace

FoldableSheet make_foldable_sheet(const LineDrawing& d, SheetMap map, const SheetFoldOptions& o) {
  check_options(d, o, map);
  FoldableSheet s;
  s.source = d.source;
  s.map = std::move(map);
  find_hinges(d, o, s);
  find_pieces(o, s);
  for (const SheetRegion& r : s.map.regions) s.triangles.push_back(triangulate(r.outer, r.holes));
  return s;
}

}  // namespace popcut
