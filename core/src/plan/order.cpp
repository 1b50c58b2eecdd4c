// Ordering: the greedy nearest-neighbour tour, handed to the local search (plan/tour_search.h).
#include "popcut/plan/order.h"

#include <utility>

#include "plan/path_geometry.h"
#include "plan/tour_search.h"
#include "popcut/spatial_grid.h"

namespace popcut {

using plan_detail::dist;
using plan_detail::is_closed;

namespace {

// Greedy nearest neighbour from `start`: entries are both ends of an open path and every vertex
// of a closed loop, found through a grid (ties: the entry first in path order); picks each path's
// direction and each loop's start.
std::vector<std::vector<Point2>> greedy_order(std::vector<std::vector<Point2>> paths, Point2 start) {
  const std::size_t n = paths.size();
  struct Entry {
    int path;
    int vertex;
  };
  std::vector<Entry> entries;
  std::vector<std::size_t> first_entry;  // of each path; its entries run up to the next path's
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = paths[i];
    first_entry.push_back(entries.size());
    if (is_closed(p)) {
      for (std::size_t k = 0; k + 1 < p.size(); ++k) entries.push_back({static_cast<int>(i), static_cast<int>(k)});
    } else {
      entries.push_back({static_cast<int>(i), 0});
      entries.push_back({static_cast<int>(i), static_cast<int>(p.size() - 1)});
    }
  }
  first_entry.push_back(entries.size());
  std::vector<Point2> pts;
  for (const Entry& e : entries)
    pts.push_back(paths[static_cast<std::size_t>(e.path)][static_cast<std::size_t>(e.vertex)]);
  pts.push_back(start);
  SpatialGrid grid(bounds(pts), entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i) grid.insert(static_cast<int>(i), pts[i]);
  std::vector<std::vector<Point2>> tour;
  std::vector<std::pair<double, int>> nearest;
  Point2 at = start;
  for (std::size_t step = 0; step < n; ++step) {
    grid.nearest(at, 1, SpatialGrid::kNoGroup, nearest);
    const Entry e = entries[static_cast<std::size_t>(nearest.front().second)];
    const auto s = static_cast<std::size_t>(e.path);
    for (std::size_t k = first_entry[s]; k < first_entry[s + 1]; ++k) grid.erase(static_cast<int>(k), pts[k]);
    auto p = std::move(paths[s]);
    if (is_closed(p))
      plan_detail::rotate_loop(p, static_cast<std::size_t>(e.vertex));
    else if (e.vertex != 0)
      p = plan_detail::reversed(std::move(p));
    at = p.back();
    tour.push_back(std::move(p));
  }
  return tour;
}

}  // namespace

std::vector<std::vector<Point2>> order_paths(std::vector<std::vector<Point2>> paths, Point2 start,
                                             std::uint64_t work_budget) {
  // An empty path has nothing to cut and no end to travel to.
  std::erase_if(paths, [](const std::vector<Point2>& p) { return p.empty(); });
  if (paths.empty()) return paths;
  std::vector<std::vector<Point2>> tour = greedy_order(std::move(paths), start);
  if (work_budget == 0) return tour;
  return plan_detail::TourSearch(std::move(tour), start, work_budget).run();
}

double travel_mm(const std::vector<std::vector<Point2>>& paths, Point2 start) {
  double t = 0;
  for (const auto& p : paths) {
    t += dist(start, p.front());
    start = p.back();
  }
  return t;
}

}  // namespace popcut
