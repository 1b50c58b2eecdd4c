// Beyond the voxel paper: a face model whose front walls' tops follow the mesh silhouette instead of voxel steps.
#pragma once

#include <string>

#include "popcut/mesh/mesh_import.h"
#include "popcut/model/face_model.h"

namespace popcut {

// How the face model's outlines compare with the voxel card's, along the redrawn edges.
struct SilhouetteComparison {
  int outlines = 0;                            // outlines (wall tops, undersides) redrawn along the silhouette
  int steps_kept = 0;                          // slice boundaries where a step had to stay (another face in the way)
  int outlines_kept = 0;                       // outlines left in voxel steps because redrawing them would break a face
  bool fell_back = false;                      // the redrawn model failed its check and the voxel outlines were kept
  int voxel_lines = 0, face_lines = 0;         // lines of the two patterns
  int samples = 0;                             // silhouette samples the distances below average over
  double voxel_mean_mm = 0, face_mean_mm = 0;  // mean distance from the silhouette
  double voxel_max_mm = 0, face_max_mm = 0;
};

struct SilhouetteFaces {
  FaceModel model;
  SilhouetteComparison comparison;
};

// Starts from the imported voxel card's pattern and redraws every cut between two faces of a
// slice with a wall (VFace at depth t) on at least one side — a wall top against a wall behind
// or a dropped top, or a wall's underside against a window's paper or a wall behind (arch and
// window openings, balconies) — as a polyline through the mesh silhouette at depth t, sampled 8×
// finer than the voxels at each slice boundary. Folds are never moved. A vertex moves only
// within the two faces' cells in both neighbouring slices, so the faces still tile the sheet;
// an outline that breaks a face or is no closer to the silhouette keeps its steps (outlines_kept).
// The result is checked anyway; if it fails, the voxel outlines are kept (fell_back).
SilhouetteFaces silhouette_faces(const TriangleSoup& mesh, const ImportOptions& options, const ImportResult& voxels,
                                 const std::string& source);

}  // namespace popcut
