// Seeded random staircases with windows, and random face-model edits, for tests and benchmarks.
#include "random_models.h"

#include <algorithm>
#include <cmath>

#include "popcut/error.h"

namespace popcut::testing {

namespace {
int uniform(std::mt19937_64& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }
}  // namespace

VoxelModel random_staircase(std::mt19937_64& rng, int width, int depth, int height, double voxel_mm) {
  VoxelModel m = VoxelModel::empty(width, depth, height, voxel_mm);
  for (int x = 0; x < width; ++x) {
    int h = uniform(rng, 0, height);
    for (int y = 0; y < depth; ++y) {
      m.h_at(x, y) = h;
      // Mostly gentle steps, sometimes a drop, so faces come in many sizes.
      if (uniform(rng, 0, 3) == 0)
        h = uniform(rng, 0, h);
      else if (h > 0 && uniform(rng, 0, 1) == 0)
        --h;
    }
  }
  return m;
}

VoxelModel random_model(std::mt19937_64& rng, const RandomModelSpec& spec) {
  VoxelModel m = random_staircase(rng, uniform(rng, 1, spec.max_width), uniform(rng, 1, spec.max_depth),
                                  uniform(rng, 1, spec.max_height), 1.0 + uniform(rng, 0, 4) * 0.5);
  std::bernoulli_distribution window(spec.window_probability);
  for (int x = 0; x < m.width; ++x) {
    for (int z = 0; z < m.h(x, 0); ++z) m.set_window(x, z, window(rng));
  }
  if (spec.random_sheet) {
    const int need = std::max(1, min_sheet_half_voxels(m));
    m.sheet.back = need + uniform(rng, 0, 3);
    m.sheet.floor = need + uniform(rng, 0, 3);
    m.sheet.side = uniform(rng, 0, 3);
  }
  return m;
}

}  // namespace popcut::testing

namespace popcut::testing {

namespace {
double half_steps(std::mt19937_64& rng, double lo, double hi) {
  const int n = static_cast<int>(std::floor((hi - lo) * 2));
  return lo + 0.5 * std::uniform_int_distribution<int>(0, std::max(0, n))(rng);
}
}  // namespace

FaceModel random_face_model(std::mt19937_64& rng, const RandomFaceSpec& spec) {
  const double width = 5.0 * std::uniform_int_distribution<int>(6, 16)(rng);
  const double back = 5.0 * std::uniform_int_distribution<int>(4, 10)(rng);
  const double floor = 5.0 * std::uniform_int_distribution<int>(4, 10)(rng);
  FaceModel m(width, back, floor);
  std::vector<std::pair<bool, double>> planes = {{true, 0.0}, {false, 0.0}};  // (vertical, t) drawn so far
  for (int k = 0; k < spec.edits; ++k) {
    FaceEdit e;
    const int op = std::uniform_int_distribution<int>(0, 9)(rng);
    e.op = op < 4 ? EditOp::add_vface : op < 8 ? EditOp::add_hface : op == 8 ? EditOp::add_vhole : EditOp::add_hhole;
    const bool vertical = e.op == EditOp::add_vface || e.op == EditOp::add_vhole;
    const bool hole = e.op == EditOp::add_vhole || e.op == EditOp::add_hhole;
    std::vector<double> same_kind;
    for (const auto& [v, t] : planes) {
      if (v == vertical) same_kind.push_back(t);
    }
    const bool reuse = hole || std::uniform_int_distribution<int>(0, 3)(rng) == 0;
    e.t_mm = reuse ? same_kind[std::uniform_int_distribution<std::size_t>(0, same_kind.size() - 1)(rng)]
                   : half_steps(rng, 0, 25);
    // The second coordinate (z in y = t, y in z = t) keeps v = z - t or v = t - y on the sheet.
    const double lo2 = vertical ? std::max(0.0, e.t_mm - floor) : std::max(0.0, e.t_mm - back);
    const double hi2 = vertical ? e.t_mm + back : e.t_mm + floor;
    double x0 = half_steps(rng, 0, width - 2), x1 = half_steps(rng, x0 + 1, std::min(width, x0 + 30));
    double s0 = half_steps(rng, lo2, hi2 - 1), s1 = half_steps(rng, s0 + 1, std::min(hi2, s0 + 30));
    if (x1 <= x0 || s1 <= s0) continue;
    const int shape = spec.slanted ? std::uniform_int_distribution<int>(0, 9)(rng) : 0;
    if (shape < 5) {
      e.outline = {{x0, s0}, {x1, s0}, {x1, s1}, {x0, s1}};
    } else if (shape < 8) {
      const double inset = (x1 - x0) / 2;
      const double a = half_steps(rng, 0, inset - 0.5), b = half_steps(rng, 0, inset - 0.5);
      e.outline = {{x0, s0}, {x1, s0}, {x1 - b, s1}, {x0 + a, s1}};
    } else {
      e.outline = {{x0, s0}, {x1, s0}, {half_steps(rng, x0, x1), s1}};
    }
    try {
      m.apply(e);
      if (!hole) planes.emplace_back(vertical, e.t_mm);
    } catch (const Error&) {
      // A hole that does not lie in a face of its plane: skipped, as a user would be told.
    }
  }
  return m;
}

}  // namespace popcut::testing
