// The CGAL side of mesh import: file readers (OBJ, STL, OFF, PLY) and ray casting on an AABB tree.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <optional>
#include <sstream>

#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/mesh/mesh_import.h"
#include "mesh/mesh_file_check.h"
#include "mesh/obj_faces.h"

namespace popcut {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

std::string extension_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool non_finite_token(const std::string& token) {
  std::string t = token;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!t.empty() && (t[0] == '-' || t[0] == '+')) t.erase(0, 1);
  return t.rfind("nan", 0) == 0 || t.rfind("inf", 0) == 0;
}

// CGAL's readers say only that they failed; for text files look for the usual reasons, so the
// error can name the line: a NaN or infinite number, and in OBJ an element other than faces
// (lines, points) or a face naming a vertex not yet defined.
std::optional<std::pair<int, std::string>> diagnose_text(const std::string& bytes, const std::string& ext) {
  std::istringstream in(bytes);
  std::string line;
  int number = 0;
  bool faces = false;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    std::string keyword, token;
    words >> keyword;
    if (ext == "obj" && !keyword.empty() && keyword[0] != '#') {
      if (keyword == "l") return std::make_pair(number, std::string("'l' (a polyline): only faces ('f') can be read"));
      if (keyword == "f") {  // its corners were checked before CGAL read the file (read_obj_faces)
        faces = true;
        continue;
      }
    }
    std::istringstream again(line);
    while (again >> token) {
      if (non_finite_token(token)) return std::make_pair(number, "'" + token + "' is not a finite number");
    }
  }
  if (ext == "obj" && !faces) return std::make_pair(number, std::string("the file has no faces ('f' lines)"));
  return std::nullopt;
}

// A token as it can be shown in a message: control bytes as \xNN.
std::string printable(const std::string& token) {
  std::string out;
  for (const char c : token) {
    const auto ch = static_cast<unsigned char>(c);
    if (ch >= 0x20 && ch < 0x7f) {
      out += static_cast<char>(ch);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", ch);
      out += hex;
    }
  }
  return out;
}

// CGAL's ASCII STL reader (which the binary one follows when it fails) says only that it
// failed; walk the same grammar — 'facet' … three 'vertex x y z' … 'endfacet', the solid closed
// by 'endsolid' — to name the line and what was expected there.
std::optional<std::pair<int, std::string>> diagnose_ascii_stl(const std::string& bytes) {
  if (bytes.compare(0, 5, "solid") != 0) return std::nullopt;
  std::istringstream in(bytes);
  std::string line;
  int number = 0, facet_line = 0, vertices = 0;
  bool in_solid = false, in_facet = false;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream words(line);
    for (std::string w; words >> w;) {
      if (!in_facet) {
        if (w == "solid") in_solid = true;
        if (w == "endsolid") in_solid = false;
        if (w == "facet") {
          in_facet = true;
          facet_line = number;
          vertices = 0;
        }
        continue;
      }
      if (w == "endfacet") {
        if (vertices != 3) {
          return std::make_pair(number, "the facet from line " + std::to_string(facet_line) + " has " +
                                            std::to_string(vertices) +
                                            " vertices: only triangles (3 'vertex x y z') can be read");
        }
        in_facet = false;
      } else if (w == "vertex") {
        ++vertices;
        for (int k = 0; k < 3; ++k) {
          std::string c;
          char* end = nullptr;
          if (words >> c) std::strtod(c.c_str(), &end);
          if (c.empty() || end != c.c_str() + c.size()) {
            return std::make_pair(
                number, c.empty()
                            ? "'vertex' has " + std::to_string(k) + " of its 3 numbers on its line: expected x y z"
                            : "'" + printable(c) + "' is not a number: expected 'vertex x y z'");
          }
        }
      }
    }
  }
  if (in_facet) {
    return std::make_pair(number, "the file ends inside the facet that begins on line " + std::to_string(facet_line) +
                                      ": expected 3 'vertex x y z' and 'endfacet' (truncated?)");
  }
  if (in_solid) return std::make_pair(number, std::string("the file ends before 'endsolid' (truncated?)"));
  return std::nullopt;
}

// Binary STL (80-byte header, count, 50 bytes a triangle): CGAL merges equal vertices through
// a map, where a NaN compares equal to anything and would silently vanish; catch it first.
void check_binary_stl(const std::string& path, const std::string& bytes) {
  if (bytes.size() < 84 || bytes.compare(0, 5, "solid") == 0) return;
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (84 + std::uint64_t{count} * 50 != bytes.size()) {
    throw Error(ErrorCode::invalid_input, path, "",
                "binary STL says " + std::to_string(count) + " triangles, which take " +
                    std::to_string(84 + std::uint64_t{count} * 50) + " bytes, but the file has " +
                    std::to_string(bytes.size()) + " (truncated?)");
  }
  for (std::uint32_t t = 0; t < count; ++t) {
    for (int k = 0; k < 9; ++k) {
      float v = 0;
      std::memcpy(&v, bytes.data() + 84 + std::size_t{t} * 50 + 12 + static_cast<std::size_t>(k) * 4, 4);
      if (!std::isfinite(v)) {
        throw Error(ErrorCode::invalid_input, path, "triangle " + std::to_string(t + 1),
                    "coordinate is not a finite number (NaN or infinite)");
      }
    }
  }
}

