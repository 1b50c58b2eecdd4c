// Beyond the voxel paper: a face model whose front walls' tops follow the mesh silhouette instead of voxel steps.
#pragma once

#include <string>

#include "popcut/mesh/mesh_import.h"
#include "popcut/model/face_model.h"

namespace popcut {

// How the face model's outlines compare with the voxel card's, along the redrawn edges.
struct SilhouetteComparison {
  int outlines = 0;        // wall tops redrawn along the silhouette
  int steps_kept = 0;      // slice boundaries where a step had to stay (another face in the way)
  int voxel_lines = 0, face_lines = 0;  // lines of the two patterns
  int samples = 0;         // silhouette samples the distances below average over
  double voxel_mean_mm = 0, face_mean_mm = 0;  // mean distance from the silhouette
  double voxel_max_mm = 0, face_max_mm = 0;
};

struct SilhouetteFaces {
  FaceModel model;
  SilhouetteComparison comparison;
};

// Starts from the imported voxel card's pattern and redraws every edge where a front wall
// (VFace at depth t) meets a wall behind it — a cut, so not tied to x-parallel lines — as a
// polyline through the mesh silhouette at depth t, sampled 8× finer than the voxels at each
// slice boundary. A vertex moves only within the two faces' cells in both neighbouring slices,
// so the faces still tile the sheet, and folds are untouched, so the pop-up walks are the same;
// the result is checked anyway, and if it fails the voxel outlines are kept (outlines = 0).
SilhouetteFaces silhouette_faces(const TriangleSoup& mesh, const ImportOptions& options, const ImportResult& voxels,
                                 const std::string& source);

}  // namespace popcut
