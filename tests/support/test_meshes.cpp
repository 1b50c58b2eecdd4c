// Builds the test meshes from extruded convex polygons and writes them as OBJ, OFF, PLY and STL.
#include "test_meshes.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <unistd.h>

namespace popcut::testing {
namespace {

std::uint32_t add_point(TriangleSoup& s, double x, double y, double z) {
  s.points.push_back({x, y, z});
  return static_cast<std::uint32_t>(s.points.size() - 1);
}

}  // namespace

void add_prism(TriangleSoup& s, const std::vector<XZ>& outline, double y0, double y1) {
  const std::size_t n = outline.size();
  std::vector<std::uint32_t> front(n), back(n);
  for (std::size_t i = 0; i < n; ++i) {
    front[i] = add_point(s, outline[i][0], y0, outline[i][1]);
    back[i] = add_point(s, outline[i][0], y1, outline[i][1]);
  }
  // Outward normals: the front cap faces -y, the back cap +y, the sides away from the axis.
  for (std::size_t i = 1; i + 1 < n; ++i) {
    s.triangles.push_back({front[0], front[i], front[i + 1]});
    s.triangles.push_back({back[0], back[i + 1], back[i]});
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    s.triangles.push_back({front[i], back[i], back[j]});
    s.triangles.push_back({front[i], back[j], front[j]});
  }
  s.polygons += static_cast<std::int64_t>(2 + n);
}

void add_box(TriangleSoup& s, double x0, double y0, double z0, double x1, double y1, double z1) {
  add_prism(s, {{x0, z0}, {x1, z0}, {x1, z1}, {x0, z1}}, y0, y1);
}

TriangleSoup house_mesh(double width, double depth, double wall, double roof) {
  TriangleSoup s;
  add_prism(s, {{0, 0}, {width, 0}, {width, wall}, {width / 2, wall + roof}, {0, wall}}, 0, depth);
  // A porch before the door: lower and in front of the house's front wall (y < 0).
  add_box(s, width * 0.35, -depth * 0.3, 0, width * 0.65, 0, wall * 0.45);
  return s;
}

TriangleSoup arch_mesh(double width, double height, double depth, int segments) {
  TriangleSoup s;
  const double pier = width * 0.2;
  const double radius = (width - 2 * pier) / 2;
  const double spring = height - radius - height * 0.15;  // where the arch starts to curve
  add_box(s, 0, 0, 0, pier, depth, spring);
  add_box(s, width - pier, 0, 0, width, depth, spring);
  // The spandrel above the opening, one convex quad per facet of the semicircle.
  const double cx = width / 2;
  for (int i = 0; i < segments; ++i) {
    const double a0 = M_PI * (1.0 - static_cast<double>(i) / segments);
    const double a1 = M_PI * (1.0 - static_cast<double>(i + 1) / segments);
    const double x0 = cx + radius * std::cos(a0), z0 = spring + radius * std::sin(a0);
    const double x1 = cx + radius * std::cos(a1), z1 = spring + radius * std::sin(a1);
    add_prism(s, {{x0, z0}, {x1, z1}, {x1, height}, {x0, height}}, 0, depth);
  }
  add_box(s, 0, 0, spring, pier, depth, height);
  add_box(s, width - pier, 0, spring, width, depth, height);
  return s;
}

TriangleSoup tower_mesh(int tiers, double base, double tier_height) {
  TriangleSoup s;
  for (int i = 0; i < tiers; ++i) {
    const double inset = base * 0.12 * i;
    add_box(s, inset, inset, tier_height * i, base - inset, base - inset * 0.5, tier_height * (i + 1));
  }
  return s;
}

TriangleSoup street_mesh(int houses) {
  TriangleSoup s;
  const double w = 80.0 / houses;
  // The street's back wall spans the full depth so the kept front half starts at y = 40.
  add_box(s, 0, 70, 0, 80, 80, 20);
  for (int i = 0; i < houses; ++i) {
    const double x0 = i * w, x1 = x0 + w;
    const double wall = 18 + 4 * (i % 3);
    const double front = 8 + 6 * (i % 2);  // houses stand at two depths
    add_prism(s, {{x0, 0}, {x1, 0}, {x1, wall}, {x0 + w / 2, std::min(40.0, wall + w * 0.45)}, {x0, wall}}, front, 70);
    // An arcade: two piers and a lintel in front of the house, open below.
    add_box(s, x0 + 1, front - 6, 0, x0 + 3, front, wall * 0.5);
    add_box(s, x1 - 3, front - 6, 0, x1 - 1, front, wall * 0.5);
    add_box(s, x0 + 1, front - 6, wall * 0.5, x1 - 1, front, wall * 0.5 + 4);
    // A balcony sticking out higher up, with nothing under it.
    add_box(s, x0 + w * 0.3, front - 5, wall * 0.75, x0 + w * 0.7, front, wall * 0.75 + 4);
  }
  // A round tower on the left, 16 facets standing on the ground: slanted walls seen from the front.
  const double cx = 10, cy = 30, r = 6;
  const auto bottom = add_point(s, cx, cy, 0), top = add_point(s, cx, cy, 38);
  for (int k = 0; k < 16; ++k) {
    const double a0 = M_PI / 8 * k, a1 = M_PI / 8 * (k + 1);
    const auto p0 = add_point(s, cx + r * std::cos(a0), cy + r * std::sin(a0), 0);
    const auto p1 = add_point(s, cx + r * std::cos(a1), cy + r * std::sin(a1), 0);
    const auto q0 = add_point(s, cx + r * std::cos(a0), cy + r * std::sin(a0), 38);
    const auto q1 = add_point(s, cx + r * std::cos(a1), cy + r * std::sin(a1), 38);
    s.triangles.push_back({p0, q0, q1});
    s.triangles.push_back({p0, q1, p1});
    s.triangles.push_back({bottom, p1, p0});
    s.triangles.push_back({top, q0, q1});
  }
  s.polygons += 16 * 3;
  add_box(s, 0, 0, 0, 0.01, 80, 0.01);  // pins the bounding box to 80 × 80 × 40
  add_box(s, 79.99, 79.99, 39.99, 80, 80, 40);
  return s;
}

TriangleSoup city_mesh(int n, unsigned seed) {
  TriangleSoup s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> height(4, 40), inset(0, 1.5);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double a = inset(rng), b = inset(rng);
      add_box(s, i * 10 + a, j * 10 + b, 0, i * 10 + 10 - b, j * 10 + 10 - a, height(rng));
    }
  }
  return s;
}

