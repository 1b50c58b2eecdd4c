// The pattern's lines and folds worked out a second, independent way: CGAL's general arrangement of all face
// boundaries.
#pragma once

#include "popcut/model/face_model.h"
#include "popcut/pattern/pattern.h"

namespace popcut::testing {

// Lines (sorted as make_pattern sorts them) and folds of a face model, from a CGAL
// Arrangement_2 of every face boundary with exact arithmetic and a full intersection sweep:
// the construction the polygon paper describes, against which make_pattern's per-line
// splitting (Fig. 10) is checked. Only `lines` and `folds` are filled.
Pattern arrangement_lines(const FaceModel& model);

}  // namespace popcut::testing
