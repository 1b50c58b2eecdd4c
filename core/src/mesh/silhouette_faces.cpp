// Redraws the voxel pattern's wall-on-wall edges along the mesh silhouette, keeping the faces a partition.
#include "popcut/mesh/silhouette_faces.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "popcut/error.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
namespace {

// The silhouette finely sampled: depth in voxels from the back wall per fine cell.
struct FineDepth {
  int scale = 1, width = 0, height = 0;
  std::vector<double> voxels;
  double at(int i, int k) const {
    return voxels[static_cast<std::size_t>(i) * static_cast<std::size_t>(height) + static_cast<std::size_t>(k)];
  }

  // Top (in voxels) of the run of fine cells in column i reaching depth t, searched from z_ref
  // (voxels) within two voxels either way; nothing when the mesh is not there.
  std::optional<double> top(int i, double t, double z_ref) const {
    if (i < 0 || i >= width) return std::nullopt;
    const double threshold = t - 0.5;  // the voxel model rounds depths the same way
    int k = std::clamp(static_cast<int>(std::lround(z_ref * scale)) - 1, 0, height - 1);
    const int reach = 2 * scale;
    if (at(i, k) >= threshold) {
      const int limit = std::min(height - 1, k + reach);
      while (k < limit && at(i, k + 1) >= threshold) ++k;
      return static_cast<double>(k + 1) / scale;
    }
    const int limit = std::max(0, k - reach);
    while (k > limit && at(i, k) < threshold) --k;
    if (at(i, k) < threshold) return std::nullopt;
    return static_cast<double>(k + 1) / scale;
  }

  // Bottom (in voxels) of the run of fine cells in column i reaching depth t, searched from
  // z_ref the same way: the underside of an arch or a balcony at that depth.
  std::optional<double> bottom(int i, double t, double z_ref) const {
    if (i < 0 || i >= width) return std::nullopt;
    const double threshold = t - 0.5;
    int k = std::clamp(static_cast<int>(std::lround(z_ref * scale)), 0, height - 1);
    const int reach = 2 * scale;
    if (at(i, k) >= threshold) {
      const int limit = std::max(0, k - reach);
      while (k > limit && at(i, k - 1) >= threshold) --k;
      return static_cast<double>(k) / scale;
    }
    const int limit = std::min(height - 1, k + reach);
    while (k < limit && at(i, k) < threshold) ++k;
    if (at(i, k) < threshold) return std::nullopt;
    return static_cast<double>(k) / scale;
  }

  // The silhouette edge at depth t near z_ref: the top of the region when the wall lies below
  // the edge, its bottom when the wall lies above it.
  std::optional<double> edge(int i, double t, double z_ref, bool wall_below) const {
    return wall_below ? top(i, t, z_ref) : bottom(i, t, z_ref);
  }
};

FineDepth fine_depth(const TriangleSoup& mesh, const ImportOptions& o, const ImportGrid& coarse,
                     const std::string& source) {
  FineDepth f;
  // 8× finer, or less when that would pass 16 million samples.
  const double cells = static_cast<double>(coarse.width) * coarse.height;
  f.scale = std::clamp(static_cast<int>(std::sqrt(16e6 / cells)), 1, 8);
  ImportGrid g = coarse;
  g.width *= f.scale;
  g.height *= f.scale;
  g.step /= f.scale;
  const DepthMap map = sample_depth_zbuffer(to_card_frame(mesh, o.up, o.front, source), g);
  f.width = g.width;
  f.height = g.height;
  f.voxels.resize(map.front.size());
  for (std::size_t i = 0; i < map.front.size(); ++i) f.voxels[i] = (map.front[i] - coarse.back_wall_y) / coarse.step;
  return f;
}

// One cut between two faces of the pattern, `a` below and `b` above it, running across
// consecutive slices: rows[k] is the boundary row in grid column first + k. The outline it
// follows is the nearer wall's (the VFace with the larger depth, or the only VFace): a wall top
// (the wall below, a wall behind or a dropped top above) or a wall's underside (the wall above,
// a window's paper or a wall behind below: an arch or window opening, a balcony).
struct Chain {
  int a = -1, b = -1;
  bool wall_below = true;
  int first = 0;
  std::vector<int> rows;
  std::vector<int> low, high;  // per column: A's cells reach down to `low`, B's up to `high` (rows)
};

std::size_t find_or_insert(Ring& ring, Point2 p) {
  for (std::size_t i = 0; i < ring.size(); ++i) {
    if (ring[i] == p) return i;
  }
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point2 a = ring[i], b = ring[(i + 1) % ring.size()];
    const bool on_v =
        a.x_mm == b.x_mm && p.x_mm == a.x_mm && p.v_mm > std::min(a.v_mm, b.v_mm) && p.v_mm < std::max(a.v_mm, b.v_mm);
    const bool on_h =
        a.v_mm == b.v_mm && p.v_mm == a.v_mm && p.x_mm > std::min(a.x_mm, b.x_mm) && p.x_mm < std::max(a.x_mm, b.x_mm);
    if (on_v || on_h) {
      ring.insert(ring.begin() + static_cast<std::ptrdiff_t>(i + 1), p);
      return i + 1;
    }
  }
  return ring.size();
}

