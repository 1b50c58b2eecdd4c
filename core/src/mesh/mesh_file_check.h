// Bounds every list and face count of a PLY or OFF file by what the rest of the file can hold, and every corner by the
// vertex count, before CGAL reads it.
#pragma once

#include <string>

namespace popcut {

// Throws popcut::Error (invalid_input) naming the file and the record ("face 12", "line 9 (face
// 3)") when a binary or text PLY list, or an OFF face, claims more entries than the bytes or
// numbers left in the file, or is negative, and when a face's corner is not a vertex of the file
// (negative, not a whole number, or at least the vertex count: "corner 3 is vertex 9, but the
// file has 4 vertices: expected 0 to 3"); does nothing for other extensions or for headers it
// cannot follow (CGAL's reader then reports them).
void check_mesh_list_counts(const std::string& path, const std::string& ext, const std::string& bytes);

}  // namespace popcut
