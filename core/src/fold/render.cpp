// Software rendering of the folded card: painter's algorithm to SVG, z-buffer and shadow map to PNG (stb).
#include "popcut/fold/render.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#include "depth_buffer.h"
#include "picture_space.h"
#include "popcut/error.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/text.h"
#include "shadow_map.h"

namespace popcut {
namespace {

using picture::kCameraAxes;
using picture::kLightAxes;
using picture::V3;

struct Screen {
  double x, y, depth;  // depth grows toward the viewer
};
Screen project(const Point3& p) {
  const V3 q = picture::frame(p);
  return {dot(q, kCameraAxes.right), dot(q, kCameraAxes.up), dot(q, kCameraAxes.toward)};
}

// The side of a triangle the camera sees: its paper's colour and how squarely it faces the lamp.
struct SeenSide {
  double rgb[3];
  double facing_light;  // n · kPictureLight for that side's normal n; ≤ 0 when the lamp is behind it
};
SeenSide seen_side(const CardMesh& m, const std::array<std::uint32_t, 3>& t) {
  V3 n = picture::normal_of(m, t);
  const bool front = dot(n, kCameraAxes.toward) >= 0;
  if (!front) n = -1.0 * n;
  static constexpr double kPaper[2][3] = {{245, 237, 214}, {140, 158, 184}};  // cream front, blue-grey back
  const double* c = kPaper[front ? 0 : 1];
  return {{c[0], c[1], c[2]}, dot(n, kLightAxes.toward)};
}

struct Shade {
  unsigned char r, g, b;
};
// The lighting render.h documents, with `lit_share` of the lamp reaching the point.
Shade shade(const SeenSide& s, double lit_share) {
  const double k = kPictureAmbient + kPictureDiffuse * std::max(0.0, s.facing_light) * lit_share;
  const auto ch = [&](double v) { return static_cast<unsigned char>(std::clamp(std::round(v * k), 0.0, 255.0)); };
  return {ch(s.rgb[0]), ch(s.rgb[1]), ch(s.rgb[2])};
}

// The box (view_box) holds every point drawn, so coordinates are never below zero and the
// "-0.00" that format_fixed would write as "0.00" cannot arise.
std::string num(double v) { return format_fixed(v, 2); }

constexpr int kSupersample = 2;  // per axis: edges are averaged over 2 × 2 samples

// The camera's z-buffer, kSupersample times the picture's size, each pixel knowing its triangle.
picture::DepthBuffer draw_view(const CardMesh& m, const ViewBox& box, int width_px, int height_px) {
  picture::DepthBuffer view(width_px * kSupersample, height_px * kSupersample);
  std::vector<picture::RasterPoint> at(m.vertices.size());
  for (std::size_t i = 0; i < at.size(); ++i) {
    const PicturePoint q = picture_point(m.vertices[i], box, width_px);
    at[i] = {q.x_px * kSupersample, q.y_px * kSupersample, project(m.vertices[i]).depth};
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    view.draw({at[t[0]], at[t[1]], at[t[2]]}, static_cast<std::uint32_t>(i));
  }
  return view;
}

// Lights every pixel of `view`: the point it shows, found again from its depth, is looked up in the
// shadow map, unless the lamp is behind its side anyway. Returns RGB, white where nothing was drawn.
std::vector<unsigned char> shade_view(const CardMesh& m, const ViewBox& box, const picture::DepthBuffer& view,
                                      double px_per_mm) {
  // A texel per picture pixel: the taps then spread a shadow's edge over about three pixels, soft
  // but still sharp where a wall stands on its shadow, and the map is a quarter of the samples.
  const picture::ShadowMap shadows(m, kSupersample / px_per_mm);
  std::vector<SeenSide> sides;
  sides.reserve(m.triangles.size());
  for (const auto& t : m.triangles) sides.push_back(seen_side(m, t));
  std::vector<unsigned char> rgb(view.depth_mm.size() * 3, 255);
  for (int y = 0; y < view.height_px; ++y) {
    const double up_mm = box.max_y - (y + 0.5) / px_per_mm;
    for (int x = 0; x < view.width_px; ++x) {
      const std::size_t i = view.index(x, y);
      const std::uint32_t tri = view.id[i];
      if (tri == picture::kNoTriangle) continue;
      const SeenSide& side = sides[tri];
      double lit = 0;
      if (side.facing_light > 0) {
        const double right_mm = box.min_x + (x + 0.5) / px_per_mm;
        const V3 p = right_mm * kCameraAxes.right + up_mm * kCameraAxes.up + view.depth_mm[i] * kCameraAxes.toward;
        lit = shadows.lit_share(p, tri);
      }
      const Shade s = shade(side, lit);
      rgb[3 * i] = s.r;
      rgb[3 * i + 1] = s.g;
      rgb[3 * i + 2] = s.b;
    }
  }
  return rgb;
}

// Box-filters the supersampled image down to `width_px` × `height_px`.
std::vector<unsigned char> downsample(const std::vector<unsigned char>& rgb, int width_px, int height_px) {
  const auto wide = static_cast<std::size_t>(width_px) * kSupersample;
  std::vector<unsigned char> image(static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px) * 3);
  for (int y = 0; y < height_px; ++y) {
    for (int x = 0; x < width_px; ++x) {
      for (std::size_t c = 0; c < 3; ++c) {
        int sum = 0;
        for (int dy = 0; dy < kSupersample; ++dy)
          for (int dx = 0; dx < kSupersample; ++dx)
            sum += rgb[3 * (static_cast<std::size_t>(y * kSupersample + dy) * wide +
                            static_cast<std::size_t>(x * kSupersample + dx)) +
                       c];
        image[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_px) + static_cast<std::size_t>(x)) +
              c] = static_cast<unsigned char>(sum / (kSupersample * kSupersample));
      }
    }
  }
  return image;
}

}  // namespace

