// A z-buffer that remembers which triangle won each pixel: the camera's view and the light's shadow map.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace popcut::picture {

// A triangle's corner in a buffer: x and y in pixels (pixel (i, j) covers [i, i + 1) × [j, j + 1)),
// depth in mm growing toward the eye.
struct RasterPoint {
  double x, y, depth;
};

inline constexpr std::uint32_t kNoTriangle = 0xffffffffU;

struct DepthBuffer {
  DepthBuffer(int width_px, int height_px);
  // Where triangle `drawn` covers a pixel's centre nearer than what the pixel holds, the pixel takes
  // its depth and id; on a tie the triangle drawn first keeps the pixel. Edge-on triangles cover nothing.
  void draw(const std::array<RasterPoint, 3>& p, std::uint32_t drawn);
  std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x);
  }

  int width_px, height_px;
  std::vector<double> depth_mm;   // lowest() where nothing was drawn
  std::vector<std::uint32_t> id;  // what the caller drew (a triangle, a plane); kNoTriangle: nothing
};

}  // namespace popcut::picture
