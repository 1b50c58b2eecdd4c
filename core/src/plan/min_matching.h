// Minimum-weight perfect matching (LEMON's blossom algorithm) behind a plain, std-only interface.
#pragma once

#include <optional>
#include <vector>

namespace popcut::plan_detail {

struct WeightedPair {
  int a, b;          // vertices, 0 .. n-1
  long long weight;  // any sign; integers, so the blossom algorithm's duals stay exact
};

// The least total weight of a perfect matching of vertices 0..n-1 over `pairs`, with
// chosen[i] = 1 for the pairs in it; nullopt when no perfect matching exists.
std::optional<long long> min_weight_perfect_matching(int n, const std::vector<WeightedPair>& pairs,
                                                     std::vector<char>& chosen);

}  // namespace popcut::plan_detail