// Replaces the ring's path from `from` to `to` when it is exactly `expected` (corners between
// them), by `interior`; false (ring unchanged) otherwise.
bool replace_path(std::vector<Ring*> rings, Point2 from, Point2 to, const std::vector<Point2>& expected,
                  const std::vector<Point2>& interior) {
  for (Ring* ring_ptr : rings) {
    Ring ring = *ring_ptr;
    const std::size_t i = find_or_insert(ring, from);
    if (i == ring.size()) continue;
    const std::size_t j = find_or_insert(ring, to);
    if (j == ring.size()) continue;
    const std::size_t i2 = static_cast<std::size_t>(std::find(ring.begin(), ring.end(), from) - ring.begin());
    std::vector<Point2> path;
    for (std::size_t k = (i2 + 1) % ring.size(); k != j; k = (k + 1) % ring.size()) path.push_back(ring[k]);
    if (path != expected) continue;
    Ring out;
    for (std::size_t k = j; k != i2; k = (k + 1) % ring.size()) out.push_back(ring[k]);
    out.push_back(ring[i2]);
    out.insert(out.end(), interior.begin(), interior.end());
    *ring_ptr = out;
    return true;
  }
  return false;
}

// At least three distinct points: a ring the face model accepts.
bool ring_ok(const Ring& ring) {
  std::vector<Point2> distinct(ring.begin(), ring.end());
  std::sort(distinct.begin(), distinct.end(), lexicographic_less);
  return std::unique(distinct.begin(), distinct.end()) - distinct.begin() >= 3;
}

// The voxel pattern's faces on the cell grid, and what the open card makes of each boundary row.
struct FaceGrid {
  const CellGrid& g;
  const std::vector<PatternFace>& faces;
  std::vector<int> region;
  int side = 0, floor = 0;
  double mm = 0;

  int reg(int c, int row) const {
    return region[static_cast<std::size_t>(row) * static_cast<std::size_t>(g.columns) + static_cast<std::size_t>(c)];
  }
  int t_of(int f) const { return static_cast<int>(std::lround(faces[static_cast<std::size_t>(f)].t_mm / mm)); }
  bool is_v(int f) const { return faces[static_cast<std::size_t>(f)].kind == FaceKind::vertical; }

  // Where the top edge of a cell of face a (below) and the bottom edge of a cell of face b
  // (above) lie on the open card, at the boundary row `row`: a VFace at depth t holds row v at
  // z = v + t, an HFace at height z holds it at y = z - v. They meet (a fold) when both are at
  // one place; otherwise the boundary is a cut and may follow the silhouette.
  bool is_fold(int a, int b, int row) const {
    const int v = row - floor;
    const auto place = [&](int f) {
      return is_v(f) ? std::make_pair(t_of(f), v + t_of(f)) : std::make_pair(t_of(f) - v, t_of(f));
    };
    return place(a) == place(b);
  }
  bool wall_is_below(int a, int b) const { return is_v(a) && (!is_v(b) || t_of(a) > t_of(b)); }
  Point2 pt(double c, double row) const { return Point2{c * mm, (row - floor) * mm}; }
};

