// Mesh → voxel OA model without CGAL: view frame, grid, z-buffer depth sampling, morphology, eq. 7 filling.
#include "popcut/mesh/mesh_import.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "popcut/design/repair.h"
#include "popcut/design/thin_tops.h"
#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
namespace {

constexpr double kDefaultCardWidthMm = 120;
constexpr double kInf = std::numeric_limits<double>::infinity();

int axis_index(Axis a) { return static_cast<int>(a) / 2; }
double axis_sign(Axis a) { return static_cast<int>(a) % 2 == 0 ? 1.0 : -1.0; }

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Six significant digits: an option of 1e308 is named as such, not in 300 digits.
std::string fmt(double v) { return format_significant(v, 6); }

void check_options(const ImportOptions& o, const std::string& source) {
  const auto bad = [&](const char* option, const std::string& message) {
    throw Error(ErrorCode::invalid_input, source, option, message);
  };
  if (o.resolution < 1 || o.resolution > kMaxImportResolution) {
    bad("--resolution",
        "must be 1 to " + std::to_string(kMaxImportResolution) + " voxels across, not " + std::to_string(o.resolution));
  }
  if (!(o.keep_depth > 0 && o.keep_depth <= 1))
    bad("--keep-depth", "must be a fraction above 0 and at most 1, not " + fmt(o.keep_depth));
  if (o.structuring_element < 1 || o.structuring_element > kMaxStructuringElement || o.structuring_element % 2 == 0) {
    bad("--smooth", "the structuring element's side must be odd, 1 to " + std::to_string(kMaxStructuringElement) +
                        ", not " + std::to_string(o.structuring_element));
  }
  // Each of these sets the card's size on its own, so any two disagree.
  std::vector<const char*> sizes;
  if (o.width_mm) sizes.push_back("--width-mm");
  if (o.voxel_mm) sizes.push_back("--voxel-mm");
  if (o.height_mm) sizes.push_back("--height-mm");
  if (o.fit) sizes.push_back("--fit-mm");
  if (sizes.size() > 1) {
    bad(sizes[1],
        std::string(
            "give one of --width-mm, --voxel-mm, --height-mm and --fit-mm (each sets the card's size), not both ") +
            sizes[0] + " and " + sizes[1]);
  }
  if (o.thin_top_voxels < 0 || o.thin_top_voxels > kMaxVoxelAxis)
    bad("--thin-tops", "must be 0 (off) to " + std::to_string(kMaxVoxelAxis) + " voxels");
  if (o.width_mm && !(*o.width_mm > 0))
    bad("--width-mm", "the card width must be a positive number of mm, not " + fmt(*o.width_mm));
  if (o.voxel_mm && !(*o.voxel_mm > 0))
    bad("--voxel-mm", "the voxel size must be a positive number of mm, not " + fmt(*o.voxel_mm));
  if (o.height_mm && !(*o.height_mm > 0 && std::isfinite(*o.height_mm))) {
    bad("--height-mm", "the card's height must be a positive number of mm, not " + fmt(*o.height_mm));
  }
  if (o.fit && !(o.fit->width_mm > 0 && o.fit->height_mm > 0 && std::isfinite(o.fit->width_mm) &&
                 std::isfinite(o.fit->height_mm))) {
    bad("--fit-mm", "the box must be a positive number of mm each way, not " + fmt(o.fit->width_mm) + " x " +
                        fmt(o.fit->height_mm));
  }
  // A height or a box gives the voxel size only once the model's sheet is known (sized_voxel_mm).
  const double voxel = o.voxel_mm ? *o.voxel_mm : o.width_mm.value_or(kDefaultCardWidthMm) / o.resolution;
  if (!o.height_mm && !o.fit && !(voxel >= kMinVoxelMm && voxel <= kMaxVoxelMm)) {
    bad(o.voxel_mm ? "--voxel-mm" : "--width-mm",
        "gives voxels of " + fmt(voxel) + " mm; they must be " + fmt(kMinVoxelMm) + " to " + fmt(kMaxVoxelMm) + " mm");
  }
  if (axis_index(o.up) == axis_index(o.front)) {
    bad("--front", std::string("must be perpendicular to --up (both are along ") + "xyz"[axis_index(o.up)] + ")");
  }
}

// The voxel edge that gives the card --height-mm or fits it into --fit-mm, from the sheet the
// model needs in voxels (which no voxel size changes): rounded down to a whole nanometre, as
// plan_grid rounds, so the card never comes out over the size asked for (and is short of it by
// under a nanometre per voxel).
double sized_voxel_mm(const VoxelModel& m, const ImportOptions& o, const std::string& source) {
  const SheetVoxels s = resolve_sheet(m, source);
  const double across = m.width + 2.0 * s.side, closed = std::max(s.back, s.floor),
               flat = static_cast<double>(s.back) + s.floor;
  double voxel = 0;
  const char* option = "--height-mm";
  std::string asked;
  if (o.height_mm) {
    // Standing at 90°, the card is as tall as its back board.
    voxel = *o.height_mm / s.back;
    asked = "a card " + fmt(*o.height_mm) + " mm high";
  } else {
    option = "--fit-mm";
    voxel = std::min(o.fit->width_mm / across, o.fit->height_mm / (o.fit->flat ? flat : closed));
    asked = (o.fit->flat ? "the sheet inside " : "the closed card inside ") + o.fit->what;
  }
  voxel = std::floor(voxel * 1e6) / 1e6;
  if (!(voxel >= kMinVoxelMm && voxel <= kMaxVoxelMm)) {
    throw Error(ErrorCode::invalid_input, source, option,
                asked + " needs voxels of " + fmt(voxel) + " mm (the sheet is " + fmt(across) + " x " + fmt(flat) +
                    " voxels); they must be " + fmt(kMinVoxelMm) + " to " + fmt(kMaxVoxelMm) +
                    " mm: change the size or --resolution");
  }
  return voxel;
}

}  // namespace

