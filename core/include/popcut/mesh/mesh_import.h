// Polygon mesh → voxel OA model (voxel paper §3): read, depth-sample, smooth, fill (eq. 7), windows, thin tops.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "popcut/model/voxel_model.h"
#include "popcut/names.h"

namespace popcut {

// Documented limits of a mesh import.
inline constexpr std::size_t kMaxMeshFileBytes = std::size_t{256} << 20;  // 256 MiB
inline constexpr std::int64_t kMaxMeshTriangles = 10'000'000;
inline constexpr int kMaxImportResolution = 2048;  // voxels across; height and depth ≤ kMaxVoxelAxis
inline constexpr int kMaxStructuringElement = 15;

// Triangles with indices into `points`, as read (any polygon is split into a fan of triangles).
struct TriangleSoup {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::int64_t polygons = 0;    // polygons in the file
  std::int64_t degenerate = 0;  // triangles dropped for zero area (repeated or collinear corners)
};

// Reads OBJ, STL (ASCII or binary), OFF or PLY, chosen by the file's extension, with CGAL's
// readers; "-" is not accepted (the format comes from the name). Throws popcut::Error naming the
// file: unreadable or over kMaxMeshFileBytes (io / limit), unknown extension, a file the reader
// rejects (truncated, malformed), a vertex index out of range, a coordinate that is NaN or
// infinite (naming the vertex), no triangle of non-zero area, more than kMaxMeshTriangles.
// Non-manifold or inconsistently oriented meshes are fine: only the surface seen is used.
TriangleSoup read_mesh(const std::string& path);

// A signed coordinate axis of the mesh file.
enum class Axis { px, nx, py, ny, pz, nz };
inline constexpr auto kAxisNames = enum_names<Axis>(
    {{Axis::px, "+x"}, {Axis::nx, "-x"}, {Axis::py, "+y"}, {Axis::ny, "-y"}, {Axis::pz, "+z"}, {Axis::nz, "-z"}});
// "+x", "-x", "x" (= "+x"), … ; nothing for anything else.
std::optional<Axis> parse_axis(const std::string& text);
const char* to_string(Axis axis);

enum class DepthMethod {
  zbuffer,  // rasterise every triangle into the grid, keeping the nearest depth per cell
  raycast,  // one ray per cell against a CGAL AABB tree
};
inline constexpr auto kDepthMethodNames =
    enum_names<DepthMethod>({{DepthMethod::zbuffer, "zbuffer"}, {DepthMethod::raycast, "raycast"}});  // --depth-method

// --fit-mm: a box the card is scaled to fit. A W x H box holds the folded card's outline (the
// sheet's width by its taller half: the card as it closes); a device's media hold the whole flat
// sheet, which is what the device cuts.
struct CardFit {
  double width_mm = 0, height_mm = 0;
  bool flat = false;  // the flat sheet (a device's media), not the closed card
  std::string what;   // "210 x 297 mm" or "sim-a's media (600 x 1000 mm)", for messages
};

struct ImportOptions {
  Axis up = Axis::pz;               // the mesh axis that becomes the card's height z
  Axis front = Axis::ny;            // the mesh axis pointing at the viewer: the card's depth y
  int resolution = 80;              // voxels across the card (x), as the paper's 80
  std::optional<double> width_mm;   // card width of the model; or
  std::optional<double> voxel_mm;   // the voxel edge; or
  std::optional<double> height_mm;  // the standing card's height (its back board, = the closed card's); or
  std::optional<CardFit> fit;       // the largest card inside a box (one of the four; default width 120 mm)
  double keep_depth = 0.5;          // fraction of the model's depth kept, from the front (paper: half)
  int structuring_element = 3;      // side of the square for opening and closing; 1 turns it off
  bool windows = true;              // filled rows become windows where the card still pops up
  int thin_top_voxels = 0;          // drop top faces this narrow (in x) when the card stays valid; 0 = off
  DepthMethod depth = DepthMethod::zbuffer;
  std::string name;  // the model's label
  // A caller's budget of voxel cells (width x depth x height), checked on the planned grid before
  // any sampling: popcutd's [limits] model_cells. 0: only the per-axis kMaxVoxelAxis.
  std::int64_t max_cells = 0;
};

// The first surface seen from the front, per cell of the (x, z) grid: the card depth y of
// the surface in mesh units, or nothing.
struct DepthMap {
  int width = 0, height = 0;
  std::vector<double> front;  // width × height, index x * height + z; -infinity where no surface
  double at(int x, int z) const {
    return front[static_cast<std::size_t>(x) * static_cast<std::size_t>(height) + static_cast<std::size_t>(z)];
  }
};

// Where the grid lies in card coordinates (mesh units), decided from the mesh and the options.
struct ImportGrid {
  int width = 0, depth = 0, height = 0;  // voxels
  double x0 = 0, z0 = 0;                 // card x, z of the grid's corner
  double step = 1;                       // mesh units per voxel
  double back_wall_y = 0;                // card y of the back wall; the kept slab ends at the mesh front
  double voxel_mm = 1;
};

// The mesh in card coordinates: x across, y towards the viewer, z up (right-handed).
TriangleSoup to_card_frame(const TriangleSoup& mesh, Axis up, Axis front, const std::string& source);
ImportGrid plan_grid(const TriangleSoup& card_mesh, const ImportOptions& options, const std::string& source);

DepthMap sample_depth_zbuffer(const TriangleSoup& card_mesh, const ImportGrid& grid);
DepthMap sample_depth_raycast(const TriangleSoup& card_mesh, const ImportGrid& grid);

// Occupancy of one slice as a profile: cells y < depth_cells[z] are filled (solid from the back
// wall to the surface), which is how a depth map fills voxels.
using Profile = std::vector<int>;
// Column depths in voxels from the back wall, width × height (index x * height + z).
std::vector<int> depth_cells(const DepthMap& map, const ImportGrid& grid);

// Opening then closing of each yz slice with a side × side square (§3.2 a). On profiles these
// are running minima and maxima over z shifted in y; outside the grid counts as filled for the
// erosion and empty for the dilation, so the boards do not eat into the model.
void open_close(std::vector<int>& cells, const ImportGrid& grid, int side);

struct ImportStats {
  std::int64_t triangles = 0, degenerate = 0;
  std::int64_t cells_filled = 0;
  int windows_added = 0, windows_rejected = 0;
  std::int64_t window_full_checks = 0;
  std::int64_t window_work = 0;  // segments re-labelled plus regions and folds walked by the window decisions
  int tops_dropped = 0, tops_kept = 0;
};

struct ImportTimings {
  double read_ms = 0, sample_ms = 0, morphology_ms = 0, fill_ms = 0, windows_ms = 0, thin_ms = 0;
};

struct ImportResult {
  VoxelModel model;
  ImportGrid grid;
  ImportStats stats;
  ImportTimings timings;  // read_ms is left to the caller that read the file
};

// The whole pipeline on a mesh already read. The model always validates and pops up (the
// filled staircase without windows pops up; windows and dropped tops are kept only while it
// does). Throws popcut::Error (invalid_input, limit) naming `source` and the option at fault.
ImportResult import_mesh(const TriangleSoup& mesh, const ImportOptions& options, const std::string& source);

}  // namespace popcut
