// A webOAcard card brought into the designer: the faces its editor shows, each a wall or a roof item to edit on.
#pragma once

#include <string>

#include "popcut/design/face_design.h"
#include "popcut/model/oa_card.h"

namespace popcut {

// The design whose items draw exactly the faces webOAcard's editor shows for `card`
// (face_model_from_oa): each wall face a wall item at its depth and each top face a roof item at
// its height, with their holes, tops off (the card's top faces are items of their own). The
// card's holes and pulls are worked into those faces; the items are then edited like any other
// (docs/designer.md, "Importing a webOAcard card"). Errors (popcut::Error) name `source`: the
// card's own, or a face whose outline has more corners than a design item may (limit).
FaceDesign design_from_oa(const OaCard& card, const std::string& source);

}  // namespace popcut
