// A webOAcard card (its edit history of walls, holes and pulls) and the face model its editor derives from it.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "popcut/geometry.h"
#include "popcut/model/face_model.h"

namespace popcut {

// What a drawn contour does (webOAcard's faceCreateMode): 0 a wall, 1 a hole cut through the
// walls at its depth and behind, 2 a pull (a wall part that rises past the roof its wall gets).
enum class OaMode { wall = 0, hole = 1, pull = 2 };

// One region of a drawn face in webOAcard's 2D frame: X across the card, Y = t - z (the pattern's
// -v). The outer ring and its holes, in either orientation.
struct OaContour {
  Ring outer;  // Point2{X, Y}
  std::vector<Ring> holes;
  std::vector<std::size_t> hole_index;  // each hole's index in the file's "holes", which may hold empty rings
};

struct OaFace {
  OaMode mode = OaMode::wall;
  double t_mm = 0;          // the depth y of the plane the face is drawn in, from 0 to the card's cardH
  bool expolygons = false;  // contoursType "expolygons" (text): only a region's top edges get a roof
  std::vector<OaContour> contours;
  std::string where;  // "faces[3]", for messages
};

// cardW × cardH: the back board is cardW wide and cardH high, the floor as deep, so the sheet is
// cardW × 2·cardH with the centre fold across its middle.
struct OaCard {
  double width_mm = 0;
  double half_height_mm = 0;
  std::vector<OaFace> faces;  // in the file's order
};

// The faces webOAcard's editor shows for the card (OA.Clipper.makeModel): walls clipped to the
// card and above the floor, merged by depth; holes cut through every wall and pull at their
// depth or behind; a top face from every top edge of a wall back to the wall behind; then each
// face drawn over those of smaller depth (walls) or height (top faces). Errors (popcut::Error)
// name `source` and the face (`faces[3].contours[0].outer`); the model's drawn_by() names the
// .oa faces each derived face comes from ("faces[3] (a wall at t = 24 mm)", "the top face of
// faces[3] (at z = 40 mm)", "the back board").
FaceModel face_model_from_oa(const OaCard& card, const std::string& source);

}  // namespace popcut
