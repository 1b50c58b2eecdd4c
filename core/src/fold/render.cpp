// Software rendering of the folded card: painter's algorithm to SVG, z-buffer to PNG (stb).
#include "popcut/fold/render.h"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
namespace {

struct V3 {
  double x, y, z;
};
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 unit(V3 a) {
  const double n = std::sqrt(dot(a, a));
  return {a.x / n, a.y / n, a.z / n};
}

// Right-handed Y-up frame, as in the 3D exports: (X, Y, Z) = (x, z, y).
V3 frame(const Point3& p) { return {p.x_mm, p.z_mm, p.y_mm}; }

struct Camera {
  V3 eye = unit({0.55, 0.65, 1.0});  // toward the viewer: front, right, above
  V3 right, up;
  V3 light = unit({-0.3, 0.8, 0.6});
  Camera() {
    const V3 forward{-eye.x, -eye.y, -eye.z};
    right = unit(cross(forward, {0, 1, 0}));
    up = cross(right, forward);
  }
};
const Camera kCamera;

struct Screen {
  double x, y, depth;  // depth grows toward the viewer
};
Screen project(const Point3& p) {
  const V3 q = frame(p);
  return {dot(q, kCamera.right), dot(q, kCamera.up), dot(q, kCamera.eye)};
}

struct Shade {
  unsigned char r, g, b;
};
// The side the camera sees, lit by one light with some ambient, so every fold shows.
Shade shade_of(const CardMesh& m, const std::array<std::uint32_t, 3>& t) {
  const V3 a = frame(m.vertices[t[0]]), b = frame(m.vertices[t[1]]), c = frame(m.vertices[t[2]]);
  V3 n = unit(cross(b - a, c - a));
  const bool front = dot(n, kCamera.eye) >= 0;
  if (!front) n = {-n.x, -n.y, -n.z};
  const double k = 0.45 + 0.55 * std::max(0.0, dot(n, kCamera.light));
  const double base[2][3] = {{245, 237, 214}, {140, 158, 184}};  // cream front, blue-grey back
  const double* col = base[front ? 0 : 1];
  const auto ch = [&](double v) { return static_cast<unsigned char>(std::clamp(v * k, 0.0, 255.0)); };
  return {ch(col[0]), ch(col[1]), ch(col[2])};
}

// The box (view_box) holds every point drawn, so coordinates are never below zero and the
// "-0.00" that format_fixed would write as "0.00" cannot arise.
std::string num(double v) { return format_fixed(v, 2); }

}  // namespace

CardMesh fold_card_for_picture(const Pattern& pattern, double angle_deg) {
  check_fold_angle(angle_deg, "angle");  // before the clamp below, which would make 1e9 a picture at 179°
  return fold_card(pattern, std::min(angle_deg, kPictureMaxAngleDeg));
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
    const Shade s = shade_of(m, t);
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
  const int ss = 2;  // supersampling
  const double scale = width_px * ss / (box.max_x - box.min_x);
  const int wide_px = width_px * ss;  // the supersampled image
  const int high_px = std::max(1, static_cast<int>(std::ceil((box.max_y - box.min_y) * scale)));
  std::vector<double> zbuf(static_cast<std::size_t>(wide_px) * static_cast<std::size_t>(high_px),
                           std::numeric_limits<double>::lowest());
  std::vector<unsigned char> rgb(zbuf.size() * 3, 255);
  for (const auto& t : m.triangles) {
    Screen p[3];
    for (int k = 0; k < 3; ++k) {
      const Screen s = project(m.vertices[t[static_cast<std::size_t>(k)]]);
      p[k] = {(s.x - box.min_x) * scale, (box.max_y - s.y) * scale, s.depth};
    }
    const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    if (std::abs(area) < 1e-12) continue;  // seen edge-on
    const Shade s = shade_of(m, t);
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
    const int x1 = std::min(wide_px - 1, static_cast<int>(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
    const int y1 = std::min(high_px - 1, static_cast<int>(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((p[1].x - px) * (p[2].y - py) - (p[2].x - px) * (p[1].y - py)) / area;
        const double w1 = ((p[2].x - px) * (p[0].y - py) - (p[0].x - px) * (p[2].y - py)) / area;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const double z = w0 * p[0].depth + w1 * p[1].depth + w2 * p[2].depth;
        const std::size_t i =
            static_cast<std::size_t>(y) * static_cast<std::size_t>(wide_px) + static_cast<std::size_t>(x);
        if (z <= zbuf[i]) continue;
        zbuf[i] = z;
        rgb[3 * i] = s.r;
        rgb[3 * i + 1] = s.g;
        rgb[3 * i + 2] = s.b;
      }
    }
  }
  // Box-filter the supersampled image down to the requested size.
  const int w = width_px, h = high_px / ss;
  std::vector<unsigned char> image(static_cast<std::size_t>(w) * static_cast<std::size_t>(std::max(h, 1)) * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < 3; ++c) {
        int sum = 0;
        for (int dy = 0; dy < ss; ++dy)
          for (int dx = 0; dx < ss; ++dx)
            sum += rgb[3 * (static_cast<std::size_t>(y * ss + dy) * static_cast<std::size_t>(wide_px) +
                            static_cast<std::size_t>(x * ss + dx)) +
                       static_cast<std::size_t>(c)];
        image[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) +
              static_cast<std::size_t>(c)] = static_cast<unsigned char>(sum / (ss * ss));
      }
    }
  }
  // Encoded in memory: stbi's own file writer ignores short writes, so a full disk would go unnoticed.
  std::string png;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<std::size_t>(size));
  };
  if (!stbi_write_png_to_func(append, &png, w, std::max(h, 1), 3, image.data(), w * 3)) {
    throw Error(ErrorCode::internal, "", "", "PNG encoding failed");
  }
  return png;
}

}  // namespace popcut
