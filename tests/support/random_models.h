// Random valid voxel and face models for property tests and benchmarks (seeded, reproducible).
#pragma once

#include <cstdint>
#include <random>

#include "popcut/model/face_model.h"
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

namespace popcut::testing {

struct RandomFaceSpec {
  int edits = 8;        // edits attempted; those the model rejects are skipped
  bool slanted = true;  // trapezoids and triangles as well as rectangles
};

// A face model drawn by random edits on a random sheet: faces and holes in both planes, often
// reusing a plane already drawn (coplanar neighbours, holes that land), coordinates on a 0.5 mm
// grid so decimal input and slanted intersections are both exercised.
FaceModel random_face_model(std::mt19937_64& rng, const RandomFaceSpec& spec);

}  // namespace popcut::testing