// CGAL's OFF and PLY readers reserve what the header declares before reading a record, so a
// 30-byte file declaring a billion vertices would take all the memory there is (Linux
// overcommits, so bad_alloc never comes). Every vertex takes at least 6 bytes ("0 0 0\n", or 12
// in binary) and every face at least 2 (a count and an index), so larger counts cannot be true.
void check_declared_counts(const std::string& path, const std::string& ext, const std::string& bytes) {
  std::istringstream in(bytes.substr(0, 64 * 1024));
  std::string line;
  unsigned long long vertices = 0, faces = 0;
  if (ext == "off") {
    std::vector<std::string> tokens;
    while (tokens.size() < 4 && std::getline(in, line)) {
      line = line.substr(0, line.find('#'));
      std::istringstream words(line);
      for (std::string w; words >> w;) tokens.push_back(w);
    }
    if (tokens.size() < 3 || tokens[0].find("OFF") == std::string::npos) return;  // CGAL reports it
    try {
      vertices = std::stoull(tokens[1]);
      faces = std::stoull(tokens[2]);
    } catch (const std::exception&) {
      return;
    }
  } else if (ext == "ply") {
    while (std::getline(in, line) && line.rfind("end_header", 0) != 0) {
      std::istringstream words(line);
      std::string keyword, name;
      unsigned long long count = 0;
      if (words >> keyword >> name >> count && keyword == "element") {
        if (name == "vertex") vertices = count;
        if (name == "face") faces = count;
      }
    }
  } else {
    return;
  }
  const unsigned long long size = bytes.size();
  if (vertices > size / 6 || faces > size / 2 || vertices * 6 + faces * 2 > size) {
    throw Error(ErrorCode::invalid_input, path, "header",
                "declares " + std::to_string(vertices) + " vertices and " + std::to_string(faces) +
                    " faces, more than a file of " + std::to_string(size) +
                    " bytes can hold: the file is truncated or corrupt");
  }
}

// Runs one of CGAL's readers on the file's bytes. They report failure as `false` without a
// reason (and may throw on absurd counts), so the error says which format did not parse.
template <typename Points, typename Polygons>
void parse(const std::string& path, const std::string& ext, const std::string& bytes, Points& points,
           Polygons& polygons) {
  std::istringstream in(bytes, std::ios::in | std::ios::binary);
  bool ok = false;
  try {
    if (ext == "obj") {
      ok = CGAL::IO::read_OBJ(in, points, polygons, CGAL::parameters::verbose(false));
    } else if (ext == "off") {
      ok = CGAL::IO::read_OFF(in, points, polygons, CGAL::parameters::verbose(false));
    } else if (ext == "ply") {
      ok = CGAL::IO::read_PLY(in, points, polygons, CGAL::parameters::verbose(false));
    } else {
      ok = CGAL::IO::read_STL(in, points, polygons, CGAL::parameters::verbose(false));
    }
  } catch (const std::bad_alloc&) {
    throw Error(ErrorCode::limit, path, "",
                "the file's counts need more memory than there is; is it truncated or corrupt?");
  } catch (const std::exception& e) {
    throw Error(ErrorCode::invalid_input, path, "", "not a readable " + ext + " file: " + e.what());
  }
  if (!ok && ext != "ply") {
    if (auto why = ext == "stl" ? diagnose_ascii_stl(bytes) : diagnose_text(bytes, ext)) {
      throw Error(ErrorCode::invalid_input, path, "line " + std::to_string(why->first), why->second);
    }
  }
  if (!ok) {
    std::string upper = ext;
    std::transform(upper.begin(), upper.end(), upper.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    throw Error(
        ErrorCode::invalid_input, path, "",
        "not a readable " + upper + " file (malformed or truncated; CGAL's reader stopped" +
            (points.empty() ? " before the first vertex)" : " after " + std::to_string(points.size()) + " vertices)"));
  }
}

}  // namespace

