// Patterns drawn elsewhere (SVG, DXF, FOLD): typed polylines in millimetres, each naming where it was drawn.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "popcut/geometry.h"
#include "popcut/names.h"

namespace popcut {

// What a drawn line asks of the sheet. `fold` is a crease whose direction the import works out
// (a score, FOLD's "U"); `flat` is a crease left unfolded (FOLD's "F"); `outline` is the sheet's
// edge; `unknown` is a line no convention classifies (listed, never guessed).
enum class DrawnKind { cut, mountain, valley, fold, flat, outline, unknown };
inline constexpr auto kDrawnKindNames = enum_names<DrawnKind>({{DrawnKind::cut, "cut"},
                                                               {DrawnKind::mountain, "mountain"},
                                                               {DrawnKind::valley, "valley"},
                                                               {DrawnKind::fold, "fold"},
                                                               {DrawnKind::flat, "flat"},
                                                               {DrawnKind::outline, "outline"},
                                                               {DrawnKind::unknown, "unknown"}});
const char* to_string(DrawnKind kind);

// A polyline in sheet coordinates (mm, x right, v up as in the pattern). `where` names the
// element it came from, e.g. `<path id="p12"> (line 40)` or `edges[7]`, for every report.
struct DrawnLine {
  DrawnKind kind = DrawnKind::cut;
  std::vector<Point2> points;
  bool closed = false;
  std::string where;
  std::string why;                       // how the kind was decided, e.g. `layer "Valley"`, or why it was not
  std::optional<double> fold_angle_deg;  // FOLD's edges_foldAngle: + valley, − mountain, 180 flat-folded
};

struct LineDrawing {
  std::string source;
  std::vector<DrawnLine> lines;
  std::optional<Rect> page;        // the SVG page (viewBox in mm), where the file has one
  std::vector<std::string> notes;  // what the reader did that a user should know (flattening, units)
};

// Documented limits: segments in one drawing, coordinates (100 m), nesting of groups.
inline constexpr std::size_t kMaxDrawingSegments = 2'000'000;
inline constexpr double kMaxDrawingCoordinateMm = 1e5;

struct DrawingOptions {
  double chord_tolerance_mm = 0.05;  // curves become chords no farther than this from the curve
  // Extra layer/group names (matched case-insensitively) and the kind each means, before the
  // built-in names (cut, mountain, valley, score, crease, fold, outline, ... and translations).
  std::vector<std::pair<std::string, DrawnKind>> layer_names;
  bool red_is_cut = false;  // the laser-cutter convention: red cut; else red is mountain, black cut
  // What one unit measures in a drawing that does not say: a FOLD file without frame_unit (or
  // "unit"), a DXF file without $INSUNITS (or 0, unitless).
  double unit_mm = 1;
};

LineDrawing read_svg_drawing(const std::string& text, const std::string& source, const DrawingOptions& options = {});
LineDrawing read_fold_drawing(const std::string& text, const std::string& source, const DrawingOptions& options = {});
// ASCII DXF (R12 and later) through dxflib: LINE, LWPOLYLINE and POLYLINE with bulges, ARC,
// CIRCLE, ELLIPSE, SPLINE and INSERT of blocks, in the units of $INSUNITS.
LineDrawing read_dxf_drawing(const std::string& text, const std::string& source, const DrawingOptions& options = {});

// True for file names popcut reads as drawings (.svg, .dxf, .fold), case-insensitively.
bool is_drawing_path(const std::string& path);
// The drawing in `text`, read as its name's extension says (.svg, .dxf, .fold); throws
// popcut::Error naming `source`.
LineDrawing read_drawing(const std::string& text, const std::string& source, const DrawingOptions& options = {});
// Reads the file and dispatches by its extension; throws popcut::Error naming the file.
LineDrawing load_drawing(const std::string& path, const DrawingOptions& options = {});

// The straight segments of the drawing's lines (a closed line's closing segment counted), the
// measure of its size that limits and benchmarks use.
std::size_t segment_count(const LineDrawing& drawing);

// The kind a layer or group name means under the built-in names and `options.layer_names`.
std::optional<DrawnKind> kind_of_layer_name(const std::string& name, const DrawingOptions& options);

}  // namespace popcut
