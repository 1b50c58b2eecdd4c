// FOLD (.fold JSON) crease patterns as drawings: vertices, edges, assignments and fold angles.
#include <cmath>
#include <map>

#include "io/json_util.h"
#include "popcut/error.h"
#include "popcut/io/drawing_io.h"

namespace popcut {
namespace {

using json_util::json;

bool has_class(const json& frame, const char* name) {
  const auto it = frame.find("frame_classes");
  if (it == frame.end() || !it->is_array()) return false;
  for (const json& c : *it)
    if (c.is_string() && c.get<std::string>() == name) return true;
  return false;
}

// The frame holding the crease pattern: the file itself, else the first of file_frames that
// has coordinates and is no folded form (frames may inherit nothing here: each must be whole).
const json& crease_frame(const json& root, const json_util::Reader& in, std::string& path) {
  const auto usable = [](const json& f) {
    return f.is_object() && f.contains("vertices_coords") && !has_class(f, "foldedForm");
  };
  if (usable(root)) return root;
  if (const auto it = root.find("file_frames"); it != root.end() && it->is_array()) {
    for (std::size_t i = 0; i < it->size(); ++i) {
      if (usable((*it)[i])) {
        path = json_util::index_path("file_frames", i) + ".";
        return (*it)[i];
      }
    }
  }
  if (root.contains("vertices_coords"))
    in.fail("frame_classes", "the file is a folded form, not a crease pattern: popcut reads the flat sheet");
  in.fail("vertices_coords", "is missing: no frame of the file holds a crease pattern");
}

double unit_mm(const json& frame, const json_util::Reader& in, const std::string& path, double unitless_mm) {
  const auto it = frame.find("frame_unit");
  if (it == frame.end()) return unitless_mm;
  static const std::map<std::string, double> units = {{"unit", 0}, {"in", 25.4}, {"pt", 25.4 / 72}, {"m", 1000},
                                                      {"cm", 10},  {"mm", 1},    {"um", 1e-3},      {"nm", 1e-6}};
  const std::string u = in.string(*it, path + "frame_unit");
  const auto found = units.find(u);
  if (found == units.end())
    in.fail(path + "frame_unit", "expected unit, in, pt, m, cm, mm, um or nm, got \"" + u + "\"");
  return found->second == 0 ? unitless_mm : found->second;
}

DrawnKind kind_of_assignment(const std::string& a, const json_util::Reader& in, const std::string& field) {
  static const std::map<std::string, DrawnKind> kinds = {
      {"B", DrawnKind::outline}, {"M", DrawnKind::mountain}, {"V", DrawnKind::valley}, {"F", DrawnKind::flat},
      {"U", DrawnKind::fold},    {"C", DrawnKind::cut},      {"J", DrawnKind::flat}};
  const auto it = kinds.find(a);
  if (it == kinds.end()) in.fail(field, "expected B, M, V, F, U, C or J, got \"" + a + "\"");
  return it->second;
}

std::vector<Point2> read_vertices(const json& frame, const json_util::Reader& in, const std::string& path, double mm) {
  const json& coords = frame.at("vertices_coords");
  in.require_array(coords, path + "vertices_coords");
  if (coords.size() > kMaxDrawingSegments)
    throw Error(ErrorCode::limit, in.source(), path + "vertices_coords",
                "more than " + std::to_string(kMaxDrawingSegments) + " vertices, the documented limit");
  std::vector<Point2> out;
  const double limit = kMaxDrawingCoordinateMm / mm;
  for (std::size_t i = 0; i < coords.size(); ++i) {
    const std::string field = json_util::index_path(path + "vertices_coords", i);
    in.require_array(coords[i], field);
    if (coords[i].size() != 2 && coords[i].size() != 3) in.fail(field, "expected [x, y] or [x, y, 0]");
    const double x = in.number(coords[i][0], field + "[0]", -limit, limit);
    const double y = in.number(coords[i][1], field + "[1]", -limit, limit);
    if (coords[i].size() == 3 && in.number(coords[i][2], field + "[2]", -limit, limit) != 0)
      in.fail(field + "[2]", "the sheet must lie flat (z = 0): this frame is folded, not a crease pattern");
    out.push_back({x * mm, y * mm});
  }
  return out;
}

}  // namespace

LineDrawing read_fold_drawing(const std::string& text, const std::string& source, const DrawingOptions& options) {
  const json root = json_util::parse(text, source);
  const json_util::Reader in(source);
  in.require_object(root, "document");
  std::string path;
  const json& frame = crease_frame(root, in, path);
  const double mm = unit_mm(frame, in, path, options.unit_mm);
  LineDrawing out;
  out.source = source;
  const std::vector<Point2> vertices = read_vertices(frame, in, path, mm);
  const json& edges = in.require(frame, "edges_vertices", path.empty() ? "" : path.substr(0, path.size() - 1));
  in.require_array(edges, path + "edges_vertices");
  // An absent per-edge array reads as one of nulls, so every edge looks the same.
  const auto optional_array = [&](const char* key) {
    const auto it = frame.find(key);
    if (it == frame.end()) return json(std::vector<json>(edges.size()));
    in.require_array(*it, path + key);
    if (it->size() != edges.size())
      in.fail(path + key,
              "has " + std::to_string(it->size()) + " entries for " + std::to_string(edges.size()) + " edges");
    return *it;
  };
  const json assignment = optional_array("edges_assignment");
  const json angle = optional_array("edges_foldAngle");
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::string field = json_util::index_path(path + "edges_vertices", i);
    in.require_array(edges[i], field);
    if (edges[i].size() != 2) in.fail(field, "expected two vertex indices");
    const int last = static_cast<int>(vertices.size()) - 1;
    const auto a = static_cast<std::size_t>(in.integer(edges[i][0], field + "[0]", 0, last));
    const auto b = static_cast<std::size_t>(in.integer(edges[i][1], field + "[1]", 0, last));
    DrawnLine line;
    line.where = "edges[" + std::to_string(i) + "]";
    line.points = {vertices[a], vertices[b]};
    if (line.points[0] == line.points[1]) in.fail(field, "a zero-length edge: both ends lie at the same point");
    line.kind = DrawnKind::fold;
    line.why = "no edges_assignment";
    if (!assignment[i].is_null()) {
      const std::string af = json_util::index_path(path + "edges_assignment", i);
      const std::string a_text = in.string(assignment[i], af);
      line.kind = kind_of_assignment(a_text, in, af);
      line.why = "edges_assignment \"" + a_text + "\"";
    }
    if (!angle[i].is_null()) {
      line.fold_angle_deg = in.number(angle[i], json_util::index_path(path + "edges_foldAngle", i), -180, 180);
      if (line.kind == DrawnKind::fold && *line.fold_angle_deg != 0)
        line.kind = *line.fold_angle_deg > 0 ? DrawnKind::valley : DrawnKind::mountain;
    }
    out.lines.push_back(std::move(line));
  }
  if (!frame.contains("frame_unit") || frame.at("frame_unit") == "unit")
    out.notes.push_back("the file states no length unit: one unit read as " + json_util::number_text(mm) + " mm");
  return out;
}

}  // namespace popcut
