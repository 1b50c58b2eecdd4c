// Dropping thin top faces (voxel paper §3.3, Fig. 13–14): fewer, wider faces to cut and fold.
#pragma once

#include <string>

#include "popcut/model/voxel_model.h"

namespace popcut {

struct ThinTops {
  int dropped = 0;  // thin top faces left out (each a whole face, across all its slices)
  int kept = 0;     // thin top faces that had to stay, or the card would not pop up (the supports)
};

// A top face is the HFace on a step of a slice (the columns of one height z); across slices it
// is one face while neighbouring slices have a step at the same z over overlapping depths. A
// face at most `max_width_voxels` slices wide is left out (VoxelModel::dropped_tops) as a whole
// — all its slices or none — when the card still pops up; faces are tried lowest first, so the
// tallest of a run of thin tops stays to hold the rest, as in the paper's Fig. 14 (a). A card
// that does not pop up to begin with is left as it is.
ThinTops drop_thin_tops(VoxelModel& model, int max_width_voxels, const std::string& source = "");

}  // namespace popcut
