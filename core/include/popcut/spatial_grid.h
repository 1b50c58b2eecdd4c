// A uniform grid over points, boxes and segments: the one spatial index, for planning's junctions,
// fold gaps and nearest path ends, and a drawing's snapped ends and line comparisons.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "popcut/geometry.h"

namespace popcut {

// Items are small non-negative ids, each inserted as a box (found by at() and ids_in_box()) or as
// a point (found by nearest() as well); one grid holds one sort. The grid has about as many cells
// as it was sized for, at most 4096 a side; items outside its box fall into the edge cells, so
// every query stays exact, only slower.
class SpatialGrid {
 public:
  SpatialGrid(Rect box, std::size_t items);

  void insert(int id, Point2 lo, Point2 hi);  // a box: every cell it overlaps
  // The cells within pad_mm of segment ab (each row of cells only as wide as the segment passes
  // it, so a long slanted segment fills a band of cells, not its whole box).
  void insert_segment(int id, Point2 a, Point2 b, double pad_mm);
  // A point; nearest() skips the points of the query's `group` (a path's own ends).
  void insert(int id, Point2 at, int group = 0);
  void erase(int id, Point2 at);  // a point inserted before: nearest() no longer finds it

  // The items of the cell holding p, in the order they were inserted (erase() reorders).
  const std::vector<int>& at(Point2 p) const;
  // Each item in a cell that the box lo..hi meets, once: rows of cells upwards, each left to
  // right, a cell's items in order.
  void ids_in_box(Point2 lo, Point2 hi, std::vector<int>& out);

  // The up to k points nearest `at`, except those of `skip_group`, as (distance, id) in
  // ascending order: equal distances go to the lower id, so the answer is exactly that of sorting
  // every such point. Searches rings of cells outwards until no nearer point can exist.
  void nearest(Point2 at, std::size_t k, int skip_group, std::vector<std::pair<double, int>>& found) const;
  static constexpr int kNoGroup = -2;  // a skip_group no point has: every point counts

 private:
  struct Item {
    Point2 at;
    int group = 0;
  };
  long cx(double x) const;
  long cv(double v) const;
  void mark(int id);
  std::vector<int>& cell(long x, long v) { return cells_[static_cast<std::size_t>(v * nx_ + x)]; }
  const std::vector<int>& cell(long x, long v) const { return cells_[static_cast<std::size_t>(v * nx_ + x)]; }
  void gather_ring(Point2 at, long r, std::size_t k, int skip_group, std::vector<std::pair<double, int>>& found) const;

  Point2 origin_;
  double cell_mm_ = 1;
  long nx_ = 1, nv_ = 1;
  std::vector<std::vector<int>> cells_;
  std::vector<Item> points_;  // by id: where each point item lies
  std::vector<char> seen_;    // by id: ids_in_box's marks, all clear between calls
};

}  // namespace popcut
