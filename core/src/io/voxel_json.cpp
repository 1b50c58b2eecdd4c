// Reader and writer for popcut.voxel.v1 with a precise error for every malformed field.
#include "popcut/io/voxel_json.h"

#include <algorithm>
#include <sstream>
#include <tuple>

#include "io/json_util.h"
#include "io/readers.h"
#include "popcut/error.h"
#include "popcut/io/files.h"

namespace popcut {
using json_util::index_path;
using json_util::json;

namespace {

struct GridSize {
  int width = 0, depth = 0, height = 0;
};

std::string grid_text(const GridSize& g) {
  return std::to_string(g.width) + " x " + std::to_string(g.depth) + " x " + std::to_string(g.height);
}

void read_sheet(const json_util::Reader& in, const json& j, SheetSpec& sheet) {
  in.require_object(j, "sheet");
  in.only_keys(j, {"back", "floor", "side"}, "sheet");
  if (j.contains("back")) sheet.back = in.integer(j["back"], "sheet.back", 1, kMaxSheetVoxels);
  if (j.contains("floor")) sheet.floor = in.integer(j["floor"], "sheet.floor", 1, kMaxSheetVoxels);
  if (j.contains("side")) sheet.side = in.integer(j["side"], "sheet.side", 0, kMaxVoxelAxis);
}

// Column tops from a heights array; grid size from its extent.
void read_heights(const json_util::Reader& in, const json& heights, std::vector<std::vector<int>>& tops,
                  GridSize& size) {
  in.require_array(heights, "heights");
  if (heights.size() > static_cast<std::size_t>(kMaxVoxelAxis)) {
    in.fail("heights",
            "has " + std::to_string(heights.size()) + " columns; the limit is " + std::to_string(kMaxVoxelAxis));
  }
  tops.resize(heights.size());
  for (std::size_t x = 0; x < heights.size(); ++x) {
    const std::string px = index_path("heights", x);
    in.require_array(heights[x], px);
    if (heights[x].size() > static_cast<std::size_t>(kMaxVoxelAxis)) {
      in.fail(px,
              "has " + std::to_string(heights[x].size()) + " entries; the limit is " + std::to_string(kMaxVoxelAxis));
    }
    for (std::size_t y = 0; y < heights[x].size(); ++y) {
      const int h = in.integer(heights[x][y], index_path(px, y), 0, kMaxVoxelAxis);
      tops[x].push_back(h);
      size.height = std::max(size.height, h);
    }
    size.depth = std::max(size.depth, static_cast<int>(heights[x].size()));
  }
  size.width = static_cast<int>(heights.size());
}

struct Cell {
  int x, y, z;
  std::size_t index;
};

// Column tops from a list of filled voxels, remembering the empty cells under each top.
void read_voxels(const json_util::Reader& in, const json& voxels, std::vector<Cell>& cells, GridSize& size) {
  in.require_array(voxels, "voxels");
  cells.reserve(voxels.size());
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    const std::string p = index_path("voxels", i);
    if (!voxels[i].is_array() || voxels[i].size() != 3) in.fail(p, "expected [x, y, z]");
    Cell c{in.integer(voxels[i][0], index_path(p, 0), 0, kMaxVoxelAxis - 1),
           in.integer(voxels[i][1], index_path(p, 1), 0, kMaxVoxelAxis - 1),
           in.integer(voxels[i][2], index_path(p, 2), 0, kMaxVoxelAxis - 1), i};
    size.width = std::max(size.width, c.x + 1);
    size.depth = std::max(size.depth, c.y + 1);
    size.height = std::max(size.height, c.z + 1);
    cells.push_back(c);
  }
  std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) {
    return std::tie(a.x, a.y, a.z, a.index) < std::tie(b.x, b.y, b.z, b.index);
  });
  for (std::size_t i = 1; i < cells.size(); ++i) {
    const Cell& a = cells[i - 1];
    const Cell& b = cells[i];
    if (a.x == b.x && a.y == b.y && a.z == b.z) {
      in.fail(index_path("voxels", b.index), "repeats " + index_path("voxels", a.index));
    }
  }
}

}  // namespace

