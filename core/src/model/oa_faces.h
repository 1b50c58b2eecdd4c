// The faces of a webOAcard card worked out exactly (oa_card.cpp), and their rounding to a FaceModel (oa_faces.cpp).
#pragma once

#include <string>
#include <vector>

#include "model/exact_faces.h"
#include "popcut/model/face_model.h"

namespace popcut::detail {

// A face of the derived card: its plane, its exact region, and what in the .oa file made it
// ("faces[3] (a wall at t = 24 mm)", "the top face of faces[3] (at z = 40 mm)", "the floor").
struct OaPiece {
  FaceKind kind;
  FT t_nm;
  ExactPolygonWithHoles polygon;
  std::string drawn_by;
};

// The pieces rounded to the 1 nm grid as a FaceModel whose drawn_by() names the .oa faces. A
// piece the rounding degenerates or makes overlap another (drawn edges that cross within 1 nm of
// a third) is invalid input naming the piece's .oa faces.
FaceModel oa_face_model(const std::vector<OaPiece>& pieces, double width_mm, double half_height_mm,
                        const std::string& source);

}  // namespace popcut::detail
