// Chaining: a kind's segments split at junctions and joined into the fewest knife-down trails.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut {

// Splits segments where another's endpoint lies inside them, so chains may turn there.
std::vector<std::pair<Point2, Point2>> split_at_junctions(const std::vector<std::pair<Point2, Point2>>& segments);

// Minimum number of strokes covering a graph's edges once each: per connected component
// max(1, odd-degree vertices / 2).
int euler_bound(const std::vector<std::pair<Point2, Point2>>& edges);

// Chains edges into exactly euler_bound() trails (then splits at turns sharper than max_turn_deg).
std::vector<std::vector<Point2>> chain_edges(const std::vector<std::pair<Point2, Point2>>& edges,
                                             std::optional<double> max_turn_deg);

}  // namespace popcut
