// A street of walls for the designer's benchmarks (design_bench, popcutd_bench): the same card in the core and through
// popcutd.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "popcut/design/face_design.h"

namespace popcut::bench {

inline DesignItem street_wall(double t, double x0, double x1, double h) {
  return {DesignTool::wall, t, {{x0, 0}, {x1, 0}, {x1, h}, {x0, h}}, true, false};
}

// A street of walls at depths 5–24 mm, each with its top: about two faces a wall. Added back to
// front, as a designer would draw it (adding in any order gives the same card, only slower).
inline FaceDesign design_street(int faces) {
  const int walls = faces / 2;
  FaceDesign d(5.0 * walls + 10, 60, 60);
  std::mt19937_64 rng(3);
  std::vector<DesignItem> items;
  for (int i = 0; i < walls; ++i) {
    const double x0 = 5.0 + 5.0 * i;
    items.push_back(street_wall(5 + static_cast<double>(rng() % 20), x0, x0 + 4, 5 + static_cast<double>(rng() % 30)));
  }
  std::stable_sort(items.begin(), items.end(),
                   [](const DesignItem& a, const DesignItem& b) { return a.t_mm < b.t_mm; });
  for (const DesignItem& it : items) d.add(it);
  d.pattern();
  return d;
}

}  // namespace popcut::bench
