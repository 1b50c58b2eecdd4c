// Stroke planning: fold gaps, Euler chaining, perforation, passes and travel-minimising order.
#include "popcut/plan/plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

#include "plan/fold_clearance.h"
#include "plan/line_graph.h"

namespace popcut {

using plan_detail::build_graph;
using plan_detail::components;
using plan_detail::Graph;

namespace {

constexpr double kEps = 1e-7;  // mm: pattern coordinates are exact to far better than this
constexpr double kPi = 3.14159265358979323846;

// Not std::hypot: its overflow care costs several times more, and millimetres never overflow.
double dist(Point2 a, Point2 b) {
  const double dx = a.x_mm - b.x_mm, dv = a.v_mm - b.v_mm;
  return std::sqrt(dx * dx + dv * dv);
}
bool same(Point2 a, Point2 b) { return dist(a, b) <= kEps; }

// A uniform grid over item bounding boxes: the spatial index for junctions and nearest neighbours.
class Grid {
 public:
  Grid(Rect box, std::size_t items) {
    const double w = std::max(box.max.x_mm - box.min.x_mm, 1e-3), h = std::max(box.max.v_mm - box.min.v_mm, 1e-3);
    const double cells = std::max<double>(1, static_cast<double>(items));
    cell_mm_ = std::max(std::sqrt(w * h / cells), 1e-3);
    origin_ = box.min;
    nx_ = std::min<long>(4096, static_cast<long>(w / cell_mm_) + 1);
    nv_ = std::min<long>(4096, static_cast<long>(h / cell_mm_) + 1);
    cells_.resize(static_cast<std::size_t>(nx_ * nv_));
  }
  long cx(double x) const { return std::clamp(static_cast<long>((x - origin_.x_mm) / cell_mm_), 0L, nx_ - 1); }
  long cv(double v) const { return std::clamp(static_cast<long>((v - origin_.v_mm) / cell_mm_), 0L, nv_ - 1); }
  std::vector<int>& cell(long x, long v) { return cells_[static_cast<std::size_t>(v * nx_ + x)]; }
  void insert(int id, Point2 lo, Point2 hi) {
    for (long v = cv(lo.v_mm); v <= cv(hi.v_mm); ++v)
      for (long x = cx(lo.x_mm); x <= cx(hi.x_mm); ++x) cell(x, v).push_back(id);
  }
  double cell_mm() const { return cell_mm_; }
  long nx() const { return nx_; }
  long nv() const { return nv_; }

