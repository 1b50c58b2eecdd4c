// Chaining: junction splits, the line graph (plan/line_graph.h), the Euler bound and Hierholzer trails.
#include "popcut/plan/chaining.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "plan/line_graph.h"
#include "plan/path_geometry.h"
#include "popcut/spatial_grid.h"

namespace popcut {

using plan_detail::build_graph;
using plan_detail::components;
using plan_detail::dist;
using plan_detail::Graph;
using plan_detail::kEps;
using plan_detail::lerp;
using plan_detail::same;

namespace {

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

// Degrees the direction turns at b when going a → b → c (0 = straight on, 180 = back).
double turn_deg(Point2 a, Point2 b, Point2 c) {
  const double ux = b.x_mm - a.x_mm, uv = b.v_mm - a.v_mm, wx = c.x_mm - b.x_mm, wv = c.v_mm - b.v_mm;
  const double n = std::hypot(ux, uv) * std::hypot(wx, wv);
  if (n <= 0) return 0;
  return std::acos(std::clamp((ux * wx + uv * wv) / n, -1.0, 1.0)) * 180 / plan_detail::kPi;
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

// Pairs the odd vertices of each component with virtual edges (numbered from the real ones' count
// on): the graph then has an Euler circuit per component.
void add_virtual_edges(Graph& g, const std::vector<int>& comp, int count) {
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
}

// Iterative Hierholzer from s over the unused edges: the closed walk as (vertex, edge used to
// arrive), the first with edge -1. `used` and `next` carry over between components.
std::vector<std::pair<int, int>> euler_circuit(const Graph& g, std::size_t s, std::vector<char>& used,
                                               std::vector<std::size_t>& next) {
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
  return circuit;
}

// A closed circuit cut at its virtual edges into trails of real edges, appended to `trails`.
void cut_at_virtual_edges(const Graph& g, const std::vector<std::pair<int, int>>& circuit, std::size_t real_edges,
                          std::vector<std::vector<Point2>>& trails) {
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

std::vector<std::pair<Point2, Point2>> split_at_junctions(const std::vector<std::pair<Point2, Point2>>& segs) {
  std::vector<std::pair<Point2, Point2>> out;
  if (segs.empty()) return out;
  std::vector<Point2> ends;
  for (const auto& [a, b] : segs) ends.insert(ends.end(), {a, b});
  SpatialGrid grid(bounds(ends), segs.size());
  for (std::size_t i = 0; i < segs.size(); ++i)
    grid.insert_segment(static_cast<int>(i), segs[i].first, segs[i].second, kEps);
  std::vector<std::vector<double>> cuts_at(segs.size());
  for (Point2 p : ends) {
    for (int j : grid.at(p)) {
      const auto& s = segs[static_cast<std::size_t>(j)];
      const double t = interior_param(p, s.first, s.second);
      if (t > 0) cuts_at[static_cast<std::size_t>(j)].push_back(t);
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
  // An Euler circuit of the graph with its odd vertices paired, cut at the virtual edges, is
  // exactly odd/2 trails (or one closed trail when none are odd).
  add_virtual_edges(g, comp, count);
  std::vector<char> used(g.edges.size(), 0);
  std::vector<std::size_t> next(g.pos.size(), 0);
  std::vector<char> comp_done(static_cast<std::size_t>(count), 0);
  std::vector<std::vector<Point2>> trails;
  for (std::size_t s = 0; s < g.pos.size(); ++s) {
    const auto c = static_cast<std::size_t>(comp[s]);
    if (comp_done[c] || g.adj[s].empty()) continue;
    comp_done[c] = 1;
    cut_at_virtual_edges(g, euler_circuit(g, s, used, next), real_edges, trails);
  }
  if (!max_turn_deg) return trails;
  std::vector<std::vector<Point2>> out;
  for (auto& t : trails) {
    for (auto& piece : split_at_turns(std::move(t), *max_turn_deg)) out.push_back(std::move(piece));
  }
  return out;
}

namespace plan_detail {

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

}  // namespace popcut