VoxelFile parse_voxel_file(const std::string& text, const std::string& source) {
  return voxel_file_from_json(json_util::parse(text, source), source);
}

VoxelFile voxel_file_from_json(const json& root, const std::string& source) {
  const json_util::Reader in(source);
  in.require_document(root, kVoxelFormat,
                      {"format", "voxel_mm", "name", "grid", "heights", "voxels", "windows", "dropped_tops", "sheet"});
  VoxelFile file;
  VoxelModel& m = file.model;
  const double voxel_mm = in.number(in.require(root, "voxel_mm", ""), "voxel_mm", kMinVoxelMm, kMaxVoxelMm);
  const bool has_heights = root.contains("heights");
  const bool has_voxels = root.contains("voxels");
  if (has_heights == has_voxels) in.fail("heights", "give exactly one of \"heights\" or \"voxels\"");

  GridSize size;
  std::vector<std::vector<int>> tops;
  std::vector<Cell> cells;
  if (has_heights)
    read_heights(in, root["heights"], tops, size);
  else
    read_voxels(in, root["voxels"], cells, size);

  if (root.contains("grid")) {
    const json& g = root["grid"];
    in.require_object(g, "grid");
    in.only_keys(g, {"width", "depth", "height"}, "grid");
    const GridSize given{in.integer(in.require(g, "width", "grid"), "grid.width", 1, kMaxVoxelAxis),
                         in.integer(in.require(g, "depth", "grid"), "grid.depth", 0, kMaxVoxelAxis),
                         in.integer(in.require(g, "height", "grid"), "grid.height", 0, kMaxVoxelAxis)};
    if (given.width < size.width || given.depth < size.depth || given.height < size.height) {
      in.fail("grid", "is " + grid_text(given) + " but the model needs at least " + grid_text(size));
    }
    size = given;
  }
  if (size.width < 1) in.fail(has_heights ? "heights" : "voxels", "the model needs at least one column");

  m = VoxelModel::empty(size.width, size.depth, size.height, voxel_mm);
  file.gap_rows.assign(m.windows.size(), 0);
  for (std::size_t x = 0; x < tops.size(); ++x) {
    for (std::size_t y = 0; y < tops[x].size(); ++y) m.h_at(static_cast<int>(x), static_cast<int>(y)) = tops[x][y];
  }
  // A column's cells come sorted by z: every z missing below its top is a gap.
  for (std::size_t i = 0; i < cells.size();) {
    std::size_t j = i;
    int expected_z = 0;
    for (; j < cells.size() && cells[j].x == cells[i].x && cells[j].y == cells[i].y; ++j) {
      for (int z = expected_z; z < cells[j].z; ++z) {
        ++file.gap_cells;
        file.gap_rows[static_cast<std::size_t>(cells[i].x) * static_cast<std::size_t>(size.height) +
                      static_cast<std::size_t>(z)] = 1;
        if (!file.first_gap) file.first_gap = std::array<int, 3>{cells[i].x, cells[i].y, z};
      }
      expected_z = cells[j].z + 1;
    }
    m.h_at(cells[i].x, cells[i].y) = expected_z;
    i = j;
  }

  // Windows [x, z] (rows 0 to height - 1) and dropped tops [x, z] (heights 1 to height): the
  // same list of cells of the x-z plane, each given once.
  const auto read_cells = [&](const char* field, const char* what, int z_lo, int z_hi, auto is_set, auto set) {
    if (!root.contains(field)) return;
    const json& w = root[field];
    in.require_array(w, field);
    for (std::size_t i = 0; i < w.size(); ++i) {
      const std::string p = index_path(field, i);
      if (!w[i].is_array() || w[i].size() != 2) in.fail(p, "expected [x, z]");
      const int x = in.integer(w[i][0], index_path(p, 0), 0, kMaxVoxelAxis);
      const int z = in.integer(w[i][1], index_path(p, 1), z_lo, kMaxVoxelAxis);
      // Appended, not "[" + to_string(x): GCC 12 warns falsely (-Wrestrict) on that inlined form.
      std::string cell("[");
      cell.append(std::to_string(x)).append(", ").append(std::to_string(z)).append("]");
      if (x >= size.width || z > z_hi) {
        in.fail(p, cell + " is outside the grid (x from 0 to " + std::to_string(size.width - 1) + ", z from " +
                       std::to_string(z_lo) + " to " + std::to_string(z_hi) + ")");
      }
      if (is_set(x, z)) in.fail(p, std::string("repeats an earlier ") + what + " " + cell);
      set(x, z);
    }
  };
  read_cells(
      "windows", "window", 0, size.height - 1, [&](int x, int z) { return m.is_window(x, z); },
      [&](int x, int z) { m.set_window(x, z, true); });
  read_cells(
      "dropped_tops", "top", 1, size.height, [&](int x, int z) { return m.is_top_dropped(x, z); },
      [&](int x, int z) { m.set_top_dropped(x, z, true); });
  if (root.contains("sheet")) read_sheet(in, root["sheet"], m.sheet);
  if (root.contains("name")) m.name = in.string(root["name"], "name", 256);
  return file;
}

