// Builds the cell index of a SegmentGrid: each segment sampled every half cell along its length.
#include "pattern/segment_grid.h"

#include <algorithm>
#include <cmath>

namespace popcut::detail {

SegmentGrid::SegmentGrid(const std::vector<std::pair<Point2, Point2>>& segments, double cell_mm) : cell_mm_(cell_mm) {
  std::vector<std::pair<long long, std::size_t>> entries;
  entries.reserve(segments.size() * 2);
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const auto& [a, b] = segments[s];
    const double len = std::hypot(b.x_mm - a.x_mm, b.v_mm - a.v_mm);
    const int steps = static_cast<int>(std::ceil(len / (cell_mm_ / 2))) + 1;
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      const long long key_here = key(cell(a.x_mm + (b.x_mm - a.x_mm) * t), cell(a.v_mm + (b.v_mm - a.v_mm) * t));
      if (entries.empty() || entries.back() != std::pair{key_here, s}) entries.emplace_back(key_here, s);
    }
  }
  std::sort(entries.begin(), entries.end());
  entries.erase(std::unique(entries.begin(), entries.end()), entries.end());
  members_.reserve(entries.size());
  ranges_.reserve(entries.size());
  for (std::size_t k = 0; k < entries.size();) {
    std::size_t end = k;
    while (end < entries.size() && entries[end].first == entries[k].first) members_.push_back(entries[end++].second);
    ranges_.emplace(entries[k].first, std::pair{k, end});
    k = end;
  }
}

long long SegmentGrid::cell(double x_mm) const { return static_cast<long long>(std::floor(x_mm / cell_mm_)); }

}  // namespace popcut::detail
