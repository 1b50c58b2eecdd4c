// The folded card as OBJ (+ MTL) and glTF 2.0, the printed side and the back in two materials.
#pragma once

#include <iosfwd>
#include <string>

#include "popcut/fold/fold.h"

namespace popcut {

// Both formats use the usual right-handed Y-up frame: (X, Y, Z) = (x, z, y) of the card, so the
// viewer of the open card looks down −Z with x to the right. Each triangle is written twice:
// counter-clockwise with material "front" (printed side), and reversed with material "back".
// OBJ coordinates are millimetres; `mtl_file` is the name written in the mtllib line.
void write_obj(std::ostream& out, const CardMesh& mesh, const std::string& mtl_file);
void write_mtl(std::ostream& out);
// glTF coordinates are metres (the format's unit), with the buffer embedded as a data URI.
void write_gltf(std::ostream& out, const CardMesh& mesh);

}  // namespace popcut
