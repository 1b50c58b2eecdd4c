// Open/close simulation (polygon paper eq. 7) and the triangulated card at any fold angle.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "popcut/pattern/pattern.h"

namespace popcut {

// Eq. 7: a point (x, y, z) of the card at 90° moves to (x, y − z cos θ, z sin θ) at fold angle θ:
// 0° flat (the sheet lies in z = 0 with y = −v), 90° standing, 180° closed (everything flat again).
// Every face moves rigidly: a VFace turns about its foot, an HFace only slides.
Point3 fold_point(Point3 at_90, double angle_deg);

// Triangles covering a face (outer ring minus holes), counter-clockwise in (x, v).
std::vector<std::array<Point2, 3>> triangulate(const PatternFace& face);
std::vector<std::array<Point2, 3>> triangulate(const Ring& outer, const std::vector<Ring>& holes);

// The card at a fold angle: each face triangulated in the pattern, mapped to 3D (eq. 2, 3),
// then moved by eq. 7. Triangles run counter-clockwise seen from the sheet's printed side.
struct CardMesh {
  std::vector<Point3> vertices;                         // mm, card coordinates
  std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into vertices
  std::vector<Point2> pattern_points;                   // each vertex where it lies on the flat sheet
  std::vector<int> triangle_face;                       // the pattern face of each triangle
  std::vector<FaceKind> face_kind;                      // per pattern face
};

// The range of an opening angle, for every command option and API field that takes one: throws
// popcut::Error (invalid_input, naming `field` and the range) unless 0 ≤ angle_deg ≤ 180.
void check_fold_angle(double angle_deg, const std::string& field);

// Throws as check_fold_angle (field "angle") unless 0 ≤ angle_deg ≤ 180.
CardMesh fold_card(const Pattern& pattern, double angle_deg);

}  // namespace popcut
