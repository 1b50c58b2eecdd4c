// The pictures' frame, camera and light as vectors: what the renderers and the shadow map share.
#pragma once

#include <cmath>

#include "popcut/fold/render.h"

namespace popcut::picture {

struct V3 {
  double x, y, z;
};
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator*(double k, V3 a) { return {k * a.x, k * a.y, k * a.z}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
// A degenerate triangle's normal stays zero rather than NaN, so it lights as if edge-on.
inline V3 unit(V3 a) {
  const double n = std::sqrt(dot(a, a));
  return n > 0 ? V3{a.x / n, a.y / n, a.z / n} : V3{0, 0, 0};
}

// Right-handed Y-up frame, as in the 3D exports and kPictureView: (X, Y, Z) = (x, z, y).
inline V3 frame(const Point3& p) { return {p.x_mm, p.z_mm, p.y_mm}; }

// An orthographic view looking along -toward: `right` and `up` span its image plane, and a point's
// depth, dot(p, toward), grows toward the eye (or the light). None of the views looks straight down.
struct ViewAxes {
  V3 right, up, toward;
  explicit ViewAxes(YUpDirection d) : toward(unit({d.x, d.y, d.z})) {
    const V3 forward{-toward.x, -toward.y, -toward.z};
    right = unit(cross(forward, {0, 1, 0}));
    up = cross(right, forward);
  }
};

inline const ViewAxes kCameraAxes{kPictureView};
inline const ViewAxes kLightAxes{kPictureLight};

// Triangle `t`'s unit normal in the frame, on the side its vertices run counter-clockwise.
inline V3 normal_of(const CardMesh& m, const std::array<std::uint32_t, 3>& t) {
  const V3 a = frame(m.vertices[t[0]]), b = frame(m.vertices[t[1]]), c = frame(m.vertices[t[2]]);
  return unit(cross(b - a, c - a));
}

}  // namespace popcut::picture
