// The pictures' shadow map: the light's view drawn with the picture's rasterizer, read with 4×4-tap
// percentage-closer filtering and a bias that follows each face's plane.
#include "shadow_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace popcut::picture {
namespace {

// 2048² texels of depth and id take 50 MB; the default picture (800 px, drawn at 1600) needs fewer.
constexpr int kMaxSideTexels = 2048;
// A plane's depth is exact at any texel centre, so the only slack needed is rounding.
constexpr double kRoundingMm = 1e-3;
// Planes almost edge-on to the light get no steeper than this (mm toward the light per mm across);
// they receive almost no light anyway (lambert), so a lookup on them matters little.
constexpr double kMaxSlope = 50;
constexpr std::uint32_t kMixedPlanes = kNoTriangle - 1;
constexpr int kTaps = 4;  // per axis

// The one plane of two texels or blocks (kNoTriangle: none), or kMixedPlanes.
std::uint32_t merge(std::uint32_t a, std::uint32_t b) {
  if (a == kNoTriangle || a == b) return b;
  return b == kNoTriangle ? a : kMixedPlanes;
}

}  // namespace

ShadowMap::Layout ShadowMap::layout_for(const CardMesh& m, double texel_mm) {
  double min_u = std::numeric_limits<double>::max(), min_v = min_u;
  double max_u = std::numeric_limits<double>::lowest(), max_v = max_u;
  for (const Point3& p : m.vertices) {
    const V3 q = frame(p);
    min_u = std::min(min_u, dot(q, kLightAxes.right));
    max_u = std::max(max_u, dot(q, kLightAxes.right));
    min_v = std::min(min_v, dot(q, kLightAxes.up));
    max_v = std::max(max_v, dot(q, kLightAxes.up));
  }
  if (min_u > max_u) return {1, 0, 0, 1, 1};  // nothing to shadow
  const double texel = std::max(texel_mm, std::max(max_u - min_u, max_v - min_v) / (kMaxSideTexels - 4));
  // Two texels of margin on each side, so the taps around any point of the card lie inside the map.
  return {texel, min_u - 2 * texel, min_v - 2 * texel, static_cast<int>(std::ceil((max_u - min_u) / texel)) + 4,
          static_cast<int>(std::ceil((max_v - min_v) / texel)) + 4};
}

// Faces are planar (a VFace, an HFace, a rigid region of a sheet), so the map stores planes: a
// face's triangles never shadow one another. Without faces each triangle is its own plane. A
// plane's slope comes from its largest triangle, whose normal is the most precise.
void ShadowMap::set_planes(const CardMesh& m) {
  const bool faces = m.triangle_face.size() == m.triangles.size();
  plane_of_.resize(m.triangles.size());
  for (std::size_t i = 0; i < m.triangles.size(); ++i)
    plane_of_[i] = static_cast<std::uint32_t>(faces ? m.triangle_face[i] : static_cast<int>(i));
  const std::size_t planes =
      plane_of_.empty() ? 0 : static_cast<std::size_t>(*std::max_element(plane_of_.begin(), plane_of_.end())) + 1;
  std::vector<double> largest(planes, -1);
  slope_.assign(planes, {0, 0});
  const ViewAxes& l = kLightAxes;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    const V3 a = frame(m.vertices[t[0]]), n = cross(frame(m.vertices[t[1]]) - a, frame(m.vertices[t[2]]) - a);
    const double area = dot(n, n);
    if (area <= largest[plane_of_[i]]) continue;
    largest[plane_of_[i]] = area;
    const V3 u = unit(n);
    const double toward = dot(u, l.toward);
    const double n_l = std::abs(toward) < 1 / kMaxSlope ? std::copysign(1 / kMaxSlope, toward) : toward;
    slope_[plane_of_[i]] = {std::clamp(-dot(u, l.right) / n_l, -kMaxSlope, kMaxSlope),
                            std::clamp(-dot(u, l.up) / n_l, -kMaxSlope, kMaxSlope)};
  }
}

ShadowMap::ShadowMap(const CardMesh& m, double texel_mm)
    : layout_(layout_for(m, texel_mm)), map_(layout_.width_px, layout_.height_px) {
  set_planes(m);
  const ViewAxes& l = kLightAxes;
  std::vector<RasterPoint> at(m.vertices.size());
  for (std::size_t i = 0; i < at.size(); ++i) {
    const V3 q = frame(m.vertices[i]);
    at[i] = {(dot(q, l.right) - layout_.min_u_mm) / layout_.texel_mm,
             (dot(q, l.up) - layout_.min_v_mm) / layout_.texel_mm, dot(q, l.toward)};
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    map_.draw({at[t[0]], at[t[1]], at[t[2]]}, plane_of_[i]);
  }
  set_blocks();
}

