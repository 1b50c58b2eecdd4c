// LEMON's weighted perfect matching, kept in this one file: LEMON 1.3's maps use allocator
// members that C++20 removed, so this file alone is compiled as C++17 (core/CMakeLists.txt).
#include "plan/min_matching.h"

#include <lemon/matching.h>
#include <lemon/smart_graph.h>

namespace popcut::plan_detail {

std::optional<long long> min_weight_perfect_matching(int n, const std::vector<WeightedPair>& pairs,
                                                     std::vector<char>& chosen) {
  lemon::SmartGraph g;
  g.reserveNode(n);
  g.reserveEdge(static_cast<int>(pairs.size()));
  std::vector<lemon::SmartGraph::Node> node(static_cast<std::size_t>(n));
  for (auto& v : node) v = g.addNode();
  std::vector<lemon::SmartGraph::Edge> edge;
  edge.reserve(pairs.size());
  lemon::SmartGraph::EdgeMap<long long> weight(g);
  for (const WeightedPair& p : pairs) {
    edge.push_back(g.addEdge(node[static_cast<std::size_t>(p.a)], node[static_cast<std::size_t>(p.b)]));
    weight[edge.back()] = -p.weight;  // LEMON maximises
  }
  lemon::MaxWeightedPerfectMatching<lemon::SmartGraph, lemon::SmartGraph::EdgeMap<long long>> matching(g, weight);
  if (!matching.run()) return std::nullopt;
  chosen.assign(pairs.size(), 0);
  for (std::size_t e = 0; e < pairs.size(); ++e) chosen[e] = matching.matching(edge[e]) ? 1 : 0;
  return -matching.matchingWeight();
}

}  // namespace popcut::plan_detail