 private:
  Point2 origin_;
  double cell_mm_ = 1;
  long nx_ = 1, nv_ = 1;
  std::vector<std::vector<int>> cells_;
};

Rect bounds_of(const std::vector<std::pair<Point2, Point2>>& segs) {
  Rect r{{1e300, 1e300}, {-1e300, -1e300}};
  for (const auto& [a, b] : segs) {
    for (Point2 p : {a, b}) {
      r.min = {std::min(r.min.x_mm, p.x_mm), std::min(r.min.v_mm, p.v_mm)};
      r.max = {std::max(r.max.x_mm, p.x_mm), std::max(r.max.v_mm, p.v_mm)};
    }
  }
  return r;
}

// Parameter t in (0, 1) where p lies strictly inside segment ab, or a negative value.
double interior_param(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, len2 = dx * dx + dv * dv;
  if (len2 <= kEps * kEps) return -1;
  const double t = ((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / len2;
  const Point2 q{a.x_mm + t * dx, a.v_mm + t * dv};
  if (dist(p, q) > kEps) return -1;
  const double len = std::sqrt(len2);
  if (t * len <= kEps || (1 - t) * len <= kEps) return -1;
  return t;
}


Point2 lerp(Point2 a, Point2 b, double t) { return {a.x_mm + (b.x_mm - a.x_mm) * t, a.v_mm + (b.v_mm - a.v_mm) * t}; }

// Degrees the direction turns at b when going a → b → c (0 = straight on, 180 = back).
double turn_deg(Point2 a, Point2 b, Point2 c) {
  const double ux = b.x_mm - a.x_mm, uv = b.v_mm - a.v_mm, wx = c.x_mm - b.x_mm, wv = c.v_mm - b.v_mm;
  const double n = std::hypot(ux, uv) * std::hypot(wx, wv);
  if (n <= 0) return 0;
  return std::acos(std::clamp((ux * wx + uv * wv) / n, -1.0, 1.0)) * 180 / kPi;
}

std::vector<std::vector<Point2>> split_at_turns(std::vector<Point2> path, double max_deg) {
  std::vector<std::vector<Point2>> out{{path.front()}};
  for (std::size_t i = 1; i < path.size(); ++i) {
    out.back().push_back(path[i]);
    if (i + 1 < path.size() && turn_deg(path[i - 1], path[i], path[i + 1]) > max_deg) out.push_back({path[i]});
  }
  // A closed loop split somewhere may still run smoothly through its start: join the ends there.
  const bool closed = path.size() > 2 && same(path.front(), path.back());
  if (closed && out.size() > 1 && turn_deg(path[path.size() - 2], path.front(), path[1]) <= max_deg) {
    std::vector<Point2> joined = out.back();
    joined.insert(joined.end(), out.front().begin() + 1, out.front().end());
    out.front() = std::move(joined);
    out.pop_back();
  }
  return out;
}

std::vector<Point2> reversed(std::vector<Point2> p) {
  std::reverse(p.begin(), p.end());
  return p;
}

bool is_closed(const std::vector<Point2>& p) { return p.size() > 2 && same(p.front(), p.back()); }

// Rotates a closed loop to start (and end) at vertex i.
void rotate_loop(std::vector<Point2>& p, std::size_t i) {
  if (i == 0 || i + 1 >= p.size()) return;
  std::vector<Point2> r(p.begin() + static_cast<long>(i), p.end() - 1);
  r.insert(r.end(), p.begin(), p.begin() + static_cast<long>(i) + 1);
  p = std::move(r);
}

// Where a closed loop starts and ends: on its segment `seg` (from vertex seg to seg + 1), the
// fraction t of the way along (t = 0: at the vertex).
struct LoopStart {
  std::size_t seg = 0;
  double t = 0;
  friend bool operator==(const LoopStart&, const LoopStart&) = default;
};

Point2 loop_point(const std::vector<Point2>& p, LoopStart at) { return at.t == 0 ? p[at.seg] : lerp(p[at.seg], p[at.seg + 1], at.t); }

// Rotates a closed loop to start (and end) at `at`, which becomes a vertex when mid-segment.
void rotate_loop(std::vector<Point2>& p, LoopStart at) {
  if (at.t == 0) return rotate_loop(p, at.seg);
  const Point2 q = loop_point(p, at);
  std::vector<Point2> r{q};
  r.insert(r.end(), p.begin() + static_cast<long>(at.seg) + 1, p.end() - 1);
  r.insert(r.end(), p.begin(), p.begin() + static_cast<long>(at.seg) + 1);
  r.push_back(q);
  p = std::move(r);
}

// Pieces of `path` that the knife cuts when perforating: off, on, off, ..., on, off, with the
// off gaps stretched evenly so both ends are uncut.
std::vector<std::vector<Point2>> perforate(const std::vector<Point2>& path, double on_mm, double off_mm) {
  const double length = path_length_mm(path);
  if (!(length > 0)) return {};
  const double n_real = std::floor((length - off_mm) / (on_mm + off_mm));
  int n = 1;
  double on = on_mm;
  if (n_real < 1) {
    // Shorter than one dash and its gaps: one shorter dash, still with uncut ends, so the
    // fold is still made (dropping it would leave a short fold unscored without a word).
    on = length - 2 * std::min(off_mm, length / 4);
  } else {
    n = static_cast<int>(n_real);
  }
  const double gap = (length - n * on) / (n + 1);
  // Walk the polyline once, cutting out [start_i, start_i + on] for each dash.
  std::vector<std::vector<Point2>> dashes;
  std::size_t seg = 0;
  double seg_start = 0;  // arc length at path[seg]
  const auto point_at = [&](double s) {
    while (seg + 2 < path.size() && seg_start + dist(path[seg], path[seg + 1]) < s) {
      seg_start += dist(path[seg], path[seg + 1]);
      ++seg;
    }
    const double l = dist(path[seg], path[seg + 1]);
    return lerp(path[seg], path[seg + 1], l > 0 ? std::clamp((s - seg_start) / l, 0.0, 1.0) : 0.0);
  };
  for (int i = 0; i < n; ++i) {
    const double s0 = gap + i * (on + gap), s1 = s0 + on;
    std::vector<Point2> dash{point_at(s0)};
    // Keep the path's corners that fall inside the dash.
    while (seg + 1 < path.size() && seg_start + dist(path[seg], path[seg + 1]) < s1) {
      seg_start += dist(path[seg], path[seg + 1]);
      ++seg;
      dash.push_back(path[seg]);
    }
    dash.push_back(point_at(s1));
    dashes.push_back(std::move(dash));
  }
  return dashes;
}

// The path without the vertices it runs straight through (a junction where another line ends):
// the same cut, but the cutter need not stop there, and the job is shorter. Ends stay.
std::vector<Point2> without_straight_vertices(const std::vector<Point2>& path) {
  if (path.size() < 3) return path;
  std::vector<Point2> out{path.front()};
  for (std::size_t i = 1; i + 1 < path.size(); ++i) {
    const Point2 a = out.back(), b = path[i], c = path[i + 1];
    const double ux = b.x_mm - a.x_mm, uv = b.v_mm - a.v_mm, wx = c.x_mm - b.x_mm, wv = c.v_mm - b.v_mm;
    const double len = dist(a, c);
    const bool straight = len > 0 && std::abs(ux * (c.v_mm - a.v_mm) - uv * (c.x_mm - a.x_mm)) / len <= kEps && ux * wx + uv * wv > 0;
    if (!straight) out.push_back(b);
  }
  out.push_back(path.back());
  return out;
}

std::vector<Point2> with_passes(const std::vector<Point2>& path, int passes) {
  std::vector<Point2> out = path;
  std::vector<Point2> last = path;
  for (int p = 1; p < passes; ++p) {
    last = reversed(last);  // alternate direction: the knife never lifts between passes
    out.insert(out.end(), last.begin() + 1, last.end());
  }
  return out;
}

}  // namespace

const char* to_string(PlanKind kind) { return kPlanKindNames.name(kind).data(); }

std::size_t index_of(PlanKind kind) { return static_cast<std::size_t>(kind); }

const char* to_string(ToolMode mode) { return kToolModeNames.name(mode).data(); }

KindStats StrokePlan::total() const {
  KindStats t;
  for (const KindStats& k : kinds) {
    t.strokes += k.strokes;
    t.pen_lifts += k.pen_lifts;
    t.pen_lift_bound += k.pen_lift_bound;
    t.cut_mm += k.cut_mm;
    t.travel_mm += k.travel_mm;
    t.folds_dropped += k.folds_dropped;
    t.strokes_below_resolution += k.strokes_below_resolution;
    t.precuts += k.precuts;
  }
  return t;
}

Rect StrokePlan::extent() const {
  Rect r = sheet;
  for (const Stroke& s : strokes) {
    for (Point2 p : s.points) {
      r.min = {std::min(r.min.x_mm, p.x_mm), std::min(r.min.v_mm, p.v_mm)};
      r.max = {std::max(r.max.x_mm, p.x_mm), std::max(r.max.v_mm, p.v_mm)};
    }
  }
  return r;
}

std::vector<Point2> precut_path(const std::vector<Point2>& tip_path, double precut_mm) {
  if (precut_mm <= 0 || tip_path.size() < 2) return {};
  const Point2 a = tip_path[0], b = tip_path[1];
  const double len = dist(a, b);
  if (!(len > 0)) return {};
  return {a, lerp(a, b, std::min(1.0, precut_mm / len))};
}

std::vector<Point2> with_overcut(const std::vector<Point2>& path, double overcut_mm) {
  if (overcut_mm <= 0 || !is_closed(path)) return path;
  std::vector<Point2> out = path;
  double left = overcut_mm;
  for (std::size_t i = 1; i < path.size() && left > 0; ++i) {
    const double l = dist(path[i - 1], path[i]);
    if (l >= left) {
      out.push_back(lerp(path[i - 1], path[i], left / l));
      break;
    }
    out.push_back(path[i]);
    left -= l;
  }
  return out;
}

std::vector<Point2> blade_offset_path(const std::vector<Point2>& tip, double offset_mm, double swivel_step_deg) {
  std::vector<Point2> pts;
  for (Point2 p : tip) {
    if (pts.empty() || !same(pts.back(), p)) pts.push_back(p);
  }
  if (offset_mm <= 0 || pts.size() < 2) return pts;
  const auto unit = [](Point2 a, Point2 b) {
    const double l = dist(a, b);
    return Point2{(b.x_mm - a.x_mm) / l, (b.v_mm - a.v_mm) / l};
  };
  const auto ahead = [&](Point2 p, Point2 d) { return Point2{p.x_mm + offset_mm * d.x_mm, p.v_mm + offset_mm * d.v_mm}; };
  const double step = std::max(1.0, swivel_step_deg) * kPi / 180;
  std::vector<Point2> out{ahead(pts[0], unit(pts[0], pts[1]))};
  for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
    const Point2 d0 = unit(pts[i - 1], pts[i]), d1 = unit(pts[i], pts[i + 1]);
    out.push_back(ahead(pts[i], d0));
    // Swivel: the axis circles the tip (which stays at the corner) from the old heading to the
    // new, the short way round, so the blade turns in place.
    const double a0 = std::atan2(d0.v_mm, d0.x_mm);
    const double turn = std::atan2(d0.x_mm * d1.v_mm - d0.v_mm * d1.x_mm, d0.x_mm * d1.x_mm + d0.v_mm * d1.v_mm);
    const int n = static_cast<int>(std::ceil(std::abs(turn) / step));
    for (int k = 1; k <= n; ++k) {
      const double a = a0 + turn * k / n;
      out.push_back({pts[i].x_mm + offset_mm * std::cos(a), pts[i].v_mm + offset_mm * std::sin(a)});
    }
  }
  out.push_back(ahead(pts.back(), unit(pts[pts.size() - 2], pts.back())));
  return out;
}

double path_length_mm(const std::vector<Point2>& path) {
  double l = 0;
  for (std::size_t i = 1; i < path.size(); ++i) l += dist(path[i - 1], path[i]);
  return l;
}

double travel_mm(const std::vector<std::vector<Point2>>& paths, Point2 start) {
  double t = 0;
  for (const auto& p : paths) {
    t += dist(start, p.front());
    start = p.back();
  }
  return t;
}

std::vector<Segment> kind_lines(const Pattern& pattern, PlanKind kind, double fold_gap_mm, int* dropped) {
  std::vector<Segment> out;
  if (dropped) *dropped = 0;
  const Rect& s = pattern.sheet;
  if (kind == PlanKind::outline) {
    const Point2 c[4] = {s.min, {s.max.x_mm, s.min.v_mm}, s.max, {s.min.x_mm, s.max.v_mm}};
    for (int i = 0; i < 4; ++i) out.push_back({LineKind::cut, c[i], c[(i + 1) % 4]});
    return out;
  }
  const LineKind want = kind == PlanKind::cut ? LineKind::cut : (kind == PlanKind::valley ? LineKind::valley : LineKind::mountain);
  // Cut lines and the outline's four edges in a grid, so each fold looks only at the cuts near it.
  std::vector<std::pair<Point2, Point2>> cuts;
  for (const Segment& l : pattern.lines) {
    if (l.kind == LineKind::cut) cuts.emplace_back(l.a, l.b);
  }
  const Point2 corner[4] = {s.min, {s.max.x_mm, s.min.v_mm}, s.max, {s.min.x_mm, s.max.v_mm}};
  for (int i = 0; i < 4; ++i) cuts.emplace_back(corner[i], corner[(i + 1) % 4]);
  Grid grid(s, cuts.size());
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    const auto& [a, b] = cuts[i];
    grid.insert(static_cast<int>(i), {std::min(a.x_mm, b.x_mm) - kEps, std::min(a.v_mm, b.v_mm) - kEps},
                {std::max(a.x_mm, b.x_mm) + kEps, std::max(a.v_mm, b.v_mm) + kEps});
  }
  std::vector<std::uint8_t> seen(cuts.size(), 0);
  std::vector<int> near_ids;
  std::vector<std::pair<Point2, Point2>> near;
  for (const Segment& l : pattern.lines) {
    if (l.kind != want) continue;
    if (want == LineKind::cut || fold_gap_mm <= 0) {
      out.push_back(l);
      continue;
    }
    // Every cut whose box comes within the gap of the fold's box.
    const double reach = fold_gap_mm + kEps;
    near_ids.clear();
    for (long v = grid.cv(std::min(l.a.v_mm, l.b.v_mm) - reach); v <= grid.cv(std::max(l.a.v_mm, l.b.v_mm) + reach); ++v) {
      for (long x = grid.cx(std::min(l.a.x_mm, l.b.x_mm) - reach); x <= grid.cx(std::max(l.a.x_mm, l.b.x_mm) + reach); ++x) {
        for (int id : grid.cell(x, v)) {
          if (!seen[static_cast<std::size_t>(id)]) {
            seen[static_cast<std::size_t>(id)] = 1;
            near_ids.push_back(id);
          }
        }
      }
    }
    near.clear();
    for (int id : near_ids) {
      seen[static_cast<std::size_t>(id)] = 0;
      near.push_back(cuts[static_cast<std::size_t>(id)]);
    }
    // Euclidean clearance: a slanted cut takes gap / sin(angle) of the fold, not the gap.
    const auto pieces = plan_detail::clear_pieces(l.a, l.b, near, fold_gap_mm, kEps);
    if (pieces.empty() && dropped) ++*dropped;
    for (const auto& [t0, t1] : pieces) {
      out.push_back({l.kind, t0 == 0 ? l.a : lerp(l.a, l.b, t0), t1 == 1 ? l.b : lerp(l.a, l.b, t1)});
    }
  }
  return out;
}

std::vector<std::pair<Point2, Point2>> split_at_junctions(const std::vector<std::pair<Point2, Point2>>& segs) {
  std::vector<std::pair<Point2, Point2>> out;
  if (segs.empty()) return out;
  Grid grid(bounds_of(segs), segs.size());
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const auto& [a, b] = segs[i];
    grid.insert(static_cast<int>(i), {std::min(a.x_mm, b.x_mm) - kEps, std::min(a.v_mm, b.v_mm) - kEps},
                {std::max(a.x_mm, b.x_mm) + kEps, std::max(a.v_mm, b.v_mm) + kEps});
  }
  std::vector<std::vector<double>> cuts_at(segs.size());
  for (const auto& [a, b] : segs) {
    for (Point2 p : {a, b}) {
      for (int j : grid.cell(grid.cx(p.x_mm), grid.cv(p.v_mm))) {
        const auto& s = segs[static_cast<std::size_t>(j)];
        const double t = interior_param(p, s.first, s.second);
        if (t > 0) cuts_at[static_cast<std::size_t>(j)].push_back(t);
      }
    }
  }
  for (std::size_t i = 0; i < segs.size(); ++i) {
    auto& ts = cuts_at[i];
    std::sort(ts.begin(), ts.end());
    Point2 from = segs[i].first;
    for (double t : ts) {
      const Point2 to = lerp(segs[i].first, segs[i].second, t);
      if (!same(from, to)) out.emplace_back(from, to);
      from = to;
    }
    if (!same(from, segs[i].second)) out.emplace_back(from, segs[i].second);
  }
  return out;
}

