// popcut.design.v1: a face-mode design (its sheet and items) as a file, for drafts and for open/save.
#pragma once

#include <string>

#include "popcut/design/face_design.h"

namespace popcut {

inline constexpr const char* kDesignFormat = "popcut.design.v1";

// True when `text` is a JSON object tagged popcut.design.v1 (a model file's readers then read it
// as a design; popcutd takes the face model it makes, not the design).
bool is_design_document(const std::string& text);

// Reads a design and draws its items back to front in one pass (FaceDesign::add_all: the order of
// the file does not change the card, and undo starts from the design as read); every
// error names `source` and the field ("items[2].outline[1]", "items[3]" for an item the design
// refuses, with the reason).
FaceDesign parse_design(const std::string& text, const std::string& source);

// One item as the design file writes it ({"tool", "t", "outline", "top"?, "mirror"?}): an editor's
// edit. Errors name `source` and the field ("outline[2]"); whether the design takes it is add's business.
DesignItem parse_design_item(const std::string& text, const std::string& source);

// The design's sheet and items in drawing order (back to front: reading it back redraws nothing).
std::string to_design_json(const FaceDesign& design, const std::string& name = "");

}  // namespace popcut
