// Eq. 7 applied to the triangulated faces of a pattern.
#include "popcut/fold/fold.h"

#include <cmath>
#include <numbers>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {

Point3 fold_point(Point3 p, double angle_deg) {
  const double theta = angle_deg * std::numbers::pi / 180.0;
  // Exact at the angles people ask for most, so a closed card is flat to the last bit.
  const double c = angle_deg == 90 ? 0.0 : (angle_deg == 180 ? -1.0 : (angle_deg == 0 ? 1.0 : std::cos(theta)));
  const double s = angle_deg == 90 ? 1.0 : (angle_deg == 180 || angle_deg == 0 ? 0.0 : std::sin(theta));
  return {p.x_mm, p.y_mm - p.z_mm * c, p.z_mm * s};
}

void check_fold_angle(double angle_deg, const std::string& field) {
  if (std::isfinite(angle_deg) && angle_deg >= 0 && angle_deg <= 180) return;
  throw Error(ErrorCode::invalid_input, "", field,
              "the fold angle must be from 0 (flat) to 180 (closed) degrees, not " + format_significant(angle_deg, 15));
}

CardMesh fold_card(const Pattern& pattern, double angle_deg) {
  check_fold_angle(angle_deg, "angle");
  CardMesh mesh;
  for (std::size_t fi = 0; fi < pattern.faces.size(); ++fi) {
    const PatternFace& f = pattern.faces[fi];
    mesh.face_kind.push_back(f.kind);
    for (const auto& tri : triangulate(f)) {
      std::array<std::uint32_t, 3> idx{};
      for (std::size_t k = 0; k < 3; ++k) {
        idx[k] = static_cast<std::uint32_t>(mesh.vertices.size());
        mesh.vertices.push_back(fold_point(to_card(f.kind, f.t_mm, tri[k]), angle_deg));
        mesh.pattern_points.push_back(tri[k]);
      }
      mesh.triangles.push_back(idx);
      mesh.triangle_face.push_back(static_cast<int>(fi));
    }
  }
  return mesh;
}

}  // namespace popcut