VoxelModel parse_voxel_model(const std::string& text, const std::string& source) {
  return voxel_model_from_json(json_util::parse(text, source), source);
}

VoxelModel voxel_model_from_json(const json& root, const std::string& source) {
  VoxelFile file = voxel_file_from_json(root, source);
  if (file.first_gap) {
    const auto& g = *file.first_gap;
    throw Error(ErrorCode::invalid_input, source, "voxels",
                "cell [" + std::to_string(g[0]) + ", " + std::to_string(g[1]) + ", " + std::to_string(g[2]) +
                    "] is empty under a filled voxel: columns must be filled from the floor up (eq. 4); "
                    "'popcut repair' fills them");
  }
  require_valid(file.model, source);
  resolve_sheet(file.model, source);  // a sheet too small for the model is an input error too
  return std::move(file.model);
}

VoxelModel load_voxel_model(const std::string& path) { return parse_voxel_model(read_text_file(path), path); }

std::string to_voxel_json(const VoxelModel& m) {
  std::ostringstream o;
  o << "{\n  \"format\": \"" << kVoxelFormat << "\",\n";
  if (!m.name.empty()) o << "  \"name\": " << json(m.name).dump() << ",\n";
  o << "  \"voxel_mm\": " << json_util::number_text(m.voxel_mm) << ",\n";
  o << "  \"grid\": {\"width\": " << m.width << ", \"depth\": " << m.depth << ", \"height\": " << m.height << "},\n";
  o << "  \"heights\": [";
  for (int x = 0; x < m.width; ++x) {
    // Trailing zero columns are implied; the grid keeps the depth.
    int n = m.depth;
    while (n > 0 && m.h(x, n - 1) == 0) --n;
    o << (x ? ",\n    [" : "\n    [");
    for (int y = 0; y < n; ++y) o << (y ? ", " : "") << m.h(x, y);
    o << "]";
  }
  o << "\n  ],\n  \"windows\": [";
  bool first = true;
  for (int x = 0; x < m.width; ++x) {
    for (int z = 0; z < m.height; ++z) {
      if (!m.is_window(x, z)) continue;
      o << (first ? "" : ", ") << "[" << x << ", " << z << "]";
      first = false;
    }
  }
  o << "]";
  bool any_top = false;
  for (int x = 0; x < m.width; ++x) {
    for (int z = 1; z <= m.height; ++z) {
      if (!m.is_top_dropped(x, z)) continue;
      o << (any_top ? ", " : ",\n  \"dropped_tops\": [") << "[" << x << ", " << z << "]";
      any_top = true;
    }
  }
  if (any_top) o << "]";
  if (m.sheet.back || m.sheet.floor || m.sheet.side) {
    o << ",\n  \"sheet\": {";
    const char* sep = "";
    if (m.sheet.back) {
      o << sep << "\"back\": " << *m.sheet.back;
      sep = ", ";
    }
    if (m.sheet.floor) {
      o << sep << "\"floor\": " << *m.sheet.floor;
      sep = ", ";
    }
    if (m.sheet.side) {
      o << sep << "\"side\": " << *m.sheet.side;
    }
    o << "}";
  }
  o << "\n}\n";
  return o.str();
}

}  // namespace popcut
