// Random valid voxel models for property tests and benchmarks (seeded, reproducible).
#pragma once

#include <cstdint>
#include <random>

#include "popcut/model/voxel_model.h"

namespace popcut::testing {

struct RandomModelSpec {
  int max_width = 8;
  int max_depth = 6;
  int max_height = 8;
  double window_probability = 0.0;  // chance that a row with a front face becomes a window
  bool random_sheet = false;        // random back/floor/side at or above the minimum
};

VoxelModel random_model(std::mt19937_64& rng, const RandomModelSpec& spec);

// A model of exactly this size: staircase columns drawn at random, no windows.
VoxelModel random_staircase(std::mt19937_64& rng, int width, int depth, int height, double voxel_mm);

}  // namespace popcut::testing
