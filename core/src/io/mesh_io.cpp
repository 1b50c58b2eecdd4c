// OBJ/MTL and glTF 2.0 writers for the folded card.
#include "popcut/io/mesh_io.h"

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <ostream>
#include <vector>

#include "io/json_util.h"
#include "popcut/io/base64.h"

namespace popcut {
namespace {

using json_util::number_text;

struct Vec {
  double x, y, z;
};
Vec sub(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Vec unit(Vec a) {
  const double n = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
  return n > 0 ? Vec{a.x / n, a.y / n, a.z / n} : Vec{0, 0, 1};
}
// Card (x, y, z) to the right-handed Y-up frame, scaled.
Vec frame(const Point3& p, double scale) { return {p.x_mm * scale, p.z_mm * scale, p.y_mm * scale}; }

Vec normal_of(const CardMesh& m, const std::array<std::uint32_t, 3>& t, double scale) {
  const Vec a = frame(m.vertices[t[0]], scale), b = frame(m.vertices[t[1]], scale), c = frame(m.vertices[t[2]], scale);
  return unit(cross(sub(b, a), sub(c, a)));
}

struct Rgb {
  double r, g, b;
};
constexpr Rgb kFront{0.96, 0.93, 0.84};  // cream card stock
constexpr Rgb kBack{0.55, 0.62, 0.72};   // the back, clearly another colour

std::string rgb_text(Rgb c) { return number_text(c.r) + " " + number_text(c.g) + " " + number_text(c.b); }

void put_float(std::vector<unsigned char>& buf, double v) {
  const float f = static_cast<float>(v);
  unsigned char b[4];
  std::memcpy(b, &f, 4);  // glTF buffers are little-endian, as is every platform popcut builds on
  buf.insert(buf.end(), b, b + 4);
}

}  // namespace

void write_mtl(std::ostream& out) {
  out << "# popcut card materials: the printed side and the back of the sheet\n"
      << "newmtl front\nKd " << rgb_text(kFront) << "\nKa 0.2 0.2 0.2\nillum 1\n\n"
      << "newmtl back\nKd " << rgb_text(kBack) << "\nKa 0.2 0.2 0.2\nillum 1\n";
}

void write_obj(std::ostream& out, const CardMesh& m, const std::string& mtl_file) {
  out << "# popcut folded card: Y up, millimetres; " << m.triangles.size() << " triangles per side\n"
      << "mtllib " << mtl_file << "\n";
  for (const Point3& p : m.vertices) {
    const Vec v = frame(p, 1.0);
    out << "v " << number_text(v.x) << " " << number_text(v.y) << " " << number_text(v.z) << "\n";
  }
  // Normals 1..T face the printed side, T+1..2T the back.
  for (int side = 0; side < 2; ++side) {
    for (const auto& t : m.triangles) {
      const Vec n = normal_of(m, t, 1.0);
      const double k = side == 0 ? 1.0 : -1.0;
      out << "vn " << number_text(k * n.x) << " " << number_text(k * n.y) << " " << number_text(k * n.z) << "\n";
    }
  }
  const std::size_t count = m.triangles.size();
  for (int side = 0; side < 2; ++side) {
    out << "usemtl " << (side == 0 ? "front" : "back") << "\n";
    for (std::size_t i = 0; i < count; ++i) {
      const auto& t = m.triangles[i];
      const std::size_t n = i + 1 + (side == 0 ? 0 : count);
      const std::uint32_t b = side == 0 ? t[1] : t[2], c = side == 0 ? t[2] : t[1];
      out << "f " << t[0] + 1 << "//" << n << " " << b + 1 << "//" << n << " " << c + 1 << "//" << n << "\n";
    }
  }
}

void write_gltf(std::ostream& out, const CardMesh& m) {
  using nlohmann::json;
  const double scale = 0.001;  // glTF is in metres
  std::vector<unsigned char> buf;
  json accessors = json::array(), views = json::array(), primitives = json::array();
  for (int side = 0; side < 2; ++side) {
    const std::size_t pos_offset = buf.size();
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (const auto& t : m.triangles) {
      const std::array<std::uint32_t, 3> order = side == 0 ? t : std::array<std::uint32_t, 3>{t[0], t[2], t[1]};
      for (std::uint32_t i : order) {
        const Vec v = frame(m.vertices[i], scale);
        const double c[3] = {v.x, v.y, v.z};
        for (int k = 0; k < 3; ++k) {
          // Bounds from the float values written, as validators compare them exactly.
          const double f = static_cast<float>(c[k]);
          lo[k] = std::min(lo[k], f);
          hi[k] = std::max(hi[k], f);
          put_float(buf, c[k]);
        }
      }
    }
    const std::size_t count = m.triangles.size() * 3;
    const std::size_t norm_offset = buf.size();
    for (const auto& t : m.triangles) {
      Vec n = normal_of(m, t, scale);
      if (side == 1) n = {-n.x, -n.y, -n.z};
      for (int k = 0; k < 3; ++k) {
        put_float(buf, n.x);
        put_float(buf, n.y);
        put_float(buf, n.z);
      }
    }
    const auto view = [&](std::size_t offset) {
      views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", count * 12}, {"target", 34962}});
      return views.size() - 1;
    };
    json pos = {{"bufferView", view(pos_offset)}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}};
    if (count > 0) {
      pos["min"] = {lo[0], lo[1], lo[2]};
      pos["max"] = {hi[0], hi[1], hi[2]};
    }
    accessors.push_back(pos);
    accessors.push_back(
        {{"bufferView", view(norm_offset)}, {"componentType", 5126}, {"count", count}, {"type", "VEC3"}});
    primitives.push_back({{"attributes", {{"POSITION", accessors.size() - 2}, {"NORMAL", accessors.size() - 1}}},
                          {"material", side},
                          {"mode", 4}});
  }
  const auto rgba = [](Rgb c) { return json::array({c.r, c.g, c.b, 1.0}); };
  const json doc = {{"asset", {{"version", "2.0"}, {"generator", "popcut"}}},
                    {"scene", 0},
                    {"scenes", {{{"nodes", {0}}}}},
                    {"nodes", {{{"mesh", 0}, {"name", "card"}}}},
                    {"meshes", {{{"name", "card"}, {"primitives", primitives}}}},
                    {"materials",
                     {{{"name", "front"},
                       {"pbrMetallicRoughness",
                        {{"baseColorFactor", rgba(kFront)}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.9}}}},
                      {{"name", "back"},
                       {"pbrMetallicRoughness",
                        {{"baseColorFactor", rgba(kBack)}, {"metallicFactor", 0.0}, {"roughnessFactor", 0.9}}}}}},
                    {"accessors", accessors},
                    {"bufferViews", views},
                    {"buffers",
                     {{{"byteLength", buf.size()},
                       {"uri", "data:application/octet-stream;base64," +
                                   base64(std::string_view(reinterpret_cast<const char*>(buf.data()), buf.size()))}}}}};
  out << doc.dump(1) << "\n";
}

}  // namespace popcut