TriangleSoup read_mesh(const std::string& path) {
  const std::string ext = extension_of(path);
  if (ext != "obj" && ext != "stl" && ext != "off" && ext != "ply") {
    throw Error(ErrorCode::invalid_input, path, "",
                (ext.empty() ? std::string("no file extension") : "unknown mesh format '." + ext + "'") +
                    ": the format is taken from the name: .obj, .stl, .off or .ply");
  }
  const std::string bytes = read_text_file(path, kMaxMeshFileBytes);
  if (bytes.find_first_not_of(" \t\r\n") == std::string::npos)
    throw Error(ErrorCode::invalid_input, path, "", "the file is empty");

  if (ext == "stl") check_binary_stl(path, bytes);
  check_declared_counts(path, ext, bytes);
  check_mesh_list_counts(path, ext, bytes);
  // OBJ corners are read here, not by CGAL, whose reader ends a face silently at the first
  // corner it cannot read as an int (see obj_faces.cpp); CGAL still reads the vertices.
  std::vector<std::vector<std::size_t>> obj_faces;
  if (ext == "obj") obj_faces = read_obj_faces(path, bytes);
  std::vector<K::Point_3> points;
  std::vector<std::vector<std::size_t>> polygons;
  parse(path, ext, bytes, points, polygons);
  if (ext == "obj") polygons = std::move(obj_faces);

  TriangleSoup soup;
  soup.points.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const K::Point_3& p = points[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) {
      throw Error(ErrorCode::invalid_input, path, "vertex " + std::to_string(i + 1),
                  "coordinate is not a finite number (NaN or infinite)");
    }
    soup.points.push_back({p.x(), p.y(), p.z()});
  }
  soup.polygons = static_cast<std::int64_t>(polygons.size());
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const std::vector<std::size_t>& poly = polygons[f];
    for (std::size_t v : poly) {
      if (v >= points.size()) {
        throw Error(ErrorCode::invalid_input, path, "face " + std::to_string(f + 1),
                    "refers to a vertex that does not exist (the file has " + std::to_string(points.size()) + ")");
      }
    }
    if (poly.size() < 3) {
      ++soup.degenerate;
      continue;
    }
    // A fan: exact for convex polygons, which is what exporters write; the depth of a
    // non-convex polygon's fan may cover a notch (documented best effort).
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
      const auto& a = soup.points[poly[0]];
      const auto& b = soup.points[poly[k]];
      const auto& c = soup.points[poly[k + 1]];
      const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
      const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
      const double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      if (nx == 0 && ny == 0 && nz == 0) {
        ++soup.degenerate;
        continue;
      }
      soup.triangles.push_back({static_cast<std::uint32_t>(poly[0]), static_cast<std::uint32_t>(poly[k]),
                                static_cast<std::uint32_t>(poly[k + 1])});
      if (static_cast<std::int64_t>(soup.triangles.size()) > kMaxMeshTriangles) {
        throw Error(ErrorCode::limit, path, "", "more than " + std::to_string(kMaxMeshTriangles) + " triangles");
      }
    }
  }
  if (soup.triangles.empty()) {
    throw Error(ErrorCode::invalid_input, path, "",
                polygons.empty() ? "the mesh has no faces" : "every face has zero area: nothing to see from the front");
  }
  return soup;
}

// One orthographic ray per cell centre, from in front of the mesh towards the back wall; the
// first hit is the surface seen. Kept for comparison with the z-buffer (bench/import_bench).
DepthMap sample_depth_raycast(const TriangleSoup& mesh, const ImportGrid& grid) {
  using Triangle = K::Triangle_3;
  using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
  std::vector<Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  double y_max = -std::numeric_limits<double>::infinity();
  for (const auto& t : mesh.triangles) {
    const auto p = [&](int i) {
      const auto& q = mesh.points[t[static_cast<std::size_t>(i)]];
      return K::Point_3(q[0], q[1], q[2]);
    };
    triangles.emplace_back(p(0), p(1), p(2));
    for (int i = 0; i < 3; ++i) y_max = std::max(y_max, mesh.points[t[static_cast<std::size_t>(i)]][1]);
  }
  DepthMap map;
  map.width = grid.width;
  map.height = grid.height;
  map.front.assign(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height),
                   -std::numeric_limits<double>::infinity());
  if (triangles.empty()) return map;
  Tree tree(triangles.begin(), triangles.end());
  const double start_y = y_max + 1 + std::abs(y_max);
  for (int x = 0; x < grid.width; ++x) {
    for (int z = 0; z < grid.height; ++z) {
      const double cx = grid.x0 + (x + 0.5) * grid.step;
      const double cz = grid.z0 + (z + 0.5) * grid.step;
      const K::Ray_3 ray(K::Point_3(cx, start_y, cz), K::Direction_3(0, -1, 0));
      const auto hit = tree.first_intersection(ray);
      if (!hit) continue;
      double y = -std::numeric_limits<double>::infinity();
      if (const K::Point_3* p = boost::get<K::Point_3>(&hit->first)) {
        y = p->y();
      } else if (const K::Segment_3* s = boost::get<K::Segment_3>(&hit->first)) {
        y = std::max(s->source().y(), s->target().y());
      }
      map.front[static_cast<std::size_t>(x) * static_cast<std::size_t>(grid.height) + static_cast<std::size_t>(z)] = y;
    }
  }
  return map;
}

}  // namespace popcut
