// Reads the faces of an OBJ file strictly: each corner a whole vertex index that exists, else an error naming the line.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace popcut {

// The faces of the OBJ text `bytes` as 0-based vertex indices, one polygon per 'f' line in
// order. A corner is "v", "v/vt", "v/vt/vn" or "v//vn", separated by spaces or tabs; v counts
// from 1, or back from the last vertex defined before the line when negative (-1 is that
// vertex). Throws popcut::Error (invalid_input) naming "line N" for a corner that is not a
// whole number, is 0, overflows, or names a vertex the file does not have.
std::vector<std::vector<std::size_t>> read_obj_faces(const std::string& path, const std::string& bytes);

}  // namespace popcut
