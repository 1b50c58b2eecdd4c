// FOLD writer: the pattern as a crease pattern (planar graph, assignments, fold angles) for Origami Simulator and
// friends.
#include <map>
#include <ostream>
#include <sstream>

#include "io/json_util.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/pattern_io.h"
#include "popcut/pattern/sheet_map.h"

namespace popcut {
namespace {

// The pattern as a drawing in sheet coordinates (origin at the sheet's lower left), so its
// planar map splits every line where another meets or crosses it, as FOLD's edges must be.
LineDrawing as_drawing(const Pattern& p) {
  LineDrawing d;
  d.source = "pattern";
  const Point2 o = p.sheet.min;
  const auto at = [&](Point2 q) { return Point2{q.x_mm - o.x_mm, q.v_mm - o.v_mm}; };
  const Point2 w{p.sheet.max.x_mm - o.x_mm, p.sheet.max.v_mm - o.v_mm};
  d.lines.push_back({DrawnKind::outline, {{0, 0}, {w.x_mm, 0}, w, {0, w.v_mm}}, true, "sheet", "", {}});
  for (const Segment& s : p.lines) {
    const DrawnKind k = s.kind == LineKind::cut        ? DrawnKind::cut
                        : s.kind == LineKind::mountain ? DrawnKind::mountain
                                                       : DrawnKind::valley;
    d.lines.push_back({k, {at(s.a), at(s.b)}, false, "line", "", {}});
  }
  return d;
}

}  // namespace

// Fold angles are the card's at 90° open: valleys +90°, mountains −90° (FOLD's sign convention).
void write_pattern_fold(std::ostream& o, const Pattern& p) {
  const SheetMap map = build_sheet_map(as_drawing(p), {.snap_tolerance_mm = 0});
  std::map<std::pair<double, double>, std::size_t> index;
  std::vector<Point2> vertices;
  const auto vertex = [&](Point2 q) {
    const auto [it, fresh] = index.emplace(std::pair{q.x_mm, q.v_mm}, vertices.size());
    if (fresh) vertices.push_back(q);
    return it->second;
  };
  std::ostringstream edges, assignment, angle;
  bool first = true;
  for (const SheetEdge& e : map.edges) {
    const std::size_t a = vertex(e.a), b = vertex(e.b);
    const char* kind = e.kind == DrawnKind::outline    ? "B"
                       : e.kind == DrawnKind::cut      ? "C"
                       : e.kind == DrawnKind::mountain ? "M"
                                                       : "V";
    const int deg = e.kind == DrawnKind::mountain ? -90 : e.kind == DrawnKind::valley ? 90 : 0;
    edges << (first ? "" : ", ") << "[" << a << ", " << b << "]";
    assignment << (first ? "\"" : ", \"") << kind << "\"";
    angle << (first ? "" : ", ") << deg;
    first = false;
  }
  o << "{\n  \"file_spec\": 1.1,\n  \"file_creator\": \"popcut\",\n  \"file_classes\": [\"singleModel\"],\n"
    << "  \"frame_classes\": [\"creasePattern\"],\n  \"frame_unit\": \"mm\",\n  \"vertices_coords\": [";
  for (std::size_t i = 0; i < vertices.size(); ++i)
    o << (i ? ", " : "") << "[" << json_util::number_text(vertices[i].x_mm) << ", "
      << json_util::number_text(vertices[i].v_mm) << "]";
  o << "],\n  \"edges_vertices\": [" << edges.str() << "],\n  \"edges_assignment\": [" << assignment.str()
    << "],\n  \"edges_foldAngle\": [" << angle.str() << "]\n}\n";
}

}  // namespace popcut
