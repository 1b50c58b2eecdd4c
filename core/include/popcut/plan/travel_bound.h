// Lower bounds on the knife-up moves of every plan at the Euler bound: for benchmarks and reports.
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut {

struct KnifeUpBound {
  double matching = 0;  // min-weight perfect matching over stroke ends (no connectivity)
  double value = 0;     // the best bound found: the matching with connectivity (>= matching)
};

// A lower bound on the sum of cost(length) over the knife-up moves of ANY plan that cuts the line
// graphs `kinds` (each split at junctions, in cutting order: every stroke of one kind before the
// next kind's) from `home`, in the minimum number of strokes (per component of each kind
// max(1, odd vertices / 2)), each stroke cut once from one end to the other: any trail
// decomposition, order, direction and closed-loop start (even mid-segment). The last stroke ends
// anywhere. `cost` must be non-decreasing with cost(0) = 0 (the length itself, or a move's time).
// `plan_cost` is the cost of some real plan; it only steers the search's step size, so the result
// is a bound whatever it is. O(ends³) per matching, a few hundred matchings: never for planning.
KnifeUpBound knife_up_lower_bound(const std::vector<std::vector<std::pair<Point2, Point2>>>& kinds, Point2 home,
                                  const std::function<double(double)>& cost, double plan_cost);

}  // namespace popcut
