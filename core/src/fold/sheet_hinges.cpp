// A sheet map's creases grouped into straight hinges with their angles, its pieces, and each region's triangles.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <tuple>

#include "io/ascii_case.h"
#include "popcut/error.h"
#include "popcut/fold/sheet_fold.h"
#include "popcut/text.h"

namespace popcut {
namespace {

// Map edges within this of a hinge's line lie on it (the map rounds its points far finer).
constexpr double kOnLineMm = 1e-3;
constexpr int kMaxStages = 100;
constexpr std::size_t kMaxPieceNotes = 20;

bool is_crease(DrawnKind k) { return k == DrawnKind::mountain || k == DrawnKind::valley || k == DrawnKind::fold; }

double length(Point2 a, Point2 b) { return std::hypot(b.x_mm - a.x_mm, b.v_mm - a.v_mm); }

double line_distance(Point2 a, Point2 b, Point2 p) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm;
  return std::abs(dx * (p.v_mm - a.v_mm) - dv * (p.x_mm - a.x_mm)) / std::hypot(dx, dv);
}

Point2 midpoint(Point2 a, Point2 b) { return {(a.x_mm + b.x_mm) / 2, (a.v_mm + b.v_mm) / 2}; }

// Does the selector name this drawn line: its SVG id (or, with a trailing '*', any SVG id that
// starts so), its DXF handle (hexadecimal, either case) or its FOLD edge ("edges[7]")?
bool names_line(const std::string& selector, const DrawnLine& line) {
  const std::string& w = line.where;
  if (w == selector) return true;
  if (!selector.empty() && selector.back() == '*')
    return w.find("id=\"" + selector.substr(0, selector.size() - 1)) != std::string::npos;
  if (w.find("id=\"" + selector + "\"") != std::string::npos) return true;
  const std::string upper = ascii_upper(w), handle = "#" + ascii_upper(selector);
  const auto at = upper.find(handle);
  const auto after = at + handle.size();
  return at != std::string::npos && (after == upper.size() || upper[after] == ' ');
}

struct Turn {
  double angle_deg = 0;
  int stage = 1;
};

// How a drawn crease turns: by its own angle (FOLD), else the default; then as any selector
// naming it says, the last winning. Mountains turn negative, valleys positive.
Turn crease_turn(const DrawnLine& line, const SheetFoldOptions& o, std::vector<bool>& used) {
  Turn turn{line.fold_angle_deg.value_or(o.angle_deg), 1};
  for (std::size_t i = 0; i < o.angles.size(); ++i) {
    const CreaseAngle& c = o.angles[i];
    const auto kind = kDrawnKindNames.find(c.selector);
    if (kind ? *kind != line.kind : !names_line(c.selector, line)) continue;
    used[i] = true;
    turn = {c.angle_deg, c.stage};
  }
  if (line.kind == DrawnKind::mountain) turn.angle_deg = -std::abs(turn.angle_deg);
  if (line.kind == DrawnKind::valley) turn.angle_deg = std::abs(turn.angle_deg);
  return turn;
}

void check_options(const LineDrawing& d, const SheetFoldOptions& o, const SheetMap& map) {
  if (!(o.angle_deg >= 0 && o.angle_deg <= 180))
    throw Error(ErrorCode::invalid_input, d.source, "--crease-angle",
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
  if (o.fixed_region < -1 || o.fixed_region >= static_cast<int>(map.regions.size()))
    throw Error(ErrorCode::invalid_input, d.source, "--fixed",
                "region " + std::to_string(o.fixed_region) + " does not exist: the sheet has " +
                    std::to_string(map.regions.size()) + " regions (0 to " + std::to_string(map.regions.size() - 1) +
                    ")");
}

// The hinges of each pair of regions (lower index first), so an edge finds its own at once.
using HingesByPair = std::map<std::pair<int, int>, std::vector<std::size_t>>;

// Adds the edge to the hinge of its two regions whose line it lies on, or starts one.
void add_to_hinge(FoldableSheet& s, HingesByPair& by_pair, int edge_index, const DrawnLine* line, Turn turn) {
  const double angle = turn.angle_deg;
  const SheetEdge& e = s.map.edges[static_cast<std::size_t>(edge_index)];
  std::vector<std::size_t>& mine = by_pair[{std::min(e.left, e.right), std::max(e.left, e.right)}];
  for (const std::size_t h : mine) {
    SheetHinge& hinge = s.hinges[h];
    if (line_distance(hinge.a, hinge.b, e.a) > kOnLineMm || line_distance(hinge.a, hinge.b, e.b) > kOnLineMm) continue;
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
  mine.push_back(s.hinges.size());
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
  std::vector<std::optional<Turn>> turns(d.lines.size());  // selectors matched once per drawn line
  HingesByPair by_pair;
  for (int i : order) {
    const SheetEdge& e = s.map.edges[static_cast<std::size_t>(i)];
    // A sliver where creases nearly meet has no direction to turn about; its neighbours carry the hinge.
    if (!is_crease(e.kind) || length(e.a, e.b) <= kOnLineMm) continue;
    const bool drawn = e.drawn >= 0 && e.drawn < static_cast<int>(d.lines.size());
    const DrawnLine* line = drawn ? &d.lines[static_cast<std::size_t>(e.drawn)] : nullptr;
    if (line && !turns[static_cast<std::size_t>(e.drawn)])
      turns[static_cast<std::size_t>(e.drawn)] = crease_turn(*line, o, used);
    const Turn turn = line ? *turns[static_cast<std::size_t>(e.drawn)] : Turn{o.angle_deg, 1};
    if (e.left >= 0 && e.right >= 0 && e.left != e.right) {
      add_to_hinge(s, by_pair, i, line, turn);
    } else if (turn.angle_deg != 0 && !(drawn && reported[static_cast<std::size_t>(e.drawn)])) {
      if (drawn) reported[static_cast<std::size_t>(e.drawn)] = true;
      const int r = std::max(e.left, e.right);
      s.problems.push_back({std::string(line ? line->where : "a crease") + ": region " + std::to_string(r) +
                                " lies on both sides of the crease (it ends inside the region, or runs to a hole): "
                                "the paper is joined around it, so nothing can turn about it; it stays flat",
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

// The piece's fixed region: the asked one, else the largest, ties to the one with most hinges
// (a box's base over its lid), then the lowest index, so the choice never depends on the walk.
int fixed_of(const std::vector<int>& members, const SheetFoldOptions& o, const FoldableSheet& s,
             const std::vector<std::vector<int>>& next) {
  int fixed = members.front();
  const auto rank = [&](int r) {
    return std::tuple(s.map.regions[static_cast<std::size_t>(r)].area_mm2, next[static_cast<std::size_t>(r)].size(),
                      -r);
  };
  for (int r : members) {
    if (r == o.fixed_region) return r;
    if (rank(r) > rank(fixed)) fixed = r;
  }
  return fixed;
}

// A region with no hinge that exactly fills another region's hole is what a closed cut takes
// out (a window's waste, FOLD's hole): it falls out of the sheet, so it neither shows nor collides.
bool is_cut_out(const FoldableSheet& s, int r, const std::vector<std::vector<int>>& next) {
  if (!next[static_cast<std::size_t>(r)].empty() || s.map.regions.size() == 1) return false;
  const SheetRegion& me = s.map.regions[static_cast<std::size_t>(r)];
  const Rect box = bounds(me.outer);
  for (const SheetRegion& other : s.map.regions)
    for (const Ring& hole : other.holes)
      if (bounds(hole) == box && std::abs(std::abs(signed_area_mm2(hole)) - me.area_mm2) <= 1e-9 * me.area_mm2)
        return true;
  return false;
}

// Pieces: regions joined through hinges, each with its fixed region; cut-outs fall out.
void find_pieces(const SheetFoldOptions& o, FoldableSheet& s) {
  const int n = static_cast<int>(s.map.regions.size());
  std::vector<std::vector<int>> next(static_cast<std::size_t>(n));
  for (const SheetHinge& h : s.hinges) {
    next[static_cast<std::size_t>(h.left)].push_back(h.right);
    next[static_cast<std::size_t>(h.right)].push_back(h.left);
  }
  s.piece_of.assign(static_cast<std::size_t>(n), -1);
  std::vector<double> piece_area;
  int cut_outs = 0;
  for (int start = 0; start < n; ++start) {
    if (s.piece_of[static_cast<std::size_t>(start)] >= 0) continue;
    const int piece = static_cast<int>(s.piece_fixed.size());
    std::vector<int> members{start};
    s.piece_of[static_cast<std::size_t>(start)] = piece;
    for (std::size_t k = 0; k < members.size(); ++k)
      for (int m : next[static_cast<std::size_t>(members[k])])
        if (s.piece_of[static_cast<std::size_t>(m)] < 0) {
          s.piece_of[static_cast<std::size_t>(m)] = piece;
          members.push_back(m);
        }
    double area = 0;
    for (int r : members) area += s.map.regions[static_cast<std::size_t>(r)].area_mm2;
    s.piece_fixed.push_back(fixed_of(members, o, s, next));
    piece_area.push_back(area);
    if (members.size() == 1 && is_cut_out(s, start, next)) {
      s.cut_out[static_cast<std::size_t>(start)] = true;
      ++cut_outs;
    }
  }
  if (cut_outs)
    s.notes.push_back(std::to_string(cut_outs) + " cut-out(s) fall out of the sheet (the inside of a closed cut)");
  const std::size_t pieces = s.piece_fixed.size() - static_cast<std::size_t>(cut_outs);
  if (pieces < 2) return;
  std::size_t noted = 0;
  for (std::size_t p = 0; p < s.piece_fixed.size(); ++p) {
    const int fixed = s.piece_fixed[p];
    if (s.cut_out[static_cast<std::size_t>(fixed)]) continue;
    if (++noted > kMaxPieceNotes) {
      s.notes.push_back("... and " + std::to_string(pieces - kMaxPieceNotes) + " more pieces cut free");
      break;
    }
    s.notes.push_back("piece " + std::to_string(p) + " (" + format_decimal(piece_area[p], 1) + " mm², around " +
                      describe_place(s.map.regions[static_cast<std::size_t>(fixed)].label) +
                      ") is cut free of the others and folds on its own");
  }
}

}  // namespace

std::optional<CreaseAngle> parse_crease_angle(const std::string& text) {
  const auto eq = text.rfind('=');
  if (eq == std::string::npos || eq == 0) return std::nullopt;
  const std::string turn = text.substr(eq + 1);
  const auto at = turn.find('@');
  const std::string degrees = turn.substr(0, at);
  if (!is_decimal_text(degrees)) return std::nullopt;
  try {
    std::size_t used = 0;
    CreaseAngle c{text.substr(0, eq), std::stod(degrees, &used), 1};
    if (used != degrees.size()) return std::nullopt;
    if (at != std::string::npos) {
      const std::string stage = turn.substr(at + 1);
      if (stage.empty() || stage.find_first_not_of("0123456789") != std::string::npos || stage.size() > 4)
        return std::nullopt;
      c.stage = std::stoi(stage);
    }
    return c;
  } catch (const std::exception&) {
    return std::nullopt;  // out of double's range
  }
}

FoldableSheet make_foldable_sheet(const LineDrawing& d, SheetMap map, const SheetFoldOptions& o) {
  check_options(d, o, map);
  FoldableSheet s;
  s.source = d.source;
  s.map = std::move(map);
  s.cut_out.assign(s.map.regions.size(), false);
  find_hinges(d, o, s);
  find_pieces(o, s);
  for (std::size_t r = 0; r < s.map.regions.size(); ++r)
    s.triangles.push_back(s.cut_out[r] ? std::vector<std::array<Point2, 3>>{}
                                       : triangulate(s.map.regions[r].outer, s.map.regions[r].holes));
  return s;
}

}  // namespace popcut
