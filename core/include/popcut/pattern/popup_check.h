// Pop-up check (voxel paper §2.6, polygon paper §3.6): which faces would not stand, which pieces fall out.
#pragma once

#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut {

// A VFace that one of the two walks does not reach: it is not both pulled up by the back board
// and pushed up by the floor, so it would not stand when the card opens.
struct FaceProblem {
  int face = -1;
  bool from_back = false;   // reached by the walk from the back board
  bool from_floor = false;  // reached by the walk from the floor
};

// A set of faces joined by folds but cut off from the back board: it would fall out.
struct LoosePiece {
  std::vector<int> faces;
  Rect bounds;
  double area_mm2 = 0;
};

struct PopupReport {
  // The back board is every VFace at depth 0 reaching the sheet's top edge; the floor every
  // HFace at height 0 reaching its bottom edge. A sheet without one of them cannot be a card.
  bool no_back_board = false;
  bool no_floor = false;
  // No fold path joins the floor to the back board: the sheet falls in two. Then the walks
  // mean nothing and only this, and any other loose pieces, are reported.
  bool sheet_split = false;
  std::vector<FaceProblem> not_standing;  // faces of loose pieces are reported with the piece only
  std::vector<LoosePiece> loose_pieces;   // besides the floor's piece when the sheet is split
  // Loose pieces made only of openings' paper (a round window's disc): cut out and dropped, as
  // the opening means. Not a fault.
  std::vector<LoosePiece> cut_out;
  // HFaces not reached by both walks: held from one side only, they hang or tilt instead of
  // holding their angle (a window ledge, a roof left without its front). A warning: the paper's
  // condition judges VFaces only, so these do not stop a card from popping up.
  std::vector<FaceProblem> flaps;
  bool pops_up() const {
    return !no_back_board && !no_floor && !sheet_split && not_standing.empty() && loose_pieces.empty();
  }
};

// Walk (a) starts at the back board and crosses folds downward in the pattern (V→H over a valley,
// H→V over a mountain); walk (b) starts at the floor and crosses them upward. Every VFace other
// than the back board must be reached by both.
PopupReport check_popup(const Pattern& pattern);

// Area of a face: outer ring minus holes.
double face_area_mm2(const PatternFace& face);

}  // namespace popcut
