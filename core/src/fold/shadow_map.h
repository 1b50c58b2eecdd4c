// The shadow map of the pictures' light (kPictureLight): which face is nearest the light over each
// texel, read with percentage-closer filtering so shadows have a soft edge and no face shadows itself.
#pragma once

#include <cstdint>
#include <vector>

#include "depth_buffer.h"
#include "picture_space.h"
#include "popcut/fold/fold.h"

namespace popcut::picture {

class ShadowMap {
 public:
  // `texel_mm` about a picture pixel keeps a shadow's edge as sharp as the picture; a larger card
  // gets coarser texels so the map stays within kMaxShadowMapSidePx on a side.
  ShadowMap(const CardMesh& mesh, double texel_mm);

  // The share of the light that reaches `p` (frame coordinates, mm), a point of triangle `tri`:
  // 1 lit, 0 in shadow, in between across a shadow's edge.
  double lit_share(V3 p, std::uint32_t tri) const;

 private:
  // How a triangle's plane moves toward the light per mm across the map: d depth / du and / dv.
  struct Slope {
    double du, dv;
  };
  struct Layout {
    double texel_mm, min_u_mm, min_v_mm;
    int width_px, height_px;
  };
  static Layout layout_for(const CardMesh& mesh, double texel_mm);
  void set_planes(const CardMesh& mesh);
  void set_blocks();
  bool occluded(int x, int y, double fu, double fv, double depth_mm, std::uint32_t plane) const;

  Layout layout_;
  std::vector<std::uint32_t> plane_of_;  // per triangle: its plane, the face it belongs to
  std::vector<Slope> slope_;             // per plane
  DepthBuffer map_;                      // the plane nearest the lamp over each texel
  // Per texel: the one plane in the 4 × 4 texels from it (right and up), kNoTriangle if none,
  // kMixedPlanes if more, so most lookups need one read instead of sixteen.
  std::vector<std::uint32_t> block_;
};

}  // namespace popcut::picture
