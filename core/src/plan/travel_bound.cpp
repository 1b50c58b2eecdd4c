// Knife-up lower bound: min-weight perfect matching over stroke ends, with connectivity cuts
// added by Lagrangian relaxation.
#include "popcut/plan/travel_bound.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>

#include "plan/line_graph.h"
#include "plan/min_matching.h"

namespace popcut {
namespace {

// Why this is a bound. In a plan at the Euler bound every odd vertex of a component ends exactly
// one stroke and no other vertex ends one (k = odd/2 strokes have 2k ends, each odd vertex needs
// an odd number of them); a component without odd vertices is one closed stroke, entered and
// left at one point of it. Call the stroke ends "ends": each odd vertex; two per closed loop
// (located anywhere on the loop: a relaxation of "both at the same point"); `home`; and a free
// final end F. The knife-up moves M then pair the ends perfectly: home with the first stroke's
// start, each stroke's end with the next one's start, the last stroke's end with F at cost 0.
// The strokes themselves pair ends inside their component (T), and with home–F added, M ∪ T is
// one cycle through all ends. So, for every plan:
//  (1) M is a perfect matching on the allowed pairs: no move inside a cluster of two ends (a
//      loop, a one-stroke component, {home, F}: it would close a 2-cycle); moves only inside a
//      kind or between consecutive kinds; home only to the first kind, F only to the last.
//      Its cost is at least cost(nearest distance) per pair, since cost is non-decreasing.
//  (2) M crosses every cut S (a proper, non-empty union of clusters) at least twice: the cycle
//      crosses S an even, non-zero number of times and T never does.
//  (3) M has exactly one pair between consecutive kinds (all of one kind is cut before the next).
// The bound: min over perfect matchings of cost(M) − Σ_S μ_S (|M ∩ δS| − 2) + Σ_k λ_k (x_k − 1)
// for any μ ≥ 0 and λ: on every real plan the added terms are ≤ 0, so the minimum is at most
// the plan's cost (Lagrangian relaxation). μ = λ = 0 is the plain matching bound; subgradient
// steps raise it, and the cuts are the clusters' components that the current matching leaves
// apart (it crosses them 0 times). Edge costs are rounded down to 1e-6 units: still a bound.

constexpr double kScale = 1e6;  // matching weights are integers: costs in 1e-6 units, rounded down

double dist(Point2 a, Point2 b) { return std::hypot(a.x_mm - b.x_mm, a.v_mm - b.v_mm); }

double point_segment(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, l2 = dx * dx + dv * dv;
  const double t = l2 > 0 ? std::clamp(((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / l2, 0.0, 1.0) : 0.0;
  return dist(p, {a.x_mm + t * dx, a.v_mm + t * dv});
}

double cross(Point2 o, Point2 a, Point2 b) {
  return (a.x_mm - o.x_mm) * (b.v_mm - o.v_mm) - (a.v_mm - o.v_mm) * (b.x_mm - o.x_mm);
}

// Segments of different components may cross without sharing a vertex (only T-junctions are
// split): a proper crossing is distance 0; otherwise the nearest pair involves an end point.
double segment_segment(Point2 a, Point2 b, Point2 c, Point2 d) {
  const double c1 = cross(a, b, c), c2 = cross(a, b, d), c3 = cross(c, d, a), c4 = cross(c, d, b);
  if (((c1 < 0 && c2 > 0) || (c1 > 0 && c2 < 0)) && ((c3 < 0 && c4 > 0) || (c3 > 0 && c4 < 0))) return 0;
  return std::min({point_segment(a, c, d), point_segment(b, c, d), point_segment(c, a, b), point_segment(d, a, b)});
}

struct End {
  int rank;     // 0 home, 1..K the kinds with lines, K + 1 the free final end
  int cluster;  // 0 = {home, final}; then one per component
  Point2 at;    // an odd vertex or home
  int loop;     // closed loop: index into Problem::loops (the end lies anywhere on it); else -1
};

struct Problem {
  std::vector<End> ends;
  std::vector<std::vector<std::pair<Point2, Point2>>> loops;
  std::vector<int> cluster_size;
  int kinds = 0;  // K
};

Problem ends_of(const std::vector<std::vector<std::pair<Point2, Point2>>>& kinds, Point2 home) {
  Problem pr;
  pr.ends.push_back({0, 0, home, -1});
  pr.cluster_size.push_back(2);
  for (const auto& edges : kinds) {
    const plan_detail::Graph g = plan_detail::build_graph(edges);
    if (g.edges.empty()) continue;
    const int rank = ++pr.kinds;
    int count = 0;
    const std::vector<int> comp = plan_detail::components(g, count);
    std::vector<std::vector<int>> odd(static_cast<std::size_t>(count));
    std::vector<std::vector<std::pair<Point2, Point2>>> segs(static_cast<std::size_t>(count));
    for (std::size_t v = 0; v < g.pos.size(); ++v) {
      if (g.adj[v].size() % 2 == 1) odd[static_cast<std::size_t>(comp[v])].push_back(static_cast<int>(v));
    }
    for (const auto& [u, w] : g.edges) {
      segs[static_cast<std::size_t>(comp[static_cast<std::size_t>(u)])].emplace_back(
          g.pos[static_cast<std::size_t>(u)], g.pos[static_cast<std::size_t>(w)]);
    }
    for (std::size_t c = 0; c < odd.size(); ++c) {
      if (segs[c].empty()) continue;
      const int cluster = static_cast<int>(pr.cluster_size.size());
      if (odd[c].empty()) {
        const int loop = static_cast<int>(pr.loops.size());
        pr.loops.push_back(segs[c]);
        pr.ends.push_back({rank, cluster, segs[c].front().first, loop});
        pr.ends.push_back({rank, cluster, segs[c].front().first, loop});
        pr.cluster_size.push_back(2);
      } else {
        for (int v : odd[c]) pr.ends.push_back({rank, cluster, g.pos[static_cast<std::size_t>(v)], -1});
        pr.cluster_size.push_back(static_cast<int>(odd[c].size()));
      }
    }
  }
  pr.ends.push_back({pr.kinds + 1, 0, home, -1});
  return pr;
}

// Nearest distance between two ends' possible positions.
double end_distance(const Problem& pr, const End& a, const End& b) {
  if (a.loop < 0 && b.loop < 0) return dist(a.at, b.at);
  if (a.loop >= 0 && b.loop >= 0) {
    double d = 1e300;
    for (const auto& [p, q] : pr.loops[static_cast<std::size_t>(a.loop)]) {
      for (const auto& [r, s] : pr.loops[static_cast<std::size_t>(b.loop)])
        d = std::min(d, segment_segment(p, q, r, s));
    }
    return d;
  }
  const End& loop = a.loop >= 0 ? a : b;
  const Point2 p = a.loop >= 0 ? b.at : a.at;
  double d = 1e300;
  for (const auto& [r, s] : pr.loops[static_cast<std::size_t>(loop.loop)]) d = std::min(d, point_segment(p, r, s));
  return d;
}

struct Pair {
  int a, b;
  double cost;
  int between;  // k when the pair joins kind k and kind k + 1 (1 <= k < K), else -1
};

// Every pair of ends a knife-up move may join (see (1) above), with its cost.
std::vector<Pair> allowed_pairs(const Problem& pr, const std::function<double(double)>& cost) {
  const int n = static_cast<int>(pr.ends.size());
  const int last = pr.kinds + 1;
  std::vector<Pair> pairs;
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      const End &a = pr.ends[static_cast<std::size_t>(i)], &b = pr.ends[static_cast<std::size_t>(j)];
      if (std::abs(a.rank - b.rank) > 1) continue;
      if (a.cluster == b.cluster && pr.cluster_size[static_cast<std::size_t>(a.cluster)] == 2) continue;
      const bool free_end = a.rank == last || b.rank == last;
      const int lo = std::min(a.rank, b.rank);
      const int between = a.rank != b.rank && lo >= 1 && lo < pr.kinds ? lo : -1;
      pairs.push_back({i, j, free_end ? 0.0 : cost(end_distance(pr, a, b)), between});
    }
  }
  return pairs;
}

// New cuts: the groups of clusters the chosen matching leaves unconnected, each with the pairs
// crossing it and μ = 0; cuts already known are skipped, and none are added past 4000.
void add_unconnected_cuts(const Problem& pr, const std::vector<Pair>& pairs, const std::vector<char>& chosen,
                          std::set<std::vector<char>>& known_cuts, std::vector<std::vector<int>>& cut_pairs,
                          std::vector<double>& mu) {
  const std::size_t clusters = pr.cluster_size.size();
  std::vector<std::size_t> parent(clusters);
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const auto cluster_of = [&](int end) {
    return static_cast<std::size_t>(pr.ends[static_cast<std::size_t>(end)].cluster);
  };
  for (std::size_t e = 0; e < pairs.size(); ++e) {
    if (chosen[e]) parent[find(cluster_of(pairs[e].a))] = find(cluster_of(pairs[e].b));
  }
  std::vector<std::size_t> roots;
  for (std::size_t c = 0; c < clusters; ++c) {
    if (find(c) == c) roots.push_back(c);
  }
  if (roots.size() <= 1 || known_cuts.size() >= 4000) return;
  for (std::size_t r : roots) {
    std::vector<char> in(clusters);
    for (std::size_t c = 0; c < clusters; ++c) in[c] = find(c) == r ? 1 : 0;
    if (in[0]) {
      for (char& x : in) x = static_cast<char>(!x);  // a cut and its complement are the same cut
    }
    if (!known_cuts.insert(in).second) continue;
    std::vector<int> crossing;
    for (std::size_t e = 0; e < pairs.size(); ++e) {
      if (in[cluster_of(pairs[e].a)] != in[cluster_of(pairs[e].b)]) crossing.push_back(static_cast<int>(e));
    }
    cut_pairs.push_back(std::move(crossing));
    mu.push_back(0);
  }
}

}  // namespace

KnifeUpBound knife_up_lower_bound(const std::vector<std::vector<std::pair<Point2, Point2>>>& kinds, Point2 home,
                                  const std::function<double(double)>& cost, double plan_cost) {
  const Problem pr = ends_of(kinds, home);
  if (pr.kinds == 0) return {};
  const int n = static_cast<int>(pr.ends.size());
  const std::vector<Pair> pairs = allowed_pairs(pr, cost);

  std::vector<plan_detail::WeightedPair> graph(pairs.size());
  for (std::size_t e = 0; e < pairs.size(); ++e) graph[e] = {pairs[e].a, pairs[e].b, 0};

  std::vector<std::vector<int>> cut_pairs;  // per cut: the pairs crossing it
  std::vector<double> mu;                   // per cut, >= 0
  std::set<std::vector<char>> known_cuts;
  std::vector<double> lambda(static_cast<std::size_t>(std::max(0, pr.kinds - 1)), 0.0);  // index k - 1
  std::vector<double> modified(pairs.size());
  std::vector<char> chosen(pairs.size());
  KnifeUpBound out;
  double best = -1e300, theta = 1.0;
  int since_better = 0;
  for (int iteration = 0; iteration < 400; ++iteration) {
    for (std::size_t e = 0; e < pairs.size(); ++e) {
      modified[e] =
          pairs[e].cost + (pairs[e].between > 0 ? lambda[static_cast<std::size_t>(pairs[e].between - 1)] : 0.0);
    }
    double constant = 0;
    for (std::size_t s = 0; s < mu.size(); ++s) {
      if (mu[s] <= 0) continue;
      for (int e : cut_pairs[s]) modified[static_cast<std::size_t>(e)] -= mu[s];
      constant += 2 * mu[s];
    }
    for (double l : lambda) constant -= l;
    for (std::size_t e = 0; e < pairs.size(); ++e)
      graph[e].weight = static_cast<long long>(std::floor(modified[e] * kScale));
    const std::optional<long long> least = plan_detail::min_weight_perfect_matching(n, graph, chosen);
    if (!least) throw std::logic_error("knife_up_lower_bound: no perfect matching, yet every plan gives one");
    const double value = static_cast<double>(*least) / kScale + constant;
    if (iteration == 0) out.matching = value;
    if (value > best + 1e-9 * std::max(1.0, std::abs(best))) {
      best = value;
      since_better = 0;
    } else if (++since_better >= 5) {
      theta /= 2;
      since_better = 0;
    }
    if (theta < 1e-3 || best >= plan_cost - 1e-9) break;

    add_unconnected_cuts(pr, pairs, chosen, known_cuts, cut_pairs, mu);
    // Subgradient step towards plan_cost (Polyak), then keep μ >= 0.
    std::vector<double> g_mu(mu.size()), g_lambda(lambda.size(), -1.0);
    double norm = 0;
    for (std::size_t s = 0; s < mu.size(); ++s) {
      int crossed = 0;
      for (int e : cut_pairs[s]) crossed += chosen[static_cast<std::size_t>(e)];
      g_mu[s] = 2.0 - crossed;
      if (mu[s] <= 0 && g_mu[s] < 0) g_mu[s] = 0;  // projected: it cannot go lower
      norm += g_mu[s] * g_mu[s];
    }
    for (std::size_t e = 0; e < pairs.size(); ++e) {
      if (chosen[e] && pairs[e].between > 0) g_lambda[static_cast<std::size_t>(pairs[e].between - 1)] += 1;
    }
    for (double x : g_lambda) norm += x * x;
    if (norm == 0) break;  // the matching meets every constraint: nothing left to gain
    const double step = theta * std::max(plan_cost - value, 1e-9 * std::max(1.0, plan_cost)) / norm;
    for (std::size_t s = 0; s < mu.size(); ++s) mu[s] = std::max(0.0, mu[s] + step * g_mu[s]);
    for (std::size_t k = 0; k < lambda.size(); ++k) lambda[k] += step * g_lambda[k];
  }
  out.value = std::max(best, out.matching);
  return out;
}

}  // namespace popcut