void ShadowMap::set_blocks() {
  const int w = map_.width_px, h = map_.height_px;
  std::vector<std::uint32_t> rows(map_.id.size(), kNoTriangle);  // along x first, then along y
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint32_t one = kNoTriangle;
      for (int a = x; a < std::min(x + kTaps, w); ++a) one = merge(one, map_.id[map_.index(a, y)]);
      rows[map_.index(x, y)] = one;
    }
  }
  block_.assign(map_.id.size(), kNoTriangle);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint32_t one = kNoTriangle;
      for (int b = y; b < std::min(y + kTaps, h); ++b) one = merge(one, rows[map_.index(x, b)]);
      block_[map_.index(x, y)] = one;
    }
  }
}

// Whether the plane nearest the lamp at texel (x, y) shadows the receiver's plane there. The
// receiver is compared with its own plane under the texel's centre (receiver-plane depth), not
// with the point looked up, so a face tilted to the lamp needs no slope bias to stay clear of acne.
// Where two faces meet at a fold, a tap across the fold compares the receiver's plane continued
// past the fold with the other face; they part by at most (tap distance × difference of slopes),
// which the bias allows, so a lit corner does not darken, and a shadow the other face casts starts
// within a tap of the fold (inside its soft edge), never a visible gap away.
bool ShadowMap::occluded(int x, int y, double fu, double fv, double depth_mm, std::uint32_t plane) const {
  if (x < 0 || y < 0 || x >= map_.width_px || y >= map_.height_px) return false;
  const std::size_t k = map_.index(x, y);
  const std::uint32_t o = map_.id[k];
  if (o == kNoTriangle || o == plane) return false;
  const double du_mm = (x - fu) * layout_.texel_mm, dv_mm = (y - fv) * layout_.texel_mm;
  const Slope r = slope_[plane], s = slope_[o];
  const double nearer_mm = map_.depth_mm[k] - (depth_mm + r.du * du_mm + r.dv * dv_mm) - kRoundingMm;
  if (nearer_mm <= 0) return false;  // behind the receiver's plane: no need for the fold's allowance
  const double apart_du = s.du - r.du, apart_dv = s.dv - r.dv;
  return nearer_mm * nearer_mm > (du_mm * du_mm + dv_mm * dv_mm) * (apart_du * apart_du + apart_dv * apart_dv);
}

double ShadowMap::lit_share(V3 p, std::uint32_t tri) const {
  const ViewAxes& l = kLightAxes;
  const std::uint32_t plane = plane_of_[tri];
  // In texels, with texel centres at whole numbers.
  const double fu = (dot(p, l.right) - layout_.min_u_mm) / layout_.texel_mm - 0.5;
  const double fv = (dot(p, l.up) - layout_.min_v_mm) / layout_.texel_mm - 0.5;
  const int x0 = static_cast<int>(std::floor(fu)) - 1, y0 = static_cast<int>(std::floor(fv)) - 1;
  // Most points have only their own face (or nothing) toward the lamp: lit, with no depth to compare.
  if (x0 >= 0 && y0 >= 0 && x0 < map_.width_px && y0 < map_.height_px) {
    const std::uint32_t one = block_[map_.index(x0, y0)];
    if (one == plane || one == kNoTriangle) return 1;
  }
  // A tent two texels wide each way over the 4 × 4 texels around p: the weights sum to 4 in each
  // direction wherever p lies, so the edge moves smoothly as p does (no stair steps of texels).
  const double au = fu - (x0 + 1), av = fv - (y0 + 1);
  const double wu[4] = {1 - au, 2 - au, 1 + au, au}, wv[4] = {1 - av, 2 - av, 1 + av, av};
  const double depth_mm = dot(p, l.toward);
  double lit = 0;
  for (int b = 0; b < kTaps; ++b) {
    for (int a = 0; a < kTaps; ++a) {
      if (!occluded(x0 + a, y0 + b, fu, fv, depth_mm, plane)) lit += wu[a] * wv[b];
    }
  }
  return lit / 16;
}

}  // namespace popcut::picture