std::optional<Axis> parse_axis(const std::string& text) {
  if (const auto axis = kAxisNames.find(text)) return axis;
  return kAxisNames.find("+" + text);  // "x" is "+x": only the positive names start with '+'
}

const char* to_string(Axis axis) { return kAxisNames.name(axis).data(); }

// Card axes from the mesh's: z = up, y = towards the viewer, x = up × front, which is the
// viewer's right (with +Z up and -Y to the viewer, +X stays +X).
TriangleSoup to_card_frame(const TriangleSoup& mesh, Axis up, Axis front, const std::string& source) {
  if (axis_index(up) == axis_index(front))
    throw Error(ErrorCode::invalid_input, source, "--front", "must be perpendicular to --up");
  double u[3] = {0, 0, 0}, f[3] = {0, 0, 0};
  u[axis_index(up)] = axis_sign(up);
  f[axis_index(front)] = axis_sign(front);
  const double r[3] = {u[1] * f[2] - u[2] * f[1], u[2] * f[0] - u[0] * f[2], u[0] * f[1] - u[1] * f[0]};
  TriangleSoup out = mesh;
  for (auto& p : out.points) {
    const double q[3] = {p[0], p[1], p[2]};
    p = {r[0] * q[0] + r[1] * q[1] + r[2] * q[2], f[0] * q[0] + f[1] * q[1] + f[2] * q[2],
         u[0] * q[0] + u[1] * q[1] + u[2] * q[2]};
  }
  return out;
}

ImportGrid plan_grid(const TriangleSoup& mesh, const ImportOptions& o, const std::string& source) {
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  for (const auto& t : mesh.triangles) {
    for (std::uint32_t i : t) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], mesh.points[i][static_cast<std::size_t>(k)]);
        hi[k] = std::max(hi[k], mesh.points[i][static_cast<std::size_t>(k)]);
      }
    }
  }
  if (mesh.triangles.empty()) throw Error(ErrorCode::invalid_input, source, "", "the mesh has no triangles");
  const double ext[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
  // Finite coordinates near ±1.8e308 can still span more than a double holds.
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(ext[k])) {
      throw Error(ErrorCode::limit, source, "",
                  std::string("the mesh's ") + "xyz"[k] +
                      " extent (card axes) overflows a double: its coordinates are too large (near 1e308)");
    }
  }
  if (!(ext[0] > 0))
    throw Error(ErrorCode::invalid_input, source, "", "the mesh has no width across the view: check --up and --front");
  if (!(ext[2] > 0)) throw Error(ErrorCode::invalid_input, source, "", "the mesh has no height: check --up");
  ImportGrid g;
  g.width = o.resolution;
  g.step = ext[0] / o.resolution;
  g.x0 = lo[0];
  g.z0 = lo[2];
  // Whole nanometres: face models snap every coordinate to 1 nm, and a fold needs t_h - t_v = v
  // exactly, which independent rounding of 120 / 42 mm multiples would break (--faces).
  g.voxel_mm =
      std::round((o.voxel_mm ? *o.voxel_mm : o.width_mm.value_or(kDefaultCardWidthMm) / o.resolution) * 1e6) / 1e6;
  const double slab = o.keep_depth * ext[1];
  g.back_wall_y = hi[1] - slab;
  // Sizes in voxels, computed in double first so a flat sliver of a mesh cannot overflow int.
  const double height = std::max(1.0, std::ceil(ext[2] / g.step - 1e-9));
  const double depth = std::ceil(slab / g.step - 1e-9);
  if (height > kMaxVoxelAxis || depth > kMaxVoxelAxis) {
    throw Error(ErrorCode::limit, source, "--resolution",
                "the model would be " + fmt(height) + " voxels high and " + fmt(depth) + " deep at " +
                    std::to_string(o.resolution) + " across; the limit is " + std::to_string(kMaxVoxelAxis) +
                    " per axis: lower --resolution or --keep-depth");
  }
  if (!(depth >= 1)) {
    throw Error(ErrorCode::invalid_input, source, "",
                "the mesh has no depth towards the viewer, so nothing stands out of the back wall: check --front");
  }
  g.height = static_cast<int>(height);
  g.depth = static_cast<int>(depth);
  return g;
}