CardMesh fold_card_for_picture(const Pattern& pattern, double angle_deg) {
  check_fold_angle(angle_deg, "angle");  // before the clamp below, which would make 1e9 a picture at 179°
  CardMesh mesh = fold_card(pattern, std::min(angle_deg, kPictureMaxAngleDeg));
  // The paper that drops out of openings (a round window's disc) is not on the card.
  const PopupReport report = check_popup(pattern);
  if (report.cut_out.empty()) return mesh;
  std::vector<char> gone(pattern.faces.size(), 0);
  for (const LoosePiece& lp : report.cut_out) {
    for (const int f : lp.faces) gone[static_cast<std::size_t>(f)] = 1;
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (gone[static_cast<std::size_t>(mesh.triangle_face[i])]) continue;
    mesh.triangles[kept] = mesh.triangles[i];
    mesh.triangle_face[kept] = mesh.triangle_face[i];
    ++kept;
  }
  mesh.triangles.resize(kept);
  mesh.triangle_face.resize(kept);
  return mesh;
}

ViewBox view_box(const std::vector<CardMesh>& meshes) {
  ViewBox b{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
            std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
  for (const CardMesh& m : meshes) {
    for (const Point3& p : m.vertices) {
      const Screen s = project(p);
      b.min_x = std::min(b.min_x, s.x);
      b.max_x = std::max(b.max_x, s.x);
      b.min_y = std::min(b.min_y, s.y);
      b.max_y = std::max(b.max_y, s.y);
    }
  }
  if (b.min_x > b.max_x) return {0, 0, 1, 1};
  const double margin = 0.04 * std::max(b.max_x - b.min_x, b.max_y - b.min_y);
  return {b.min_x - margin, b.min_y - margin, b.max_x + margin, b.max_y + margin};
}

PicturePoint picture_point(const Point3& p, const ViewBox& box, int width_px) {
  const double px_per_mm = width_px / (box.max_x - box.min_x);
  const Screen s = project(p);
  return {(s.x - box.min_x) * px_per_mm, (box.max_y - s.y) * px_per_mm};
}

// No cast shadows here: in SVG each would be a polygon clipped by every face between it and the
// lamp and again by every face in front of it, exact 2D Booleans (CGAL, as the pattern uses) that
// the pictures otherwise do without, and a shadowed card would be many times the file. The same
// lamp's shading keeps the SVG and the PNG alike; the PNG is the picture with shadows.
void write_render_svg(std::ostream& out, const CardMesh& m, const ViewBox& box, double px_per_mm) {
  const double w = (box.max_x - box.min_x) * px_per_mm, h = (box.max_y - box.min_y) * px_per_mm;
  std::vector<std::size_t> order(m.triangles.size());
  std::vector<double> depth(m.triangles.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = i;
    const auto& t = m.triangles[i];
    depth[i] =
        (project(m.vertices[t[0]]).depth + project(m.vertices[t[1]]).depth + project(m.vertices[t[2]]).depth) / 3;
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return depth[a] < depth[b]; });
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(w)
      << "\" height=\"" << num(h) << "\" viewBox=\"0 0 " << num(w) << " " << num(h) << "\">\n"
      << "  <rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  for (std::size_t i : order) {
    const auto& t = m.triangles[i];
    const Shade s = shade(seen_side(m, t), 1);
    char colour[8];
    std::snprintf(colour, sizeof colour, "#%02x%02x%02x", s.r, s.g, s.b);
    out << "  <polygon fill=\"" << colour << "\" stroke=\"" << colour
        << "\" stroke-width=\"0.6\" stroke-linejoin=\"round\" points=\"";
    for (int k = 0; k < 3; ++k) {
      const Screen p = project(m.vertices[t[static_cast<std::size_t>(k)]]);
      out << (k ? " " : "") << num((p.x - box.min_x) * px_per_mm) << "," << num((box.max_y - p.y) * px_per_mm);
    }
    out << "\"/>\n";
  }
  out << "</svg>\n";
}

std::string render_png(const CardMesh& m, const ViewBox& box, int width_px) {
  const double px_per_mm = kSupersample * width_px / (box.max_x - box.min_x);  // of the supersampled view
  const int height_px = std::max(1, static_cast<int>(std::ceil((box.max_y - box.min_y) * px_per_mm)) / kSupersample);
  const picture::DepthBuffer view = draw_view(m, box, width_px, height_px);
  const std::vector<unsigned char> image = downsample(shade_view(m, box, view, px_per_mm), width_px, height_px);
  // Encoded in memory: stbi's own file writer ignores short writes, so a full disk would go unnoticed.
  std::string png;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &png, width_px, height_px, 3, image.data(), width_px * 3)) {
    throw Error(ErrorCode::internal, "", "", "PNG encoding failed");
  }
  return png;
}

}  // namespace popcut
