// The line graph that planning and its travel bound share: vertices where segment ends meet.
#pragma once

#include <utility>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut::plan_detail {

struct Graph {
  std::vector<Point2> pos;
  std::vector<std::pair<int, int>> edges;
  std::vector<std::vector<std::pair<int, int>>> adj;  // (edge, other vertex)
};

// Ends closer than 1e-6 mm are one vertex; zero-length segments are left out.
Graph build_graph(const std::vector<std::pair<Point2, Point2>>& segs);

// Connected component of each vertex, numbered from 0; `count` receives how many.
std::vector<int> components(const Graph& g, int& count);

}  // namespace popcut::plan_detail
