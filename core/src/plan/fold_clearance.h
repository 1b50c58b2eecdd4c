// Which parts of a fold may be scored: those at least the fold gap (Euclidean) from every cut and the outline.
#pragma once

#include <utility>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut::plan_detail {

// The pieces of fold ab whose every point is at least gap_mm from each of `cuts` (segments),
// as (start, end) parameters along ab in [0, 1], in order. Measured as a distance in the
// plane, so a cut meeting the fold at a slant takes gap / sin(angle) of it, not gap; a cut
// passing near the fold's middle splits it. Pieces shorter than min_piece_mm are left out.
std::vector<std::pair<double, double>> clear_pieces(Point2 a, Point2 b,
                                                    const std::vector<std::pair<Point2, Point2>>& cuts, double gap_mm,
                                                    double min_piece_mm);

}  // namespace popcut::plan_detail