// Cuts with a wall on one side, per model column, then joined into chains across columns.
std::vector<Chain> find_chains(const FaceGrid& fg, int model_width) {
  std::vector<Chain> chains;
  std::map<std::pair<int, int>, std::size_t> open;  // (A, B) → chain ending at the previous column
  for (int c = fg.side; c < fg.side + model_width; ++c) {
    std::map<std::pair<int, int>, int> here;  // (A, B) → row, or -1 when it occurs twice
    for (int row = 1; row < fg.g.rows; ++row) {
      const int a = fg.reg(c, row - 1), b = fg.reg(c, row);
      if (a == b || (!fg.is_v(a) && !fg.is_v(b)) || fg.is_fold(a, b, row)) continue;
      auto [it, fresh] = here.emplace(std::make_pair(a, b), row);
      if (!fresh) it->second = -1;
    }
    std::map<std::pair<int, int>, std::size_t> next;
    for (const auto& [key, row] : here) {
      if (row < 0) continue;
      int low = row - 1, high = row;
      while (low > 0 && fg.reg(c, low - 1) == key.first) --low;
      while (high + 1 < fg.g.rows && fg.reg(c, high + 1) == key.second) ++high;
      auto prev = open.find(key);
      bool joined = false;
      if (prev != open.end()) {
        Chain& ch = chains[prev->second];
        const int r1 = ch.rows.back(), lo = std::min(r1, row), hi = std::max(r1, row);
        // The step between the two columns must separate A from B along its whole height.
        joined = true;
        for (int k = lo; k < hi && joined; ++k) {
          joined = row > r1 ? (fg.reg(c - 1, k) == key.second && fg.reg(c, k) == key.first)
                            : (fg.reg(c - 1, k) == key.first && fg.reg(c, k) == key.second);
        }
        if (joined) {
          ch.rows.push_back(row);
          ch.low.push_back(low);
          ch.high.push_back(high + 1);
          next[key] = prev->second;
        }
      }
      if (!joined) {
        chains.push_back(
            Chain{key.first, key.second, fg.wall_is_below(key.first, key.second), c, {row}, {low}, {high + 1}});
        next[key] = chains.size() - 1;
      }
    }
    open = std::move(next);
  }
  return chains;
}

// A chain's outline along the silhouette: `interior` replaces the steps `expected` between its
// ends; vertex_rows holds the outline's row at each slice boundary (v = row - floor).
struct Outline {
  std::vector<Point2> interior, expected;
  std::vector<double> vertex_rows;
  int found = 0;  // slice boundaries where the silhouette was found
};

Outline outline_of(const Chain& ch, double t, const FaceGrid& fg, const FineDepth& fine, SilhouetteComparison& cmp) {
  const int n = static_cast<int>(ch.rows.size());
  Outline out;
  out.vertex_rows.resize(static_cast<std::size_t>(n + 1));
  out.vertex_rows[0] = ch.rows.front();
  out.vertex_rows[static_cast<std::size_t>(n)] = ch.rows.back();
  for (int k = 0; k + 1 < n; ++k) {
    const int c = ch.first + k;
    const int x_model = c + 1 - fg.side;  // the boundary, in model voxels
    const double z_ref = ch.rows[static_cast<std::size_t>(k)] - fg.floor + t;
    std::optional<double> z1 = fine.edge(x_model * fine.scale - 1, t, z_ref, ch.wall_below);
    std::optional<double> z2 =
        fine.edge(x_model * fine.scale, t, ch.rows[static_cast<std::size_t>(k + 1)] - fg.floor + t, ch.wall_below);
    const double lo = std::max(ch.low[static_cast<std::size_t>(k)], ch.low[static_cast<std::size_t>(k + 1)]) + 0.1;
    const double hi = std::min(ch.high[static_cast<std::size_t>(k)], ch.high[static_cast<std::size_t>(k + 1)]) - 0.1;
    const int r1 = ch.rows[static_cast<std::size_t>(k)], r2 = ch.rows[static_cast<std::size_t>(k + 1)];
    if (r1 != r2) {
      out.expected.push_back(fg.pt(c + 1, r1));
      out.expected.push_back(fg.pt(c + 1, r2));
    }
    if ((z1 || z2) && lo <= hi) {
      const double z = z1 && z2 ? (*z1 + *z2) / 2 : (z1 ? *z1 : *z2);
      const double row = std::clamp(z - t + fg.floor, lo, hi);
      out.vertex_rows[static_cast<std::size_t>(k + 1)] = row;
      out.interior.push_back(fg.pt(c + 1, row));
      ++out.found;
    } else {
      ++cmp.steps_kept;
      out.interior.push_back(fg.pt(c + 1, r1));
      if (r2 != r1) out.interior.push_back(fg.pt(c + 1, r2));  // a repeated point would pinch the ring
      out.vertex_rows[static_cast<std::size_t>(k + 1)] = (r1 + r2) / 2.0;
    }
  }
  return out;
}

