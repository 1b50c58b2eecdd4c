// popcut import's options as text (a command line's flags or a form's fields) and the whole import of a mesh file: one
// path for `popcut import`, `popcut submit MESH` and popcutd.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "popcut/mesh/mesh_import.h"
#include "popcut/mesh/silhouette_faces.h"
#include "popcut/pattern/pattern.h"

namespace popcut {

// The option names: popcut import's flags without "--". no-windows and faces are switches.
inline constexpr std::array<std::string_view, 13> kImportOptionNames = {
    "up",         "front",  "resolution", "width-mm",  "voxel-mm",     "height-mm", "fit-mm",
    "keep-depth", "smooth", "no-windows", "thin-tops", "depth-method", "faces"};

// A device's media as a sheet lies on it: the most a sheet may measure across (pattern x) and
// along (pattern v), after the room its knife needs past the sheet's edge.
struct NamedMedia {
  std::string name;  // the device (popcutd) or profile (popcut) name --fit-mm takes
  double width_mm = 0, height_mm = 0;
};

struct ImportRequest {
  ImportOptions options;
  bool faces = false;  // --faces: a face model whose outlines follow the mesh silhouette
};

// Reads (name, text) pairs with names from kImportOptionNames; a switch takes "true" or "false";
// fit-mm takes "WxH" (x, X or ×, in mm) or the name of one of `media` (its whole flat sheet).
// Throws popcut::Error(invalid_input) naming `source` and the option as "--NAME": an unknown or
// repeated name, an axis or method that is none, a number that is not one (whole numbers for
// resolution, smooth and thin-tops), a box that is neither. Ranges are left to import_mesh,
// which names them the same way.
ImportRequest parse_import_options(const std::vector<std::pair<std::string, std::string>>& values,
                                   const std::string& source, const std::vector<NamedMedia>& media = {});

// One warning per device whose media the sheet does not fit, naming both sizes.
std::vector<std::string> media_warnings(const Rect& sheet, const std::vector<NamedMedia>& media);

struct MeshImport {
  ImportResult voxels;                   // timings.read_ms included
  std::optional<SilhouetteFaces> faces;  // with request.faces
  Pattern pattern;                       // of the model in model_json
  std::string model_json;                // popcut.voxel.v1, or popcut.faces.v1 with request.faces
};

// read_mesh(path) (format by the extension), at most `max_triangles` triangles (limit error), then
// import_mesh and, with --faces, silhouette_faces. Errors name `source` (the user's name for the
// file, which may differ from a temporary `path`) and the option at fault.
MeshImport import_mesh_file(const std::string& path, const ImportRequest& request, const std::string& source,
                            std::int64_t max_triangles = kMaxMeshTriangles);

}  // namespace popcut
