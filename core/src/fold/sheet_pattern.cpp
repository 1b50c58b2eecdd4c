// A folding sheet's lines as a pattern for the planner: cuts and scores, collinear pieces joined into maximal lines.
#include <cmath>
#include <map>

#include "popcut/fold/sheet_fold.h"

namespace popcut {
namespace {

using Key = std::pair<long long, long long>;

// Points the map made equal are equal to the last bit; a micrometre grid keys them.
Key key_of(Point2 p) { return {std::llround(p.x_mm * 1e6), std::llround(p.v_mm * 1e6)}; }

bool collinear_through(const Segment& s, const Segment& t, Point2 shared) {
  const Point2 a = s.a == shared ? s.b : s.a, b = t.a == shared ? t.b : t.a;
  const double ux = shared.x_mm - a.x_mm, uv = shared.v_mm - a.v_mm;
  const double wx = b.x_mm - shared.x_mm, wv = b.v_mm - shared.v_mm;
  const double cross = ux * wv - uv * wx, dot = ux * wx + uv * wv;
  return dot > 0 && std::abs(cross) <= 1e-9 * std::hypot(ux, uv) * std::hypot(wx, wv);
}

// Joins two pieces of one kind meeting end to end in a straight line, where nothing else meets.
std::vector<Segment> maximal(std::vector<Segment> pieces) {
  bool joined = true;
  while (joined) {
    joined = false;
    std::map<Key, std::vector<std::size_t>> at;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      at[key_of(pieces[i].a)].push_back(i);
      at[key_of(pieces[i].b)].push_back(i);
    }
    // A piece joined in this pass sits out the rest of it: its ends in `at` are stale. Runs of
    // pieces halve each pass, so passes are few.
    std::vector<bool> gone(pieces.size(), false), touched(pieces.size(), false);
    for (const auto& [key, ids] : at) {
      if (ids.size() != 2 || touched[ids[0]] || touched[ids[1]]) continue;
      Segment& s = pieces[ids[0]];
      const Segment& t = pieces[ids[1]];
      const Point2 shared = key_of(s.a) == key ? s.a : s.b;
      if (s.kind != t.kind || !collinear_through(s, t, shared)) continue;
      const Point2 far_s = s.a == shared ? s.b : s.a, far_t = key_of(t.a) == key ? t.b : t.a;
      s = {s.kind, far_s, far_t};
      gone[ids[1]] = touched[ids[0]] = touched[ids[1]] = true;
      joined = true;
    }
    std::vector<Segment> kept;
    for (std::size_t i = 0; i < pieces.size(); ++i)
      if (!gone[i]) kept.push_back(pieces[i]);
    pieces.swap(kept);
  }
  return pieces;
}

// A drawn sheet edge that is an upright rectangle is the blank the sheet is cut from; any other
// shape (a dieline's contour given as FOLD's boundary) must be cut.
bool blank_is_rectangle(const SheetMap& m) {
  const Rect b = m.bounds;
  // Every stretch of the outline runs along a side of its bounding box.
  for (std::size_t i = 0; i < m.outline.size(); ++i) {
    const Point2 p = m.outline[i], q = m.outline[(i + 1) % m.outline.size()];
    const bool upright = p.x_mm == q.x_mm && (p.x_mm == b.min.x_mm || p.x_mm == b.max.x_mm);
    const bool level = p.v_mm == q.v_mm && (p.v_mm == b.min.v_mm || p.v_mm == b.max.v_mm);
    if (!upright && !level) return false;
  }
  return true;
}

}  // namespace

Pattern sheet_pattern(const FoldableSheet& s) {
  Pattern p;
  p.sheet = s.map.bounds;
  std::vector<double> angle_of_edge(s.map.edges.size(), 0);
  for (const SheetHinge& h : s.hinges)
    for (int e : h.edges) angle_of_edge[static_cast<std::size_t>(e)] = h.angle_deg;
  const bool keep_outline = !blank_is_rectangle(s.map);
  std::vector<Segment> pieces;
  for (std::size_t i = 0; i < s.map.edges.size(); ++i) {
    const SheetEdge& e = s.map.edges[i];
    // An outline edge inside the sheet (a hole's edge, FOLD's "B" around it) is always cut.
    const bool blank_edge = e.kind == DrawnKind::outline && (e.left < 0 || e.right < 0) && !keep_outline;
    if (blank_edge || e.kind == DrawnKind::flat || e.a == e.b) continue;
    LineKind k = LineKind::cut;
    if (e.kind == DrawnKind::mountain) k = LineKind::mountain;
    if (e.kind == DrawnKind::valley) k = LineKind::valley;
    if (e.kind == DrawnKind::fold) k = angle_of_edge[i] < 0 ? LineKind::mountain : LineKind::valley;
    pieces.push_back({k, e.a, e.b});
  }
  p.lines = maximal(std::move(pieces));
  return p;
}

}  // namespace popcut