// Distances to the silhouette at every fine column inside the chain, from the voxel steps and
// from the outline.
struct Distances {
  double voxel_sum = 0, face_sum = 0, voxel_max = 0, face_max = 0;
  int samples = 0;
};

Distances distances(const Chain& ch, double t, const Outline& outline, const FaceGrid& fg, const FineDepth& fine) {
  const int n = static_cast<int>(ch.rows.size());
  Distances d;
  for (int i = (ch.first - fg.side) * fine.scale; i < (ch.first - fg.side + n) * fine.scale; ++i) {
    const double x = (i + 0.5) / fine.scale;  // model voxels
    const int k = static_cast<int>(x) - (ch.first - fg.side);
    const double z_voxel = ch.rows[static_cast<std::size_t>(k)] - fg.floor + t;
    const std::optional<double> z_sil = fine.edge(i, t, z_voxel, ch.wall_below);
    if (!z_sil) continue;
    // The polyline between the vertices of slice k: the left end x = k, the right x = k + 1.
    const double f = x - static_cast<int>(x);
    const double row = outline.vertex_rows[static_cast<std::size_t>(k)] * (1 - f) +
                       outline.vertex_rows[static_cast<std::size_t>(k + 1)] * f;
    const double z_face = row - fg.floor + t;
    const double dv = std::abs(z_voxel - *z_sil) * fg.mm, df = std::abs(z_face - *z_sil) * fg.mm;
    d.voxel_sum += dv;
    d.face_sum += df;
    d.voxel_max = std::max(d.voxel_max, dv);
    d.face_max = std::max(d.face_max, df);
    ++d.samples;
  }
  return d;
}

enum class Redrawn { yes, no_route, area_changed };

// Redraws the chain's cut in both faces' rings. A (below) walks its edge right to left, B (above)
// left to right: both keep the region on their left. Anything but yes leaves the faces as they were.
Redrawn redraw(std::vector<PatternFace>& faces, const Chain& ch, const Outline& outline, const FaceGrid& fg) {
  const int n = static_cast<int>(ch.rows.size());
  const Point2 left = fg.pt(ch.first, ch.rows.front()), right = fg.pt(ch.first + n, ch.rows.back());
  PatternFace& fa = faces[static_cast<std::size_t>(ch.a)];
  PatternFace& fb = faces[static_cast<std::size_t>(ch.b)];
  std::vector<Ring*> rings_a{&fa.outer}, rings_b{&fb.outer};
  for (Ring& h : fa.holes) rings_a.push_back(&h);
  for (Ring& h : fb.holes) rings_b.push_back(&h);
  const std::vector<Point2> expected_rev(outline.expected.rbegin(), outline.expected.rend());
  const std::vector<Point2> interior_rev(outline.interior.rbegin(), outline.interior.rend());
  const PatternFace keep_a = fa, keep_b = fb;
  if (!replace_path(rings_a, right, left, expected_rev, interior_rev) ||
      !replace_path(rings_b, left, right, outline.expected, outline.interior)) {
    fa = keep_a;
    fb = keep_b;
    return Redrawn::no_route;
  }
  // The outline only moves area between the two faces; when a ring took another route round
  // a face (a point it passes twice) or a face would vanish, this outline stays in steps.
  const double before = face_area_mm2(keep_a) + face_area_mm2(keep_b);
  const double area_a = face_area_mm2(fa), area_b = face_area_mm2(fb);
  if (!(area_a > 0 && area_b > 0 && std::abs(area_a + area_b - before) <= 1e-6 * std::max(1.0, before)) ||
      !ring_ok(fa.outer) || !ring_ok(fb.outer)) {
    fa = keep_a;
    fb = keep_b;
    return Redrawn::area_changed;
  }
  return Redrawn::yes;
}

