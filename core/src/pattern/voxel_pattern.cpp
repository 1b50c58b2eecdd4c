// Voxel model → pattern: each x-slice is a strip of unit cells in v (§2.5), windows relocate
// front-face cells to ledges (§2.3), and regions, lines and folds are read off the cell grid.
#include "popcut/pattern/voxel_pattern.h"

#include <algorithm>
#include <unordered_map>

#include "popcut/error.h"

namespace popcut {
namespace {

// Directions of a boundary edge walked with its cell on the left: +x (the cell's bottom side),
// +v (right side), -x (top side), -v (left side).
constexpr int kDx[4] = {1, 0, -1, 0};
constexpr int kDv[4] = {0, 1, 0, -1};

class RegionMap {
 public:
  explicit RegionMap(const CellGrid& g) : g_(g), label_(g.faces.size(), -1) {}

  int at(int c, int r) const {
    if (c < 0 || r < 0 || c >= g_.columns || r >= g_.rows) return -1;
    return label_[index(c, r)];
  }
  std::size_t index(int c, int r) const {
    return static_cast<std::size_t>(r) * static_cast<std::size_t>(g_.columns) + static_cast<std::size_t>(c);
  }

  // 4-connected components of cells showing the same face: one component is one face region,
  // because equal neighbouring cells always join in 3D (same plane, same 2D→3D map).
  int label_all(std::vector<std::pair<int, int>>& first_cell) {
    int next = 0;
    std::vector<std::pair<int, int>> stack;
    for (int r = 0; r < g_.rows; ++r) {
      for (int c = 0; c < g_.columns; ++c) {
        if (label_[index(c, r)] >= 0) continue;
        const std::uint32_t face = g_.at(c, r);
        label_[index(c, r)] = next;
        first_cell.emplace_back(c, r);
        stack.emplace_back(c, r);
        while (!stack.empty()) {
          auto [cc, rr] = stack.back();
          stack.pop_back();
          for (int d = 0; d < 4; ++d) {
            const int nc = cc + kDx[d];
            const int nr = rr + kDv[d];
            if (nc < 0 || nr < 0 || nc >= g_.columns || nr >= g_.rows) continue;
            const std::size_t ni = index(nc, nr);
            if (label_[ni] >= 0 || g_.at(nc, nr) != face) continue;
            label_[ni] = next;
            stack.emplace_back(nc, nr);
          }
        }
        ++next;
      }
    }
    return next;
  }

