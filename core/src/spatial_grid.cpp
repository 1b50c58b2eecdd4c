// The uniform grid behind junction splitting, fold gaps, the tour's neighbours, and snapping a drawing's ends.
#include "popcut/spatial_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace popcut {

SpatialGrid::SpatialGrid(Rect box, std::size_t items) {
  const double w = std::max(box.max.x_mm - box.min.x_mm, 1e-3), h = std::max(box.max.v_mm - box.min.v_mm, 1e-3);
  const double cells = std::max<double>(1, static_cast<double>(items));
  // Square cells about one item each, but never so small that the 4096-cell cap leaves part of the
  // box outside the grid: points clamped into an edge cell would make every query scan them all.
  cell_mm_ = std::max({std::sqrt(w * h / cells), w / 4096, h / 4096, 1e-3});
  origin_ = box.min;
  nx_ = std::min<long>(4096, static_cast<long>(w / cell_mm_) + 1);
  nv_ = std::min<long>(4096, static_cast<long>(h / cell_mm_) + 1);
  cells_.resize(static_cast<std::size_t>(nx_ * nv_));
}

namespace {

// Not std::hypot: its overflow care costs several times more, and millimetres never overflow.
double dist(Point2 a, Point2 b) {
  const double dx = a.x_mm - b.x_mm, dv = a.v_mm - b.v_mm;
  return std::sqrt(dx * dx + dv * dv);
}

// The cell index of an offset, clamped to [0, n - 1] before the cast: a NaN, an infinity or a far
// point then lands in an edge cell instead of an undefined conversion.
long cell_index(double offset_cells, long n) {
  if (!(offset_cells > 0)) return 0;
  if (offset_cells >= static_cast<double>(n - 1)) return n - 1;
  return static_cast<long>(offset_cells);
}

}  // namespace

long SpatialGrid::cx(double x) const { return cell_index((x - origin_.x_mm) / cell_mm_, nx_); }
long SpatialGrid::cv(double v) const { return cell_index((v - origin_.v_mm) / cell_mm_, nv_); }

void SpatialGrid::mark(int id) {
  if (seen_.size() <= static_cast<std::size_t>(id)) seen_.resize(static_cast<std::size_t>(id) + 1, 0);
}

void SpatialGrid::insert(int id, Point2 lo, Point2 hi) {
  mark(id);
  for (long v = cv(lo.v_mm); v <= cv(hi.v_mm); ++v)
    for (long x = cx(lo.x_mm); x <= cx(hi.x_mm); ++x) cell(x, v).push_back(id);
}

void SpatialGrid::insert_segment(int id, Point2 a, Point2 b, double pad_mm) {
  mark(id);
  if (a.v_mm > b.v_mm) std::swap(a, b);
  const double dv = b.v_mm - a.v_mm;
  // A hair more than pad_mm, so a rounding in the clip below can never drop a cell.
  const double pad = pad_mm + 1e-9 * (1 + std::abs(a.x_mm) + std::abs(b.x_mm));
  const long last = cv(b.v_mm + pad);
  for (long v = cv(a.v_mm - pad); v <= last; ++v) {
    // The part of ab whose points come within pad of this row (the edge rows reach to infinity,
    // as cv() clamps to them), then its x extent widened by pad.
    double t0 = 0, t1 = 1;
    if (dv > 0) {
      const double row_lo = origin_.v_mm + static_cast<double>(v) * cell_mm_ - pad;
      const double row_hi = row_lo + cell_mm_ + 2 * pad;
      if (v > 0) t0 = std::clamp((row_lo - a.v_mm) / dv, 0.0, 1.0);
      if (v < nv_ - 1) t1 = std::clamp((row_hi - a.v_mm) / dv, 0.0, 1.0);
    }
    const double x0 = a.x_mm + (b.x_mm - a.x_mm) * t0, x1 = a.x_mm + (b.x_mm - a.x_mm) * t1;
    for (long x = cx(std::min(x0, x1) - pad); x <= cx(std::max(x0, x1) + pad); ++x) cell(x, v).push_back(id);
  }
}

void SpatialGrid::insert(int id, Point2 at, int group) {
  if (points_.size() <= static_cast<std::size_t>(id)) points_.resize(static_cast<std::size_t>(id) + 1);
  points_[static_cast<std::size_t>(id)] = {at, group};
  insert(id, at, at);
}

void SpatialGrid::erase(int id, Point2 at) {
  std::vector<int>& c = cell(cx(at.x_mm), cv(at.v_mm));
  const auto it = std::find(c.begin(), c.end(), id);
  if (it == c.end()) return;
  *it = c.back();
  c.pop_back();
}

const std::vector<int>& SpatialGrid::at(Point2 p) const { return cell(cx(p.x_mm), cv(p.v_mm)); }

void SpatialGrid::ids_in_box(Point2 lo, Point2 hi, std::vector<int>& out) {
  out.clear();
  for (long v = cv(lo.v_mm); v <= cv(hi.v_mm); ++v) {
    for (long x = cx(lo.x_mm); x <= cx(hi.x_mm); ++x) {
      for (int id : cell(x, v)) {
        if (!seen_[static_cast<std::size_t>(id)]) {
          seen_[static_cast<std::size_t>(id)] = 1;
          out.push_back(id);
        }
      }
    }
  }
  for (int id : out) seen_[static_cast<std::size_t>(id)] = 0;
}

// Ring r of cells around the query's cell (r = 0: that cell alone): whole rows at its top and
// bottom, two cells on the rows between. Keeps the k least (distance, id) pairs seen.
void SpatialGrid::gather_ring(Point2 at, long r, std::size_t k, int skip_group,
                              std::vector<std::pair<double, int>>& found) const {
  const long qx = cx(at.x_mm), qv = cv(at.v_mm);
  // Only the ring's rows inside the grid, and of its top and bottom rows only the cells inside:
  // a query near an edge (or a long thin grid) then costs the cells there are.
  for (long v = std::max(0L, qv - r); v <= std::min(nv_ - 1, qv + r); ++v) {
    const bool edge_row = v == qv - r || v == qv + r;
    const long step = edge_row ? 1 : 2 * r;
    for (long x = edge_row ? std::max(0L, qx - r) : qx - r; x <= (edge_row ? std::min(nx_ - 1, qx + r) : qx + r);
         x += step) {
      if (x < 0 || x >= nx_) continue;
      for (int id : cell(x, v)) {
        const Item& item = points_[static_cast<std::size_t>(id)];
        if (item.group == skip_group) continue;
        const std::pair<double, int> candidate{dist(at, item.at), id};
        if (found.size() >= k && !(candidate < found.back())) continue;
        if (found.size() < k)
          found.push_back(candidate);
        else
          found.back() = candidate;
        for (std::size_t j = found.size() - 1; j > 0 && found[j] < found[j - 1]; --j) std::swap(found[j], found[j - 1]);
      }
    }
  }
}

void SpatialGrid::nearest(Point2 at, std::size_t k, int skip_group, std::vector<std::pair<double, int>>& found) const {
  found.clear();
  if (k == 0) return;
  // A point r rings out is at least r - 1 cells away: past that, nothing can displace the k-th.
  for (long r = 0; r <= std::max(nx_, nv_); ++r) {
    if (found.size() >= k && (static_cast<double>(r) - 1) * cell_mm_ > found[k - 1].first) break;
    gather_ring(at, r, k, skip_group, found);
  }
}

}  // namespace popcut