int euler_bound(const std::vector<std::pair<Point2, Point2>>& edges) {
  const Graph g = build_graph(edges);
  int count = 0;
  const std::vector<int> comp = components(g, count);
  std::vector<int> odd(static_cast<std::size_t>(count), 0), has_edge(static_cast<std::size_t>(count), 0);
  for (std::size_t v = 0; v < g.pos.size(); ++v) {
    if (g.adj[v].size() % 2 == 1) ++odd[static_cast<std::size_t>(comp[v])];
    if (!g.adj[v].empty()) has_edge[static_cast<std::size_t>(comp[v])] = 1;
  }
  int bound = 0;
  for (std::size_t c = 0; c < odd.size(); ++c) {
    if (has_edge[c]) bound += std::max(1, odd[c] / 2);
  }
  return bound;
}

std::vector<std::vector<Point2>> chain_edges(const std::vector<std::pair<Point2, Point2>>& input,
                                             std::optional<double> max_turn_deg) {
  Graph g = build_graph(input);
  const std::size_t real_edges = g.edges.size();
  int count = 0;
  const std::vector<int> comp = components(g, count);
  // Pair the odd vertices of each component with virtual edges; an Euler circuit of the result,
  // cut at the virtual edges, is exactly odd/2 trails (or one closed trail when none are odd).
  std::vector<std::vector<int>> odd(static_cast<std::size_t>(count));
  for (std::size_t v = 0; v < g.pos.size(); ++v) {
    if (g.adj[v].size() % 2 == 1) odd[static_cast<std::size_t>(comp[v])].push_back(static_cast<int>(v));
  }
  for (const auto& list : odd) {
    for (std::size_t i = 0; i + 1 < list.size(); i += 2) {
      const int e = static_cast<int>(g.edges.size());
      g.edges.emplace_back(list[i], list[i + 1]);
      g.adj[static_cast<std::size_t>(list[i])].emplace_back(e, list[i + 1]);
      g.adj[static_cast<std::size_t>(list[i + 1])].emplace_back(e, list[i]);
    }
  }
  std::vector<char> used(g.edges.size(), 0);
  std::vector<std::size_t> next(g.pos.size(), 0);
  std::vector<char> comp_done(static_cast<std::size_t>(count), 0);
  std::vector<std::vector<Point2>> trails;
  for (std::size_t s = 0; s < g.pos.size(); ++s) {
    const auto c = static_cast<std::size_t>(comp[s]);
    if (comp_done[c] || g.adj[s].empty()) continue;
    comp_done[c] = 1;
    // Iterative Hierholzer: (vertex, edge used to arrive).
    std::vector<std::pair<int, int>> stack{{static_cast<int>(s), -1}}, circuit;
    while (!stack.empty()) {
      const auto v = static_cast<std::size_t>(stack.back().first);
      while (next[v] < g.adj[v].size() && used[static_cast<std::size_t>(g.adj[v][next[v]].first)]) ++next[v];
      if (next[v] < g.adj[v].size()) {
        const auto [e, w] = g.adj[v][next[v]];
        used[static_cast<std::size_t>(e)] = 1;
        stack.emplace_back(w, e);
      } else {
        circuit.push_back(stack.back());
        stack.pop_back();
      }
    }
    std::reverse(circuit.begin(), circuit.end());
    // circuit[i] (i ≥ 1) arrives over edge circuit[i].second; the walk is closed. Start right
    // after a virtual edge, if any, so each trail is a run of real edges between virtual ones.
    const std::size_t m = circuit.size() - 1;
    std::size_t first = 0;
    for (std::size_t i = 1; i <= m; ++i) {
      if (static_cast<std::size_t>(circuit[i].second) >= real_edges) {
        first = i;
        break;
      }
    }
    std::vector<Point2> trail{g.pos[static_cast<std::size_t>(circuit[first].first)]};
    for (std::size_t k = 1; k <= m; ++k) {
      const std::size_t i = (first + k - 1) % m + 1;
      const auto [v, e] = circuit[i];
      if (static_cast<std::size_t>(e) >= real_edges) {
        if (trail.size() > 1) trails.push_back(std::move(trail));
        trail = {g.pos[static_cast<std::size_t>(v)]};
      } else {
        trail.push_back(g.pos[static_cast<std::size_t>(v)]);
      }
    }
    if (trail.size() > 1) trails.push_back(std::move(trail));
  }
  if (!max_turn_deg) return trails;
  std::vector<std::vector<Point2>> out;
  for (auto& t : trails) {
    for (auto& piece : split_at_turns(std::move(t), *max_turn_deg)) out.push_back(std::move(piece));
  }
  return out;
}

