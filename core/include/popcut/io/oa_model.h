// webOAcard's .oa files (github.com/caa1211/webOAcard) read as face models: docs/formats.md, "webOAcard .oa".
#pragma once

#include <cstddef>
#include <string>

#include "popcut/model/face_model.h"
#include "popcut/model/oa_card.h"

namespace popcut {

// A .oa card's drawn faces and the points of all their rings together (each ring also at most
// kMaxOutlinePoints). webOAcard's cards have tens of faces and a few thousand points (a line of
// text); the derivation's exact Booleans grow faster than linearly with both, so hostile files
// are refused before it starts (docs/formats.md, "webOAcard .oa").
inline constexpr std::size_t kMaxOaFaces = 2000;
inline constexpr std::size_t kMaxOaPoints = 100000;

// True for a path ending in ".oa" (any case): load_model reads it with parse_oa_model.
bool is_oa_path(const std::string& path);

// True for a JSON object that is a .oa document by its shape (webOAcard's files carry no format
// tag): "settings" and "faces" and no "format". Where a popcut document could come instead (a
// draft posted to popcutd, a file opened in the designer), this tells them apart.
bool is_oa_document(const std::string& text);

// The card of a .oa document, every field checked; errors (popcut::Error) name `source` and the
// JSON path, e.g. "faces[3].contours[0].outer[2].X".
OaCard parse_oa_card(const std::string& text, const std::string& source);

// The face model webOAcard's editor shows for the document (face_model_from_oa).
FaceModel parse_oa_model(const std::string& text, const std::string& source);

}  // namespace popcut
