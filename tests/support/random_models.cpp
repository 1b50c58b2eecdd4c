// Seeded random staircases with windows, sized for tests and benchmarks.
#include "random_models.h"

#include <algorithm>

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
      if (uniform(rng, 0, 3) == 0) h = uniform(rng, 0, h);
      else if (h > 0 && uniform(rng, 0, 1) == 0) --h;
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