namespace plan_detail {
namespace {

// Vertices are identified on a 1e-6 mm lattice so endpoints computed twice still meet.
struct Key {
  std::int64_t x, v;
  friend bool operator==(const Key&, const Key&) = default;
};
struct KeyHash {
  std::size_t operator()(const Key& k) const {
    return std::hash<std::int64_t>()(k.x) ^ (std::hash<std::int64_t>()(k.v) * 0x9e3779b97f4a7c15ULL);
  }
};
Key key_of(Point2 p) { return {std::llround(p.x_mm * 1e6), std::llround(p.v_mm * 1e6)}; }

}  // namespace

Graph build_graph(const std::vector<std::pair<Point2, Point2>>& segs) {
  Graph g;
  std::unordered_map<Key, int, KeyHash> ids;
  const auto vid = [&](Point2 p) {
    const auto [it, fresh] = ids.try_emplace(key_of(p), static_cast<int>(g.pos.size()));
    if (fresh) {
      g.pos.push_back(p);
      g.adj.emplace_back();
    }
    return it->second;
  };
  for (const auto& [a, b] : segs) {
    if (same(a, b)) continue;  // zero-length: nothing to cut
    const int u = vid(a), w = vid(b);
    const int e = static_cast<int>(g.edges.size());
    g.edges.emplace_back(u, w);
    g.adj[static_cast<std::size_t>(u)].emplace_back(e, w);
    g.adj[static_cast<std::size_t>(w)].emplace_back(e, u);
  }
  return g;
}

std::vector<int> components(const Graph& g, int& count) {
  std::vector<int> comp(g.pos.size(), -1);
  count = 0;
  for (std::size_t s = 0; s < g.pos.size(); ++s) {
    if (comp[s] >= 0) continue;
    std::vector<std::size_t> stack{s};
    comp[s] = count;
    while (!stack.empty()) {
      const std::size_t v = stack.back();
      stack.pop_back();
      for (const auto& [e, w] : g.adj[v]) {
        if (comp[static_cast<std::size_t>(w)] < 0) {
          comp[static_cast<std::size_t>(w)] = count;
          stack.push_back(static_cast<std::size_t>(w));
        }
      }
    }
    ++count;
  }
  return comp;
}

}  // namespace plan_detail