std::string to_obj(const TriangleSoup& s) {
  std::ostringstream o;
  o.precision(17);
  o << "# popcut test mesh\n";
  for (const auto& p : s.points) o << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& t : s.triangles) o << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  return o.str();
}

std::string to_off(const TriangleSoup& s) {
  std::ostringstream o;
  o.precision(17);
  o << "OFF\n" << s.points.size() << ' ' << s.triangles.size() << " 0\n";
  for (const auto& p : s.points) o << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& t : s.triangles) o << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  return o.str();
}

std::string to_ply(const TriangleSoup& s) {
  std::ostringstream o;
  o.precision(17);
  o << "ply\nformat ascii 1.0\nelement vertex " << s.points.size()
    << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << s.triangles.size()
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : s.points) o << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& t : s.triangles) o << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  return o.str();
}

std::string to_stl_ascii(const TriangleSoup& s) {
  std::ostringstream o;
  o.precision(17);
  o << "solid popcut\n";
  for (const auto& t : s.triangles) {
    o << "facet normal 0 0 0\nouter loop\n";
    for (std::uint32_t i : t)
      o << "vertex " << s.points[i][0] << ' ' << s.points[i][1] << ' ' << s.points[i][2] << '\n';
    o << "endloop\nendfacet\n";
  }
  o << "endsolid popcut\n";
  return o.str();
}

std::string to_stl_binary(const TriangleSoup& s) {
  std::string out(80, '\0');
  std::memcpy(out.data(), "popcut binary STL", 17);  // must not start with "solid"
  const auto put = [&](const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); };
  const auto count = static_cast<std::uint32_t>(s.triangles.size());
  put(&count, 4);
  for (const auto& t : s.triangles) {
    const float normal[3] = {0, 0, 0};
    put(normal, sizeof normal);
    for (std::uint32_t i : t) {
      const float v[3] = {static_cast<float>(s.points[i][0]), static_cast<float>(s.points[i][1]),
                          static_cast<float>(s.points[i][2])};
      put(v, sizeof v);
    }
    const std::uint16_t attributes = 0;
    put(&attributes, 2);
  }
  return out;
}

// The folder of this process's temporary files, removed when the process ends.
struct TempDir {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("popcut-test-" + std::to_string(::getpid()));
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

std::string write_temp(const std::string& name, const std::string& text) {
  static const TempDir dir;
  const auto path = dir.path / name;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

}  // namespace popcut::testing
