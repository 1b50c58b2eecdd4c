// Pictures of the folded card: a 3/4 view with hidden surfaces removed, as SVG or PNG.
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

// The card folded to `angle_deg` for a picture. Closed (180°) its layers lie in one plane and no
// depth test can order them (the picture speckles), so pictures stop at kPictureMaxAngleDeg:
// 1° open, which shows the same card with its layers apart.
inline constexpr double kPictureMaxAngleDeg = 179;
CardMesh fold_card_for_picture(const Pattern& pattern, double angle_deg);

// Orthographic 3/4 view from the front right, above the card; the printed side in cream, the back
// in blue-grey, both lit by one light so folds read as shading.
ViewBox view_box(const std::vector<CardMesh>& meshes);

// SVG: triangles drawn far to near (painter's algorithm), which OA cards need no more than:
// their faces meet only along edges. Size in px at `px_per_mm`.
void write_render_svg(std::ostream& out, const CardMesh& mesh, const ViewBox& box, double px_per_mm);

// PNG: a z-buffer at `width_px`, supersampled 2× for smooth edges; returns the file's bytes.
std::string render_png(const CardMesh& mesh, const ViewBox& box, int width_px);

}  // namespace popcut
