// Ordering: the cutting order of a kind's paths, each one's direction and each closed loop's start.
#pragma once

#include <cstdint>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut {

// Small cards converge far below this; a 10,000-segment pattern stops here after some 50 ms.
inline constexpr std::uint64_t kDefaultOptimiseWork = 500'000;

// Orders paths from `start` to cut knife-up travel: greedy nearest neighbour over a grid, then
// 2-opt and Or-opt (with reversal) over near path ends until no move gains or `work_budget`
// steps are spent; picks each open path's direction and each closed loop's start (a vertex, or a
// point inside a segment, which then becomes the loop's first and last point). Deterministic. Empty
// paths are dropped.
std::vector<std::vector<Point2>> order_paths(std::vector<std::vector<Point2>> paths, Point2 start,
                                             std::uint64_t work_budget = kDefaultOptimiseWork);

// Knife-up distance to walk `paths` in order from `start`.
double travel_mm(const std::vector<std::vector<Point2>>& paths, Point2 start);

}  // namespace popcut
