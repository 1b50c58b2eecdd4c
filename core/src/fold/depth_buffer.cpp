// Triangle rasterization into a z-buffer with triangle ids, shared by the picture and its shadow map.
#include "depth_buffer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace popcut::picture {

DepthBuffer::DepthBuffer(int width, int height)
    : width_px(width),
      height_px(height),
      depth_mm(static_cast<std::size_t>(width) * static_cast<std::size_t>(height),
               std::numeric_limits<double>::lowest()),
      id(depth_mm.size(), kNoTriangle) {}

void DepthBuffer::draw(const std::array<RasterPoint, 3>& p, std::uint32_t drawn) {
  const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
  if (std::abs(area) < 1e-12) return;  // seen edge-on
  // Barycentric weight i at (px, py) is a[i]·px + b[i]·py + c[i]: the signed area of the corner's
  // opposite edge and the pixel, over the whole; evaluated afresh at each pixel, never accumulated,
  // so two triangles sharing an edge agree on which side every pixel centre lies.
  double a[3], b[3], c[3];
  for (std::size_t i = 0; i < 3; ++i) {
    const RasterPoint& u = p[(i + 1) % 3];
    const RasterPoint& v = p[(i + 2) % 3];
    a[i] = (u.y - v.y) / area;
    b[i] = (v.x - u.x) / area;
    c[i] = (u.x * v.y - v.x * u.y) / area;
  }
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
  const int x1 = std::min(width_px - 1, static_cast<int>(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
  const int y1 = std::min(height_px - 1, static_cast<int>(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
  for (int y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    // The row's span inside all three edges, widened by a pixel: a thin slanted triangle then
    // costs its own pixels, not its bounding box's. The test below decides each pixel exactly.
    double lo = x0, hi = x1;
    for (std::size_t i = 0; i < 3; ++i) {
      const double edge_at = -(b[i] * py + c[i]);  // a[i]·px ≥ edge_at inside
      if (a[i] > 0) lo = std::max(lo, edge_at / a[i] - 1);
      if (a[i] < 0) hi = std::min(hi, edge_at / a[i] + 1);
    }
    const int from = static_cast<int>(std::floor(std::min(lo, x1 + 1.0)));  // clamped: lo may be far off
    const int to = static_cast<int>(std::ceil(std::max(hi, x0 - 1.0)));
    for (int x = from; x <= to; ++x) {
      const double px = x + 0.5;
      const double w0 = a[0] * px + b[0] * py + c[0], w1 = a[1] * px + b[1] * py + c[1], w2 = 1 - w0 - w1;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      const double z = w0 * p[0].depth + w1 * p[1].depth + w2 * p[2].depth;
      const std::size_t i = index(x, y);
      if (z <= depth_mm[i]) continue;
      depth_mm[i] = z;
      id[i] = drawn;
    }
  }
}

}  // namespace popcut::picture
