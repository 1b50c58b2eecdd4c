// Segments binned by the grid cells they pass, to find the segments near a point without testing them all.
#pragma once

#include <cstddef>
#include <unordered_map>
#include <utility>
#include <vector>

#include "popcut/geometry.h"

namespace popcut::detail {

class SegmentGrid {
 public:
  // A query looks at the 3 × 3 cells around its point, and a segment is sampled every half cell,
  // so a segment within 3/4 of a cell of the point is always visited: `cell_mm` must be at least
  // 4/3 of the distance asked about.
  SegmentGrid(const std::vector<std::pair<Point2, Point2>>& segments, double cell_mm);

  // Calls visit(i) for every segment i that passes a cell next to p's (some more than once).
  template <typename Visit>
  void near(Point2 p, Visit visit) const {
    const long long i = cell(p.x_mm), j = cell(p.v_mm);
    for (long long di = -1; di <= 1; ++di)
      for (long long dj = -1; dj <= 1; ++dj)
        if (const auto it = ranges_.find(key(i + di, j + dj)); it != ranges_.end())
          for (std::size_t k = it->second.first; k < it->second.second; ++k) visit(members_[k]);
  }

 private:
  long long cell(double x_mm) const;
  static long long key(long long i, long long j) { return i * 73856093LL ^ j * 19349663LL; }

  double cell_mm_;
  // One contiguous run of segment indices per cell (a hash of vectors costs an allocation per cell).
  std::unordered_map<long long, std::pair<std::size_t, std::size_t>> ranges_;
  std::vector<std::size_t> members_;
};

}  // namespace popcut::detail