namespace {

// Greedy nearest neighbour from `start`: entries are both ends of an open path and every vertex
// of a closed loop, found through a grid; picks each path's direction and each loop's start.
std::vector<std::vector<Point2>> greedy_order(std::vector<std::vector<Point2>> paths, Point2 start) {
  const std::size_t n = paths.size();
  struct Entry {
    int path;
    int vertex;
  };
  std::vector<Entry> entries;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = paths[i];
    if (is_closed(p)) {
      for (std::size_t k = 0; k + 1 < p.size(); ++k) entries.push_back({static_cast<int>(i), static_cast<int>(k)});
    } else {
      entries.push_back({static_cast<int>(i), 0});
      entries.push_back({static_cast<int>(i), static_cast<int>(p.size() - 1)});
    }
  }
  const auto entry_pos = [&](const Entry& e) { return paths[static_cast<std::size_t>(e.path)][static_cast<std::size_t>(e.vertex)]; };
  std::vector<std::pair<Point2, Point2>> pts;
  for (const Entry& e : entries) pts.emplace_back(entry_pos(e), entry_pos(e));
  pts.emplace_back(start, start);
  Grid grid(bounds_of(pts), entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i) grid.insert(static_cast<int>(i), pts[i].first, pts[i].first);
  std::vector<char> done(n, 0);
  std::vector<std::vector<Point2>> tour;
  Point2 at = start;
  for (std::size_t step = 0; step < n; ++step) {
    // Search rings of cells around `at` until no closer entry can exist.
    const long cx = grid.cx(at.x_mm), cv = grid.cv(at.v_mm);
    int best = -1;
    double best_d = 1e300;
    for (long r = 0; r <= std::max(grid.nx(), grid.nv()); ++r) {
      if (best >= 0 && (static_cast<double>(r) - 1) * grid.cell_mm() > best_d) break;
      for (long v = cv - r; v <= cv + r; ++v) {
        // The ring only: whole rows at its top and bottom, two cells on the rows between.
        const bool edge_row = v == cv - r || v == cv + r;
        for (long x = cx - r; x <= cx + r; x += (edge_row || r == 0) ? 1 : 2 * r) {
          if (x < 0 || v < 0 || x >= grid.nx() || v >= grid.nv()) continue;
          auto& cell = grid.cell(x, v);
          for (std::size_t k = 0; k < cell.size();) {
            const Entry& e = entries[static_cast<std::size_t>(cell[k])];
            if (done[static_cast<std::size_t>(e.path)]) {  // drop entries of finished paths
              cell[k] = cell.back();
              cell.pop_back();
              continue;
            }
            const double d = dist(at, entry_pos(e));
            if (d < best_d || (d == best_d && cell[k] < best)) {
              best_d = d;
              best = cell[k];
            }
            ++k;
          }
        }
      }
    }
    const Entry e = entries[static_cast<std::size_t>(best)];
    auto p = std::move(paths[static_cast<std::size_t>(e.path)]);
    done[static_cast<std::size_t>(e.path)] = 1;
    if (is_closed(p)) rotate_loop(p, static_cast<std::size_t>(e.vertex));
    else if (e.vertex != 0) p = reversed(std::move(p));
    at = p.back();
    tour.push_back(std::move(p));
  }
  return tour;
}

// Local search over a tour of paths: 2-opt (reverse a run of paths), Or-opt (move a run of one
// to three paths elsewhere, either way round), and each closed loop's start vertex. Candidate
// moves come from each path end's nearest other path ends, so a sweep costs O(n), not O(n²).
// Work is counted (evaluations and elements moved), never timed: one input, one tour.
class TourSearch {
 public:
  TourSearch(std::vector<std::vector<Point2>> tour, Point2 start, std::uint64_t budget)
      : paths_(std::move(tour)), start_(start), budget_(budget), n_(static_cast<long>(paths_.size())) {
    order_.resize(paths_.size());
    std::iota(order_.begin(), order_.end(), 0);
    pos_.assign(order_.begin(), order_.end());
    flip_.assign(paths_.size(), 0);
    loop_at_.assign(paths_.size(), LoopStart{});
    closed_.resize(paths_.size());
    for (std::size_t s = 0; s < paths_.size(); ++s) closed_[s] = is_closed(paths_[s]);
    build_neighbours();
  }

  std::vector<std::vector<Point2>> run() {
    queued_.assign(paths_.size(), 0);
    for (long i = 0; i < n_; ++i) touch(i);
    descend();
    // Iterated local search: kick the tour (double bridge, or reverse a stretch), descend again,
    // keep the result only if shorter. The kicks come from a fixed-seed generator.
    double best = tour_mm();
    Saved saved = save();
    std::uint64_t seed = 0x9e3779b97f4a7c15ULL;
    const long kicks = n_ >= 3 ? std::max<long>(50, 2 * n_) : 0;
    for (long k = 0; k < kicks && work_ < budget_; ++k) {
      kick(k % 2 == 0, seed);
      descend();
      const double len = tour_mm();
      if (len < best - kGain) {
        best = len;
        saved = save();
      } else {
        restore(saved);
      }
    }
    std::vector<std::vector<Point2>> out;
    out.reserve(paths_.size());
    for (int s : order_) {
      auto& p = paths_[static_cast<std::size_t>(s)];
      if (closed_[static_cast<std::size_t>(s)]) rotate_loop(p, loop_at_[static_cast<std::size_t>(s)]);
      if (flip_[static_cast<std::size_t>(s)]) std::reverse(p.begin(), p.end());
      out.push_back(std::move(p));
    }
    return out;
  }

 private:
  static constexpr double kGain = 1e-9;  // mm: smaller gains are rounding, not improvement
  static constexpr std::size_t kNeighbours = 8;
  static constexpr int kLoopSearchSteps = 30;     // golden-section steps per segment: 1e-6 of its length
  static constexpr double kLoopSplitGain = 0.01;  // mm: a loop starts mid-segment only to save more

