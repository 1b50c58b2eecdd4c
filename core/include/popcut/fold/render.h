// Pictures of the folded card: a 3/4 view with hidden surfaces removed, lit by one lamp, as SVG or PNG.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "popcut/fold/fold.h"

namespace popcut {

// The view's extent on the image plane, in mm, so every frame of an animation shares one frame.
struct ViewBox {
  double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

// A direction in the right-handed Y-up frame of the 3D exports (OBJ, glTF) and of three.js:
// X = x across the card, Y = z up, Z = y toward the front of the card.
struct YUpDirection {
  double x, y, z;
};

// The pictures' camera and lamp, kept here so a browser view (three.js) can show the card as the
// pictures do. The camera is orthographic and looks at the card from kPictureView (toward the
// viewer: front, right, above; any length). The lamp is a directional light toward kPictureLight
// (a unit vector: above, left and in front of the card). From the left, the card's walls cast their
// shadows to the right, onto the floor beside them and down the back wall, where the camera sees
// them, so a wall in front reads apart from the wall behind it; 53° high, floors and roofs
// (n · L = 0.8) stay lighter than walls (0.36 standing). The side of the paper the camera sees,
// with unit normal n, is drawn as
//   paper colour × (kPictureAmbient + kPictureDiffuse × max(0, n · kPictureLight) × lit)
// with lit = 1 where the lamp reaches the point, 0 in a shadow (which keeps the ambient light only)
// and between across a shadow's soft edge, the factors applied to the sRGB colour as it is (only
// the PNG has shadows; the SVG draws lit = 1). In three.js: an AmbientLight of
// kPictureAmbient and a DirectionalLight of kPictureDiffuse at kPictureLight (its target at the
// origin) casting shadows, on Lambert materials; both intensities × π from r155 on, whose lights
// have no artist's factor of π, and three.js lights in linear space, so its half-tones come out
// somewhat lighter than these pictures' unless colour management is turned off.
inline constexpr YUpDirection kPictureView{0.55, 0.65, 1.0};
inline constexpr YUpDirection kPictureLight{-0.48, 0.8, 0.36};
inline constexpr double kPictureAmbient = 0.5;
inline constexpr double kPictureDiffuse = 0.55;

// The card folded to `angle_deg` for a picture. Closed (180°) its layers lie in one plane and no
// depth test can order them (the picture speckles), so pictures stop at kPictureMaxAngleDeg:
// 1° open, which shows the same card with its layers apart.
inline constexpr double kPictureMaxAngleDeg = 179;
// Without the paper that drops out of openings (the check's cut_out).
CardMesh fold_card_for_picture(const Pattern& pattern, double angle_deg);

// The printed side in cream, the back in blue-grey, both lit by kPictureLight so folds read as
// shading. Every frame of an animation shares the box of all its meshes.
ViewBox view_box(const std::vector<CardMesh>& meshes);

// SVG: triangles drawn far to near (painter's algorithm), which OA cards need no more than:
// their faces meet only along edges. Lambert shading with the pictures' lamp, no cast shadows.
// Size in px at `px_per_mm`.
void write_render_svg(std::ostream& out, const CardMesh& mesh, const ViewBox& box, double px_per_mm);

// PNG: a z-buffer at `width_px`, supersampled 2× for smooth edges, with the shadows the lamp casts
// (a shadow map with soft edges); returns the file's bytes.
std::string render_png(const CardMesh& mesh, const ViewBox& box, int width_px);

// Where a card point (mm, at whatever angle it was folded to) lands in render_png's picture of
// `box` at `width_px`: pixels from the top-left corner, x to the right and y down; pixel (i, j)
// covers [i, i + 1) × [j, j + 1). render_png places every vertex with it.
struct PicturePoint {
  double x_px, y_px;
};
PicturePoint picture_point(const Point3& p, const ViewBox& box, int width_px);

}  // namespace popcut
