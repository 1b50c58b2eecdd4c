// The standing OA card a flat sheet map folds into (polygon paper §2): each region's plane, from its folds.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "popcut/error.h"
#include "popcut/model/face_model.h"
#include "popcut/pattern/sheet_map.h"

namespace popcut {

// Why no card (or not this card) comes from the sheet: what, where on the drawn sheet, which
// regions (indices into SheetMap::regions) and which drawn line.
struct CardConflict {
  std::string what;
  Point2 at;
  std::vector<int> regions;
  std::string drawn;  // the drawn element, when one line is at fault
};

struct InferredCard {
  std::optional<FaceModel> model;  // set when there are no conflicts
  double centre_fold_v_mm = 0;     // where the centre fold lies, up from the sheet's bottom edge
  std::vector<CardConflict> conflicts;
};

// Regions touching the sheet's top edge are the back board (VFace t = 0), those touching its
// bottom edge the floor (HFace t = 0); every fold must run along x and joins a VFace and an HFace
// meeting in 3D, t_h − t_v = v (v measured from the centre fold), which fixes the planes region
// by region and the centre fold's place. Conflicts name: folds not parallel to the centre fold,
// folds and cuts inside one region (slits), pieces cut free or held by nothing, folds whose
// planes disagree around a cycle, and drawn lines the resulting card does not have (or lacks).
InferredCard infer_card(const LineDrawing& drawing, const SheetMap& map);

// No OA card folds from the drawing: the conflicts, one per line, in the message.
class CardConflictError : public Error {
 public:
  CardConflictError(const std::string& source, const InferredCard& card);
  const std::vector<CardConflict>& conflicts() const { return conflicts_; }

 private:
  std::vector<CardConflict> conflicts_;
};

struct CardImport {
  LineDrawing drawing;
  SheetMap map;
  InferredCard card;
};

// Reads the drawing (by extension), builds its map and infers the card; conflicts are returned
// in `card`, bad input throws popcut::Error.
CardImport import_card(const std::string& path, const DrawingOptions& drawing = {}, const SheetMapOptions& map = {});

// One line per conflict for people: "at (x, v) mm, <element>: what" (at most `max` of them).
std::string describe_conflicts(const InferredCard& card, std::size_t max = 20);

}  // namespace popcut