  // An anchor is a place a path may be entered or left: an open path's ends, a loop's vertices,
  // and the start (owner -1).
  struct Anchor {
    Point2 at;
    int owner;
    int vertex;  // index into the path's points
  };

  std::size_t ix(long i) const { return static_cast<std::size_t>(i); }
  int path_at(long i) const { return order_[ix(i)]; }
  Point2 entry(long i) const {
    const int s = path_at(i);
    const auto& p = paths_[static_cast<std::size_t>(s)];
    if (closed_[static_cast<std::size_t>(s)]) return loop_point(p, loop_at_[static_cast<std::size_t>(s)]);
    return flip_[static_cast<std::size_t>(s)] ? p.back() : p.front();
  }
  Point2 exit(long i) const {
    if (i < 0) return start_;
    const int s = path_at(i);
    const auto& p = paths_[static_cast<std::size_t>(s)];
    if (closed_[static_cast<std::size_t>(s)]) return loop_point(p, loop_at_[static_cast<std::size_t>(s)]);
    return flip_[static_cast<std::size_t>(s)] ? p.front() : p.back();
  }
  // Knife-up move into position i (none past the end).
  double link(long i) const { return i < n_ ? dist(exit(i - 1), entry(i)) : 0; }

  // Does anchor `a` (of a path, at its position) currently serve as the entry / the exit?
  bool is_entry(const Anchor& a) const {
    if (a.owner < 0) return false;
    const auto s = static_cast<std::size_t>(a.owner);
    if (closed_[s]) return static_cast<std::size_t>(a.vertex) == loop_at_[s].seg;  // the anchor before a mid-segment start
    return (a.vertex == 0) != static_cast<bool>(flip_[s]);
  }
  bool is_exit(const Anchor& a) const {
    if (a.owner < 0) return true;
    const auto s = static_cast<std::size_t>(a.owner);
    if (closed_[s]) return static_cast<std::size_t>(a.vertex) == loop_at_[s].seg;  // the anchor before a mid-segment start
    return (a.vertex == 0) == static_cast<bool>(flip_[s]);
  }
  long position(const Anchor& a) const { return a.owner < 0 ? -1 : pos_[static_cast<std::size_t>(a.owner)]; }

  void build_neighbours() {
    for (std::size_t s = 0; s < paths_.size(); ++s) {
      const auto& p = paths_[s];
      const int owner = static_cast<int>(s);
      if (closed_[s]) {
        for (std::size_t k = 0; k + 1 < p.size(); ++k) anchors_.push_back({p[k], owner, static_cast<int>(k)});
      } else {
        anchors_.push_back({p.front(), owner, 0});
        anchors_.push_back({p.back(), owner, static_cast<int>(p.size() - 1)});
      }
    }
    anchors_.push_back({start_, -1, 0});
    of_path_.resize(paths_.size());
    for (std::size_t a = 0; a < anchors_.size(); ++a) {
      if (anchors_[a].owner >= 0) of_path_[static_cast<std::size_t>(anchors_[a].owner)].push_back(static_cast<int>(a));
    }
    std::vector<std::pair<Point2, Point2>> box;
    for (const Anchor& a : anchors_) box.emplace_back(a.at, a.at);
    Grid grid(bounds_of(box), anchors_.size());
    for (std::size_t a = 0; a < anchors_.size(); ++a) grid.insert(static_cast<int>(a), anchors_[a].at, anchors_[a].at);
    near_.resize(anchors_.size());
    std::vector<std::pair<double, int>> found;
    for (std::size_t a = 0; a < anchors_.size(); ++a) {
      const Point2 at = anchors_[a].at;
      const long cx = grid.cx(at.x_mm), cv = grid.cv(at.v_mm);
      found.clear();
      for (long r = 0; r <= std::max(grid.nx(), grid.nv()); ++r) {
        if (found.size() >= kNeighbours && (static_cast<double>(r) - 1) * grid.cell_mm() > found[kNeighbours - 1].first) break;
        for (long v = cv - r; v <= cv + r; ++v) {
          const bool edge_row = v == cv - r || v == cv + r;
          for (long x = cx - r; x <= cx + r; x += (edge_row || r == 0) ? 1 : 2 * r) {
            if (x < 0 || v < 0 || x >= grid.nx() || v >= grid.nv()) continue;
            for (int b : grid.cell(x, v)) {
              if (anchors_[static_cast<std::size_t>(b)].owner == anchors_[a].owner) continue;
              found.emplace_back(dist(at, anchors_[static_cast<std::size_t>(b)].at), b);
            }
          }
        }
        std::sort(found.begin(), found.end());
        if (found.size() > kNeighbours) found.resize(kNeighbours);
      }
      for (const auto& [d, b] : found) near_[a].push_back(b);
    }
  }

  // Gain of reversing positions lo..hi (each path turned round too).
  double gain_reverse(long lo, long hi) {
    ++work_;
    const double before = link(lo) + link(hi + 1);
    const double after = dist(exit(lo - 1), exit(hi)) + (hi + 1 < n_ ? dist(entry(lo), entry(hi + 1)) : 0);
    return before - after;
  }
  void reverse(long lo, long hi) {
    std::reverse(order_.begin() + lo, order_.begin() + hi + 1);
    for (long k = lo; k <= hi; ++k) {
      flip_[static_cast<std::size_t>(path_at(k))] ^= 1;
      pos_[static_cast<std::size_t>(path_at(k))] = k;
    }
    work_ += static_cast<std::uint64_t>(hi - lo + 1);
    touch(lo);
    touch(hi);
  }