// Each triangle is rasterised over the cell centres inside its projection onto the (x, z)
// plane, keeping the largest y (nearest the viewer). Work is the triangles plus the cells they
// cover, against cells × log(triangles) for ray casting.
DepthMap sample_depth_zbuffer(const TriangleSoup& mesh, const ImportGrid& grid) {
  DepthMap map;
  map.width = grid.width;
  map.height = grid.height;
  map.front.assign(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height), -kInf);
  for (const auto& t : mesh.triangles) {
    // Cell centres sit at integer (u, w).
    double u[3], w[3], y[3];
    for (int i = 0; i < 3; ++i) {
      const auto& p = mesh.points[t[static_cast<std::size_t>(i)]];
      u[i] = (p[0] - grid.x0) / grid.step - 0.5;
      w[i] = (p[2] - grid.z0) / grid.step - 0.5;
      y[i] = p[1];
    }
    const double area = (u[1] - u[0]) * (w[2] - w[0]) - (u[2] - u[0]) * (w[1] - w[0]);
    if (area == 0) continue;  // seen edge-on: covers no area from the front
    const int x_lo = std::max(0, static_cast<int>(std::ceil(std::min({u[0], u[1], u[2]}))));
    const int x_hi = std::min(grid.width - 1, static_cast<int>(std::floor(std::max({u[0], u[1], u[2]}))));
    const int z_lo = std::max(0, static_cast<int>(std::ceil(std::min({w[0], w[1], w[2]}))));
    const int z_hi = std::min(grid.height - 1, static_cast<int>(std::floor(std::max({w[0], w[1], w[2]}))));
    const double inv = 1.0 / area;
    // Points on an edge count for both triangles sharing it: a surface seen exactly along a
    // seam is still seen. The tolerance absorbs rounding of the barycentric coordinates.
    constexpr double kEdge = -1e-9;
    for (int x = x_lo; x <= x_hi; ++x) {
      for (int z = z_lo; z <= z_hi; ++z) {
        const double l0 = ((u[1] - x) * (w[2] - z) - (u[2] - x) * (w[1] - z)) * inv;
        const double l1 = ((u[2] - x) * (w[0] - z) - (u[0] - x) * (w[2] - z)) * inv;
        const double l2 = 1 - l0 - l1;
        if (l0 < kEdge || l1 < kEdge || l2 < kEdge) continue;
        double& d = map.front[static_cast<std::size_t>(x) * static_cast<std::size_t>(grid.height) +
                              static_cast<std::size_t>(z)];
        d = std::max(d, l0 * y[0] + l1 * y[1] + l2 * y[2]);
      }
    }
  }
  return map;
}

std::vector<int> depth_cells(const DepthMap& map, const ImportGrid& grid) {
  std::vector<int> cells(map.front.size(), 0);
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const double d = (map.front[i] - grid.back_wall_y) / grid.step;
    if (d > 0) cells[i] = static_cast<int>(std::min(static_cast<double>(grid.depth), std::round(d)));
  }
  return cells;
}

// A slice's filled set is {(y, z): y < p[z]}, and a square of radius r keeps that shape:
// eroded, y survives when y + r is filled in every row of the window (or runs off the grid,
// which counts as filled), so p' = min - r, or the full depth where the minimum is full;
// dilated, y is hit when y - r < p in some row, so p' = max + r where the maximum is not 0.
void open_close(std::vector<int>& cells, const ImportGrid& grid, int side) {
  const int r = side / 2;
  if (r == 0) return;
  const int h = grid.height, d = grid.depth;
  std::vector<int> tmp(static_cast<std::size_t>(h));
  const auto erode = [&](int* p) {
    for (int z = 0; z < h; ++z) {
      int m = d;
      for (int k = std::max(0, z - r); k <= std::min(h - 1, z + r); ++k) m = std::min(m, p[k]);
      tmp[static_cast<std::size_t>(z)] = m >= d ? d : std::max(0, m - r);
    }
    std::copy(tmp.begin(), tmp.end(), p);
  };
  const auto dilate = [&](int* p) {
    for (int z = 0; z < h; ++z) {
      int m = 0;
      for (int k = std::max(0, z - r); k <= std::min(h - 1, z + r); ++k) m = std::max(m, p[k]);
      tmp[static_cast<std::size_t>(z)] = m == 0 ? 0 : std::min(d, m + r);
    }
    std::copy(tmp.begin(), tmp.end(), p);
  };
  for (int x = 0; x < grid.width; ++x) {
    int* p = cells.data() + static_cast<std::size_t>(x) * static_cast<std::size_t>(h);
    erode(p);  // opening: bumps narrower than the square go
    dilate(p);
    dilate(p);  // closing: dents narrower than the square fill
    erode(p);
  }
}