 private:
  const CellGrid& g_;
  std::vector<int> label_;
};

// Traces every region boundary into rings: outer rings counter-clockwise, holes clockwise.
// Where a region touches itself only at a corner the walk turns left, so diagonal cells stay
// apart (4-connected regions, 8-connected holes). A walk may still pass such a corner twice;
// it is split there, so every ring is simple and a hole may touch the outer ring at a vertex.
void trace_rings(const CellGrid& g, const RegionMap& regions, std::vector<PatternFace>& faces) {
  const double mm = g.voxel_mm;
  const auto vertex = [&](int c, int r) { return Point2{c * mm, (r - g.sheet.floor) * mm}; };
  std::vector<std::uint8_t> done(g.faces.size(), 0);
  std::vector<std::pair<Point2, int>> walk;
  for (int r0 = 0; r0 < g.rows; ++r0) {
    for (int c0 = 0; c0 < g.columns; ++c0) {
      const int reg = regions.at(c0, r0);
      for (int d0 = 0; d0 < 4; ++d0) {
        // The cell across side d is to the right of the walking direction.
        if (regions.at(c0 + kDv[d0], r0 - kDx[d0]) == reg) continue;
        if (done[regions.index(c0, r0)] & (1u << d0)) continue;
        walk.clear();
        int c = c0, r = r0, d = d0;
        do {
          done[regions.index(c, r)] = static_cast<std::uint8_t>(done[regions.index(c, r)] | (1u << d));
          // Start vertex of side d of cell (c, r).
          const int sc = c + (d == 1 || d == 2 ? 1 : 0);
          const int sr = r + (d == 2 || d == 3 ? 1 : 0);
          walk.emplace_back(vertex(sc, sr), d);
          const int ahead_c = c + kDx[d], ahead_r = r + kDv[d];
          const int right_c = ahead_c + kDv[d], right_r = ahead_r - kDx[d];
          if (regions.at(ahead_c, ahead_r) != reg) {
            d = (d + 1) % 4;
          } else if (regions.at(right_c, right_r) != reg) {
            c = ahead_c;
            r = ahead_r;
          } else {
            c = right_c;
            r = right_r;
            d = (d + 3) % 4;
          }
        } while (!(c == c0 && r == r0 && d == d0));
        Ring ring;
        for (std::size_t i = 0; i < walk.size(); ++i) {
          const int prev = walk[(i + walk.size() - 1) % walk.size()].second;
          if (walk[i].second != prev) ring.push_back(walk[i].first);
        }
        PatternFace& face = faces[static_cast<std::size_t>(reg)];
        for (Ring& loop : split_at_repeated_vertices(ring)) {
          if (signed_area_mm2(loop) > 0) {
            if (!face.outer.empty()) {
              throw Error(ErrorCode::internal, "", "pattern", "region " + std::to_string(reg) + " has two outer rings");
            }
            face.outer = std::move(loop);
          } else {
            face.holes.push_back(std::move(loop));
          }
        }
      }
    }
  }
}

// Appends maximal runs of equal, non-empty kinds along one grid line as segments.
template <typename KindAt, typename PointAt>
void emit_runs(int count, KindAt kind_at, PointAt point_at, std::vector<Segment>& out) {
  int start = 0;
  int run = 0;  // 0: no line; else 1 + LineKind
  for (int i = 0; i <= count; ++i) {
    const int k = i < count ? kind_at(i) : 0;
    if (k == run) continue;
    if (run != 0) out.push_back({static_cast<LineKind>(run - 1), point_at(start), point_at(i)});
    run = k;
    start = i;
  }
}

}  // namespace

void slice_faces(const VoxelModel& m, const SheetVoxels& sheet, int x, std::vector<std::uint32_t>& strip) {
  const std::uint32_t back_wall = CellGrid::pack(FaceKind::vertical, 0);
  const std::uint32_t floor = CellGrid::pack(FaceKind::horizontal, 0);
  const int floor_rows = sheet.floor;
  strip.resize(static_cast<std::size_t>(sheet.back + sheet.floor));
  const auto set = [&](int v, std::uint32_t face) { strip[static_cast<std::size_t>(v + floor_rows)] = face; };
  for (int v = -floor_rows; v < sheet.back; ++v) set(v, v >= 0 ? back_wall : floor);
  if (x < 0 || x >= m.width) return;
  // below(z): the highest row under z that is not a window (-1: the floor), for §2.3; kept as
  // a running value because rows are visited bottom-up within each front face.
  std::vector<int> below(static_cast<std::size_t>(std::max(m.height, 1)));
  int last = -1;
  for (int z = 0; z < m.height; ++z) {
    below[static_cast<std::size_t>(z)] = last;
    if (!m.is_window(x, z)) last = z;
  }
  // Walk the slice's surface from the back wall down to the floor: v falls by one per cell.
  int step_start = 0;  // the first column of the current step (columns of one height)
  for (int y = 0;; ++y) {
    const int hy = m.h(x, y);
    if (y > 0 && hy != m.h(x, y - 1)) step_start = y;
    const int top_v = hy - y - 1;
    if (top_v < -floor_rows) break;
    std::uint32_t top = CellGrid::pack(FaceKind::horizontal, hy);
    if (m.is_top_dropped(x, hy)) {
      // §3.3: a dropped top's cells lie on the wall behind the step (y = step_start), whose
      // paper is next to them in the strip; where that runs below z = 0 they lie on the floor.
      top = top_v + step_start >= 0 ? CellGrid::pack(FaceKind::vertical, step_start) : floor;
    }
    set(top_v, top);
    for (int z = m.h(x, y + 1); z < hy; ++z) {
      std::uint32_t face = CellGrid::pack(FaceKind::vertical, y + 1);
      if (m.is_window(x, z)) {
        // The front cell of voxel (x, y, z) becomes the top face of voxel (x, y', h') with
        // h' the highest non-window row below z; past the back wall it lies on the wall.
        const int hp = below[static_cast<std::size_t>(z)];
        const int yp = y - (z - hp) + 1;
        face = yp >= 0 ? CellGrid::pack(FaceKind::horizontal, hp + 1) : back_wall;
      }
      set(z - y - 1, face);
    }
  }
}

CellGrid make_cell_grid(const VoxelModel& m, const std::string& source) {
  require_valid(m, source);
  CellGrid g;
  g.sheet = resolve_sheet(m, source);
  g.voxel_mm = m.voxel_mm;
  g.columns = m.width + 2 * g.sheet.side;
  g.rows = g.sheet.back + g.sheet.floor;
  g.faces.assign(static_cast<std::size_t>(g.columns) * static_cast<std::size_t>(g.rows), 0);
  std::vector<std::uint32_t> strip;
  for (int c = 0; c < g.columns; ++c) {
    slice_faces(m, g.sheet, c - g.sheet.side, strip);
    for (int r = 0; r < g.rows; ++r) {
      g.faces[static_cast<std::size_t>(r) * static_cast<std::size_t>(g.columns) + static_cast<std::size_t>(c)] =
          strip[static_cast<std::size_t>(r)];
    }
  }
  return g;
}

std::vector<int> cell_regions(const CellGrid& g) {
  RegionMap regions(g);
  std::vector<std::pair<int, int>> first_cell;
  regions.label_all(first_cell);
  std::vector<int> out(g.faces.size());
  for (int r = 0; r < g.rows; ++r) {
    for (int c = 0; c < g.columns; ++c) out[regions.index(c, r)] = regions.at(c, r);
  }
  return out;
}

Pattern make_pattern(const CellGrid& g) {
  Pattern p;
  const double mm = g.voxel_mm;
  p.sheet = {{0, -g.sheet.floor * mm}, {g.columns * mm, g.sheet.back * mm}};

  RegionMap regions(g);
  std::vector<std::pair<int, int>> first_cell;
  const int count = regions.label_all(first_cell);
  p.faces.resize(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    auto [c, r] = first_cell[static_cast<std::size_t>(i)];
    PatternFace& f = p.faces[static_cast<std::size_t>(i)];
    const std::uint32_t face = g.at(c, r);
    f.kind = CellGrid::kind_of(face);
    f.t_mm = CellGrid::t_of(face) * mm;
    f.label = {(c + 0.5) * mm, (r - g.sheet.floor + 0.5) * mm};
  }
  trace_rings(g, regions, p.faces);
  p.back_face = regions.at(0, g.rows - 1);
  p.floor_face = regions.at(0, 0);

  // x-parallel edges: typed by where the faces above and below meet in 3D (docs/architecture.md, "Geometry").
  std::unordered_map<std::uint64_t, std::size_t> link_index;
  for (int r = 1; r < g.rows; ++r) {
    const int v = r - g.sheet.floor;
    const auto kind_at = [&](int c) {
      const std::uint32_t up = g.at(c, r);
      const std::uint32_t lo = g.at(c, r - 1);
      if (up == lo) return 0;
      // Face offsets are whole voxels, so the comparison in voxel units is exact.
      LineKind kind = LineKind::cut;
      classify_x_edge(CellGrid::kind_of(up), CellGrid::t_of(up), CellGrid::kind_of(lo), CellGrid::t_of(lo), v, 0.0,
                      kind);
      if (kind != LineKind::cut) {
        const int a = regions.at(c, r), b = regions.at(c, r - 1);
        const std::uint64_t key = (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
        auto [it, fresh] = link_index.emplace(key, p.folds.size());
        if (fresh) p.folds.push_back({a, b, kind, 0});
        p.folds[it->second].length_mm += mm;
      }
      return 1 + static_cast<int>(kind);
    };
    emit_runs(
        g.columns, kind_at,
        [&](int c) {
          return Point2{c * mm, v * mm};
        },
        p.lines);
  }
  // Edges across x are never folds: a cut wherever the two cells show different faces.
  for (int c = 1; c < g.columns; ++c) {
    const auto kind_at = [&](int r) { return g.at(c - 1, r) != g.at(c, r) ? 1 : 0; };
    emit_runs(
        g.rows, kind_at,
        [&](int r) {
          return Point2{c * mm, (r - g.sheet.floor) * mm};
        },
        p.lines);
  }
  std::sort(p.folds.begin(), p.folds.end(), [](const FoldLink& a, const FoldLink& b) {
    return a.upper != b.upper ? a.upper < b.upper : a.lower < b.lower;
  });
  return p;
}

}  // namespace popcut