  // Gain of moving the run i..j to just after position q (q = -1: first), turned round or not.
  double gain_move(long i, long j, long q, bool rev) {
    ++work_;
    const double removed = link(i) + link(j + 1) - (j + 1 < n_ ? dist(exit(i - 1), entry(j + 1)) : 0);
    const Point2 in = rev ? exit(j) : entry(i), out = rev ? entry(i) : exit(j);
    const double added = dist(exit(q), in) + (q + 1 < n_ ? dist(out, entry(q + 1)) - link(q + 1) : 0);
    return removed - added;
  }
  void move(long i, long j, long q, bool rev) {
    // The paths either side of the gap left behind and of the gap filled get new links.
    std::vector<int> near;
    for (long k : {i - 1, j + 1, q, q + 1}) {
      if (k >= 0 && k < n_) near.push_back(path_at(k));
    }
    std::vector<int> run(order_.begin() + i, order_.begin() + j + 1);
    if (rev) {
      std::reverse(run.begin(), run.end());
      for (int s : run) flip_[static_cast<std::size_t>(s)] ^= 1;
    }
    order_.erase(order_.begin() + i, order_.begin() + j + 1);
    const long at = q < i ? q + 1 : q + 1 - (j - i + 1);
    order_.insert(order_.begin() + at, run.begin(), run.end());
    const long lo = std::min(i, at), hi = std::max(j, at + (j - i));
    for (long k = lo; k <= hi; ++k) pos_[static_cast<std::size_t>(path_at(k))] = k;
    // erase and insert each shift the rest of the order
    work_ += static_cast<std::uint64_t>(hi - lo + 1) + 2 * static_cast<std::uint64_t>(n_ - lo);
    for (int p : near) touch(pos_[static_cast<std::size_t>(p)]);
    touch(at);
    touch(at + (j - i));
  }
  bool try_move(long i, long j, long q, bool rev) {
    if (i < 0 || j >= n_ || i > j || (q >= i - 1 && q <= j) || q < -1 || q >= n_) return false;
    if (gain_move(i, j, q, rev) <= kGain) return false;
    move(i, j, q, rev);
    return true;
  }

  // First improving 2-opt or Or-opt move that makes a knife-up link between a path end at
  // position i and one of its near anchors.
  bool improve_at(long i) {
    for (int ai : of_path_[static_cast<std::size_t>(path_at(i))]) {
      const Anchor& a = anchors_[static_cast<std::size_t>(ai)];
      const bool a_in = is_entry(a), a_out = is_exit(a);
      if (!a_in && !a_out) continue;
      for (int ci : near_[static_cast<std::size_t>(ai)]) {
        if (work_ >= budget_) return false;
        const Anchor& c = anchors_[static_cast<std::size_t>(ci)];
        const long q = position(c);
        const bool c_in = is_entry(c), c_out = is_exit(c);
        if (q == i || (!c_in && !c_out)) continue;
        // 2-opt: exit next to exit, or entry next to entry, by reversing what lies between.
        if (a_out && c_out) {
          const long lo = std::min(i, q) + 1, hi = std::max(i, q);
          if (lo <= hi && gain_reverse(lo, hi) > kGain) return reverse(lo, hi), true;
        }
        if (a_in && c_in) {
          const long lo = std::min(i, q), hi = std::max(i, q) - 1;
          if (lo <= hi && gain_reverse(lo, hi) > kGain) return reverse(lo, hi), true;
        }
        // Or-opt: a run starting (or ending) with this path goes next to c.
        for (long len = 1; len <= 3; ++len) {
          if (a_in && c_out && try_move(i, i + len - 1, q, false)) return true;
          if (a_in && c_in && try_move(i, i + len - 1, q - 1, true)) return true;
          if (a_out && c_in && try_move(i - len + 1, i, q - 1, false)) return true;
          if (a_out && c_out && try_move(i - len + 1, i, q, true)) return true;
        }
      }
    }
    // The end of the tour is free: appending costs only the link there.
    for (long len = 1; len <= 3; ++len) {
      for (bool rev : {false, true}) {
        if (try_move(i, i + len - 1, n_ - 1, rev)) return true;
      }
    }
    // Flip this path in place; turn the whole rest of the tour round.
    for (long hi : {i, n_ - 1}) {
      if (gain_reverse(i, hi) > kGain) return reverse(i, hi), true;
    }
    return place_loop_start(i);
  }

  // A closed loop starts at the point of it nearest to both its knife-up links: a vertex, or a
  // point inside a segment (which then becomes a vertex of the stroke) when that saves more than
  // kLoopSplitGain. Along a segment the two links' sum is convex: golden-section search.
  bool place_loop_start(long i) {
    const auto s = static_cast<std::size_t>(path_at(i));
    if (!closed_[s]) return false;
    const auto& p = paths_[s];
    const Point2 from = exit(i - 1);
    const bool last = i + 1 >= n_;
    const Point2 to = last ? from : entry(i + 1);
    const auto cost = [&](Point2 q) { return dist(from, q) + (last ? 0 : dist(q, to)); };
    LoopStart best = loop_at_[s];
    double best_d = cost(loop_point(p, best));
    for (std::size_t k = 0; k + 1 < p.size(); ++k) {
      if (const double d = cost(p[k]); d < best_d - kGain) best_d = d, best = {k, 0};
      constexpr double kGolden = 0.6180339887498949;
      double lo = 0, hi = 1;
      for (int step = 0; step < kLoopSearchSteps; ++step) {
        const double a = hi - kGolden * (hi - lo), b = lo + kGolden * (hi - lo);
        if (cost(lerp(p[k], p[k + 1], a)) < cost(lerp(p[k], p[k + 1], b))) hi = b;
        else lo = a;
      }
      const double t = (lo + hi) / 2, len = dist(p[k], p[k + 1]);
      if (t * len <= kLoopSplitGain || (1 - t) * len <= kLoopSplitGain) continue;  // a vertex: tried above
      if (const double d = cost(lerp(p[k], p[k + 1], t)); d < best_d - kLoopSplitGain) best_d = d, best = {k, t};
    }
    work_ += p.size() * (2 * kLoopSearchSteps + 2);
    if (best == loop_at_[s]) return false;
    loop_at_[s] = best;
    touch(i);
    return true;
  }

  // Paths whose links changed are looked at again; the rest stay settled ("don't look" bits).
  void touch(long i) {
    for (long k = std::max(0L, i - 1); k <= std::min(n_ - 1, i + 1); ++k) {
      const auto s = static_cast<std::size_t>(path_at(k));
      if (!queued_[s]) queued_[s] = 1, queue_.push_back(static_cast<int>(s));
    }
  }
  void descend() {
    for (std::size_t head = 0; head < queue_.size() && work_ < budget_; ++head) {
      const auto s = static_cast<std::size_t>(queue_[head]);
      queued_[s] = 0;
      if (improve_at(pos_[s])) touch(pos_[s]);
    }
    queue_.clear();
    std::fill(queued_.begin(), queued_.end(), 0);
  }