ImportResult import_mesh(const TriangleSoup& mesh, const ImportOptions& o, const std::string& source) {
  check_options(o, source);
  ImportResult out;
  out.stats.triangles = static_cast<std::int64_t>(mesh.triangles.size());
  out.stats.degenerate = mesh.degenerate;
  auto t = Clock::now();
  const TriangleSoup card = to_card_frame(mesh, o.up, o.front, source);
  const ImportGrid g = plan_grid(card, o, source);
  const std::int64_t grid_cells = std::int64_t{g.width} * g.depth * g.height;
  if (o.max_cells > 0 && grid_cells > o.max_cells) {
    throw Error(ErrorCode::limit, source, "--resolution",
                "the model would be " + std::to_string(g.width) + " x " + std::to_string(g.depth) + " x " +
                    std::to_string(g.height) + " = " + std::to_string(grid_cells) + " voxel cells; at most " +
                    std::to_string(o.max_cells) + " are allowed here: lower --resolution or --keep-depth");
  }
  out.grid = g;
  const DepthMap map = o.depth == DepthMethod::zbuffer ? sample_depth_zbuffer(card, g) : sample_depth_raycast(card, g);
  std::vector<int> cells = depth_cells(map, g);
  out.timings.sample_ms = ms_since(t);

  t = Clock::now();
  open_close(cells, g, o.structuring_element);
  out.timings.morphology_ms = ms_since(t);

  // Eq. 7 from the top row down: a cell is filled when the one above it is. On a profile that
  // is a running maximum from the top; the rows it grows are the window candidates (§3.2 c).
  t = Clock::now();
  VoxelModel& m = out.model;
  m = VoxelModel::empty(g.width, g.depth, g.height, g.voxel_mm);
  m.name = o.name;
  std::vector<std::uint8_t> filled_rows(m.windows.size(), 0);
  bool any = false;
  for (int x = 0; x < g.width; ++x) {
    const int* p = cells.data() + static_cast<std::size_t>(x) * static_cast<std::size_t>(g.height);
    int running = 0;
    std::vector<int> filled(static_cast<std::size_t>(g.height));
    for (int z = g.height - 1; z >= 0; --z) {
      running = std::max(running, p[z]);
      filled[static_cast<std::size_t>(z)] = running;
      if (running > p[z]) {
        filled_rows[static_cast<std::size_t>(x) * static_cast<std::size_t>(g.height) + static_cast<std::size_t>(z)] = 1;
        out.stats.cells_filled += running - p[z];
      }
    }
    // h(y) = the number of rows whose filled depth passes y; the profile falls with z.
    int z = 0;
    for (int y = g.depth - 1; y >= 0; --y) {
      while (z < g.height && filled[static_cast<std::size_t>(z)] > y) ++z;
      m.h_at(x, y) = z;
      any = any || z > 0;
    }
  }
  if (!any) {
    throw Error(
        ErrorCode::invalid_input, source, "",
        "no voxel is left in front of the back wall (the surface seen from the front lies behind it, or every feature "
        "is "
        "narrower than the smoothing square): check --front, raise --keep-depth or --resolution, or lower --smooth");
  }
  try {
    resolve_sheet(m, source);  // the pattern's cell limit, named before any work on windows
  } catch (const Error& e) {
    throw Error(e.code(), source, "--resolution", e.message() + ": lower --resolution or --keep-depth");
  }
  // The size in mm is only a scale: windows and thin tops are then checked on the card as cut.
  if (o.height_mm || o.fit) m.voxel_mm = out.grid.voxel_mm = sized_voxel_mm(m, o, source);
  out.timings.fill_ms = ms_since(t);

  t = Clock::now();
  if (o.windows && out.stats.cells_filled > 0) {
    const WindowMarking w = mark_windows(m, filled_rows, source);
    out.stats.windows_added = w.added;
    out.stats.windows_rejected = w.rejected;
    out.stats.window_full_checks = w.full_checks;
    out.stats.window_work = w.work;
  }
  out.timings.windows_ms = ms_since(t);

  t = Clock::now();
  if (o.thin_top_voxels > 0) {
    const ThinTops tops = drop_thin_tops(m, o.thin_top_voxels, source);
    out.stats.tops_dropped = tops.dropped;
    out.stats.tops_kept = tops.kept;
  }
  out.timings.thin_ms = ms_since(t);
  return out;
}

}  // namespace popcut
