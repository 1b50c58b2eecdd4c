// Several copies of one card on one sheet: how many fit the media, and one plan that cuts them all.
#pragma once

#include "popcut/plan/plan.h"

namespace popcut {

// Cards in a grid of columns × rows, gap_mm apart, unrotated (a card's folds keep their
// direction on the cutter as a single card's do).
struct NestLayout {
  int columns = 0, rows = 0;
  double gap_mm = 0;
  int count() const { return columns * rows; }
};

// The most whole cards of `card` (the card plan's extent: its sheet and any blade-offset corners)
// that fit media_x_mm × media_y_mm; 0 × 0 when not even one does. gap_mm must be >= 0.
NestLayout nest_layout(const Rect& card, double media_x_mm, double media_y_mm, double gap_mm);

// `copies` cards of `card` (1 .. layout.count(), else std::invalid_argument), laid row by row
// from the card's own place. Strokes go kind by kind as the card's plan has them, each kind on
// every card (in a serpentine over the grid) before the next, and the outlines of all cards last
// whatever the card's order: a card cut free early would shift under the knife while its
// neighbours are cut. Statistics add up over the cards; travel is measured anew.
StrokePlan nest_plan(const StrokePlan& card, const NestLayout& layout, int copies);

}  // namespace popcut