  double tour_mm() {
    double t = 0;
    for (long i = 0; i < n_; ++i) t += link(i);
    work_ += static_cast<std::uint64_t>(n_);
    return t;
  }
  struct Saved {
    std::vector<int> order;
    std::vector<char> flip;
    std::vector<LoopStart> loop_at;
  };
  Saved save() {
    work_ += static_cast<std::uint64_t>(n_);
    return {order_, flip_, loop_at_};
  }
  void restore(const Saved& s) {
    order_ = s.order;
    flip_ = s.flip;
    loop_at_ = s.loop_at;
    for (long k = 0; k < n_; ++k) pos_[static_cast<std::size_t>(path_at(k))] = k;
    work_ += static_cast<std::uint64_t>(n_);
  }
  // splitmix64: a fixed sequence on every platform (std distributions are not portable).
  static std::uint64_t next(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  void kick(bool bridge, std::uint64_t& seed) {
    std::array<long, 3> cut{};
    for (long& c : cut) c = static_cast<long>(next(seed) % static_cast<std::uint64_t>(n_ + 1));
    std::sort(cut.begin(), cut.end());
    if (bridge && cut[0] < cut[1] && cut[1] < cut[2]) {
      // A B C D -> A C B D: a move 2-opt and Or-opt cannot undo in one step.
      std::rotate(order_.begin() + cut[0], order_.begin() + cut[1], order_.begin() + cut[2]);
      for (long k = cut[0]; k < cut[2]; ++k) pos_[static_cast<std::size_t>(path_at(k))] = k;
      work_ += static_cast<std::uint64_t>(cut[2] - cut[0]);
      for (long c : {cut[0], cut[0] + cut[2] - cut[1], cut[2] - 1}) touch(c);
    } else {
      const long lo = std::min(cut[0], n_ - 1), hi = std::max(lo, std::min(cut[2], n_ - 1));
      reverse(lo, hi);
    }
  }

  std::vector<std::vector<Point2>> paths_;
  Point2 start_;
  std::uint64_t budget_;
  std::uint64_t work_ = 0;
  long n_;
  std::vector<int> order_;           // path ids in cutting order
  std::vector<long> pos_;            // position of each path id
  std::vector<char> flip_;           // open path cut back to front
  std::vector<LoopStart> loop_at_;   // closed loop: where it starts and ends
  std::vector<char> closed_;
  std::vector<Anchor> anchors_;
  std::vector<std::vector<int>> of_path_;  // anchors of each path
  std::vector<std::vector<int>> near_;     // nearest anchors of other paths (or the start)
  std::vector<int> queue_;                 // paths to look at again
  std::vector<char> queued_;
};

}  // namespace

std::vector<std::vector<Point2>> order_paths(std::vector<std::vector<Point2>> paths, Point2 start, std::uint64_t work_budget) {
  if (paths.empty()) return paths;
  std::vector<std::vector<Point2>> tour = greedy_order(std::move(paths), start);
  if (work_budget == 0) return tour;
  return TourSearch(std::move(tour), start, work_budget).run();
}

StrokePlan plan_strokes(const Pattern& pattern, const PlanOptions& options) {
  StrokePlan plan;
  plan.sheet = pattern.sheet;
  plan.home = options.home.value_or(pattern.sheet.min);
  Point2 at = plan.home;
  for (PlanKind kind : options.order) {
    const KindPlan& kp = options.kinds[index_of(kind)];
    KindStats& stats = plan.kinds[index_of(kind)];
    if (kp.mode == ToolMode::skip) continue;
    std::vector<std::pair<Point2, Point2>> segs;
    for (const Segment& s : kind_lines(pattern, kind, options.fold_gap_mm, &stats.folds_dropped)) segs.emplace_back(s.a, s.b);
    segs = split_at_junctions(segs);
    stats.pen_lift_bound = euler_bound(segs);
    std::vector<std::vector<Point2>> paths = chain_edges(segs, options.max_turn_deg);
    if (kp.mode == ToolMode::perforate) {
      std::vector<std::vector<Point2>> dashes;
      for (const auto& p : paths) {
        for (auto& d : perforate(p, kp.perforate_on_mm, kp.perforate_off_mm)) dashes.push_back(std::move(d));
      }
      paths = std::move(dashes);
    }
    paths = order_paths(std::move(paths), at, options.optimise_work);
    for (auto& p : paths) p = without_straight_vertices(p);
    stats.travel_mm = travel_mm(paths, at);
    for (auto& p : paths) {
      // Overcut closes a loop; the blade offset applies to every pass, turns included.
      const std::vector<Point2> tip = with_passes(with_overcut(p, options.overcut_mm), kp.passes);
      at = tip.back();  // the next kind is ordered from where the blade tip stands
      if (const std::vector<Point2> pre = precut_path(tip, options.precut_mm); !pre.empty()) {
        // Turn the blade: cut the stroke's own first millimetres, lift, and start again there.
        Stroke ps{kind, blade_offset_path(pre, options.blade_offset_mm, options.swivel_step_deg), true};
        stats.cut_mm += path_length_mm(ps.points);
        stats.travel_mm += path_length_mm(pre);  // back to the stroke's start, knife up
        ++stats.precuts;
        ++stats.pen_lifts;
        plan.strokes.push_back(std::move(ps));
      }
      Stroke s{kind, blade_offset_path(tip, options.blade_offset_mm, options.swivel_step_deg)};
      stats.cut_mm += path_length_mm(s.points);
      ++stats.strokes;
      ++stats.pen_lifts;
      plan.strokes.push_back(std::move(s));
    }
  }
  return plan;
}

double move_time_s(double length_mm, double speed_mm_s, double accel_mm_s2) {
  if (length_mm <= 0 || speed_mm_s <= 0) return 0;
  if (accel_mm_s2 <= 0) return length_mm / speed_mm_s;
  const double ramp_mm = speed_mm_s * speed_mm_s / accel_mm_s2;  // accelerate + decelerate
  if (length_mm >= ramp_mm) return length_mm / speed_mm_s + speed_mm_s / accel_mm_s2;
  return 2 * std::sqrt(length_mm / accel_mm_s2);
}

TimeEstimate estimate_time(const StrokePlan& plan, const Kinematics& k, const std::array<double, 4>& cut_speed_mm_s) {
  TimeEstimate est;
  Point2 at = plan.home;
  for (const Stroke& s : plan.strokes) {
    double& t = est.kind_s[index_of(s.kind)];
    t += move_time_s(dist(at, s.points.front()), k.travel_speed_mm_s, k.accel_mm_s2) + k.knife_down_s + k.knife_up_s;
    for (std::size_t i = 1; i < s.points.size(); ++i) {
      t += move_time_s(dist(s.points[i - 1], s.points[i]), cut_speed_mm_s[index_of(s.kind)], k.accel_mm_s2);
    }
    at = s.points.back();
  }
  for (double t : est.kind_s) est.total_s += t;
  return est;
}

}  // namespace popcut