// The redrawn faces as a face model when its card pops up; else the voxel outlines, which the
// voxel card has already shown to work.
SilhouetteFaces finish(const Pattern& voxel_pattern, const std::vector<PatternFace>& faces, SilhouetteComparison cmp,
                       const std::string& source) {
  const Rect sheet = voxel_pattern.sheet;
  const auto model_of = [&](const std::vector<PatternFace>& fs) {
    std::vector<OAFace> out;
    for (const PatternFace& f : fs) out.push_back(OAFace{f.kind, f.t_mm, PolygonWithHoles{f.outer, f.holes}});
    return FaceModel::from_faces(sheet.max.x_mm, sheet.max.v_mm, -sheet.min.v_mm, out, source);
  };
  cmp.voxel_lines = static_cast<int>(voxel_pattern.lines.size());
  try {
    FaceModel model = model_of(faces);
    const Pattern p = make_pattern(AnyModel(model), source);
    if (check_popup(p).pops_up()) {
      cmp.face_lines = static_cast<int>(p.lines.size());
      return SilhouetteFaces{std::move(model), cmp};
    }
  } catch (const Error&) {
    // Fall through to the voxel outlines.
  }
  FaceModel model = model_of(voxel_pattern.faces);
  cmp = SilhouetteComparison{};
  cmp.fell_back = true;
  cmp.voxel_lines = cmp.face_lines = static_cast<int>(voxel_pattern.lines.size());
  return SilhouetteFaces{std::move(model), cmp};
}

}  // namespace

SilhouetteFaces silhouette_faces(const TriangleSoup& mesh, const ImportOptions& o, const ImportResult& r,
                                 const std::string& source) {
  const VoxelModel& m = r.model;
  const CellGrid g = make_cell_grid(m, source);
  const Pattern voxel_pattern = make_pattern(g);
  std::vector<PatternFace> faces = voxel_pattern.faces;
  const FaceGrid fg{g, voxel_pattern.faces, cell_regions(g), g.sheet.side, g.sheet.floor, g.voxel_mm};
  const FineDepth fine = fine_depth(mesh, o, r.grid, source);

  SilhouetteComparison cmp;
  double voxel_sum = 0, face_sum = 0;
  for (const Chain& ch : find_chains(fg, m.width)) {
    if (ch.rows.size() < 2) continue;  // a single slice has no step to smooth
    const double t = fg.t_of(ch.wall_below ? ch.a : ch.b);
    const Outline outline = outline_of(ch, t, fg, fine, cmp);
    if (outline.found == 0) continue;  // the silhouette at this depth is nowhere near: nothing to redraw
    // An outline that would not come closer than its steps (the search found another edge) keeps its steps.
    const Distances d = distances(ch, t, outline, fg, fine);
    if (d.samples == 0 || d.face_sum > d.voxel_sum) {
      ++cmp.outlines_kept;
      continue;
    }
    const Redrawn done = redraw(faces, ch, outline, fg);
    if (done == Redrawn::area_changed) ++cmp.outlines_kept;
    if (done != Redrawn::yes) continue;
    ++cmp.outlines;
    voxel_sum += d.voxel_sum;
    face_sum += d.face_sum;
    cmp.voxel_max_mm = std::max(cmp.voxel_max_mm, d.voxel_max);
    cmp.face_max_mm = std::max(cmp.face_max_mm, d.face_max);
    cmp.samples += d.samples;
  }
  if (cmp.samples > 0) {
    cmp.voxel_mean_mm = voxel_sum / cmp.samples;
    cmp.face_mean_mm = face_sum / cmp.samples;
  }
  return finish(voxel_pattern, faces, cmp, source);
}

}  // namespace popcut
