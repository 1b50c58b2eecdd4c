// DXF dielines: inserts expanded, curves flattened at the sheet's tolerance, each line typed by layer, linetype or
// colour.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "io/ascii_case.h"
#include "io/dxf_collect.h"
#include "io/dxf_curves.h"
#include "io/svg_path.h"
#include "popcut/error.h"
#include "popcut/io/drawing_io.h"
#include "popcut/text.h"

namespace popcut {
namespace {

using dxf::Shape;
using dxf::Style;
using svg::Affine;
constexpr int kMaxInsertDepth = 16;
constexpr std::size_t kMaxVisits = 4'000'000;

// $INSUNITS in millimetres; 0 or absent: the drawing states no unit.
std::optional<double> insunits_mm(int code, const std::string& source) {
  // Every unit of the DXF reference; the far ones (miles, light years) fail the ±100 m check.
  static const std::map<int, double> mm = {{1, 25.4},
                                           {2, 304.8},
                                           {3, 1609344},
                                           {4, 1},
                                           {5, 10},
                                           {6, 1000},
                                           {7, 1e6},
                                           {8, 25.4e-6},
                                           {9, 0.0254},
                                           {10, 914.4},
                                           {11, 1e-7},
                                           {12, 1e-6},
                                           {13, 1e-3},
                                           {14, 100},
                                           {15, 1e4},
                                           {16, 1e5},
                                           {17, 1e12},
                                           {18, 1.495978707e14},
                                           {19, 9.4607e18},
                                           {20, 3.0857e19},
                                           {21, 1200000.0 / 3937},
                                           {22, 100000.0 / 3937},
                                           {23, 3600000.0 / 3937},
                                           {24, 6336000000.0 / 3937}};
  if (code == 0) return std::nullopt;
  const auto it = mm.find(code);
  if (it == mm.end())
    throw Error(
        ErrorCode::invalid_input, source, "$INSUNITS",
        "unknown units " + std::to_string(code) + ": expected 0 (unitless) to 24, as the DXF reference lists them");
  return it->second;
}

// ACI colour names for reports.
std::string colour_name(int aci) {
  static const std::map<int, const char*> names = {{1, "red"},         {2, "yellow"}, {3, "green"},
                                                   {4, "cyan"},        {5, "blue"},   {6, "magenta"},
                                                   {7, "white/black"}, {8, "grey"},   {9, "light grey"}};
  const auto it = names.find(aci);
  return "colour " + std::to_string(aci) + (it == names.end() ? "" : std::string(" (") + it->second + ")");
}

bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

// Where a shape sits in the inserts above it: their resolved style (for layer 0 and BYBLOCK),
// the outermost insert's place, and the blocks on the way down (for cycles).
struct Context {
  Style style;
  std::string where;
  std::vector<std::string> blocks;
};

class Expander {
 public:
  Expander(const dxf::Collected& c, const std::string& source, const DrawingOptions& options, LineDrawing& out)
      : c_(c), source_(source), options_(options), out_(out) {}

  void run(const Affine& to_sheet) {
    for (const Shape& s : c_.model) emit(s, to_sheet, nullptr);
  }

  std::map<std::string, std::size_t> hidden;  // lines on layers switched off or frozen, by layer

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& message,
                         ErrorCode code = ErrorCode::invalid_input) const {
    throw Error(code, source_, where, message);
  }

  std::string where(const Shape& s, const Context* ctx) const {
    if (!ctx) return s.where;
    return s.where + " in block \"" + ctx->blocks.back() + "\" (" + ctx->where + ")";
  }

  // Layer 0 and BYBLOCK take the insert's; BYLAYER the layer's.
  Style resolve(const Style& s, const Context* ctx) const {
    Style r = s;
    if (ctx && r.layer == "0") r.layer = ctx->style.layer;
    const auto layer = c_.layers.find(ascii_upper(r.layer));  // DXF layer names ignore case
    const dxf::Layer l = layer == c_.layers.end() ? dxf::Layer{} : layer->second;
    if (r.colour == 0) r.colour = ctx ? ctx->style.colour : 7;
    if (r.colour == 256 || r.colour < 0) r.colour = l.colour;
    if (r.linetype == "BYBLOCK") r.linetype = ctx ? ctx->style.linetype : "CONTINUOUS";
    if (r.linetype == "BYLAYER" || r.linetype.empty()) r.linetype = l.linetype;
    return r;
  }

  bool hidden_layer(const std::string& layer) const {
    const auto it = c_.layers.find(ascii_upper(layer));
    return it != c_.layers.end() && it->second.hidden;
  }

  // Copies of empty or hidden blocks add no points; every entity and every copy counts, so
  // nested arrays end.
  void visit(const Shape& s, const Context* ctx) {
    if (++visits_ > kMaxVisits)
      fail(where(s, ctx),
           "the inserts expand to more than " + std::to_string(kMaxVisits) + " entities, the documented limit",
           ErrorCode::limit);
  }

  void emit(const Shape& s, const Affine& to_sheet, const Context* ctx) {
    visit(s, ctx);
    const Style style = resolve(s.style, ctx);
    if (hidden_layer(style.layer)) {
      ++hidden[style.layer];
      return;
    }
    if (s.type == Shape::Type::insert) return insert(s, style, to_sheet, ctx);
    const Affine local = s.mirrored && s.ocs ? Affine{-1, 0, 0, 1, 0, 0}.then(to_sheet) : to_sheet;
    const double tolerance = options_.chord_tolerance_mm / std::max(local.max_scale(), 1e-12);
    std::vector<Point2> points;
    try {
      points = flatten(s, tolerance);
    } catch (const std::length_error&) {
      fail(where(s, ctx), "a curve needs more than a million chords at the chord tolerance", ErrorCode::limit);
    } catch (const std::invalid_argument& x) {
      fail(where(s, ctx), x.what());
    }
    add(s, style, points, local, ctx);
  }

  std::vector<Point2> flatten(const Shape& s, double tolerance) const {
    std::vector<Point2> pts;
    if (s.type == Shape::Type::path) {
      for (std::size_t i = 0; i < s.vertices.size(); ++i) {
        if (i == 0) pts.push_back(s.vertices[0].p);
        const bool wrap = i + 1 == s.vertices.size();
        if (wrap && !s.closed) break;
        const dxf::Vertex& a = s.vertices[i];
        const dxf::Vertex& b = s.vertices[wrap ? 0 : i + 1];
        for (const Point2& p : dxf::bulge_points(a.p, b.p, a.bulge, tolerance)) pts.push_back(p);
      }
    } else if (s.type == Shape::Type::ellipse) {
      if (!(s.ratio > 0 && s.ratio <= 1) || !(std::hypot(s.major.x_mm, s.major.v_mm) > 0))
        throw std::invalid_argument("a circle, arc or ellipse of zero size, or an axis ratio outside (0, 1]");
      pts = dxf::ellipse_points(s.centre, s.major, s.ratio, s.t0, s.t1, s.mirrored && !s.ocs, tolerance);
    } else {
      if (s.control.empty() && s.fit_points)
        throw std::invalid_argument(
            "given by fit points only: popcut reads splines by their control points (convert it to control "
            "vertices in the CAD program)");
      pts = dxf::spline_points(s.degree, s.knots, s.control, s.weights, tolerance);
    }
    return pts;
  }

  void insert(const Shape& s, const Style& style, const Affine& to_sheet, const Context* ctx) {
    const auto block = c_.blocks.find(s.block);
    const std::string at = where(s, ctx);
    if (block == c_.blocks.end()) fail(at, "inserts block \"" + s.block + "\", which the file does not define");
    Context inner{style, ctx ? ctx->where : s.where, ctx ? ctx->blocks : std::vector<std::string>{}};
    if (std::find(inner.blocks.begin(), inner.blocks.end(), s.block) != inner.blocks.end()) {
      std::string chain;
      for (const std::string& b : inner.blocks) chain += b + " → ";
      fail(at, "block \"" + s.block + "\" inserts itself (" + chain + s.block + ")");
    }
    inner.blocks.push_back(s.block);
    if (inner.blocks.size() > static_cast<std::size_t>(kMaxInsertDepth))
      fail(at, "blocks nest more than " + std::to_string(kMaxInsertDepth) + " deep, the documented limit");
    if (s.columns < 1 || s.rows < 1) fail(at, "an insert array needs at least one column and one row");
    if (static_cast<double>(s.columns) * s.rows > static_cast<double>(kMaxDrawingSegments))
      fail(at, "an insert array of " + std::to_string(s.columns) + " × " + std::to_string(s.rows) + " copies",
           ErrorCode::limit);
    const double a = s.angle_deg * std::numbers::pi / 180, cs = std::cos(a), sn = std::sin(a);
    const Affine placed = Affine{1, 0, 0, 1, -block->second.base.x_mm, -block->second.base.v_mm}
                              .then({s.sx, 0, 0, s.sy, 0, 0})
                              .then({cs, sn, -sn, cs, 0, 0});
    const Affine outer = s.mirrored ? Affine{-1, 0, 0, 1, 0, 0}.then(to_sheet) : to_sheet;
    for (int r = 0; r < s.rows; ++r)
      for (int col = 0; col < s.columns; ++col) {
        visit(s, ctx);
        const double ox = col * s.column_mm, oy = r * s.row_mm;
        const Affine copy = placed.then({1, 0, 0, 1, s.at.x_mm + cs * ox - sn * oy, s.at.v_mm + sn * ox + cs * oy});
        for (const Shape& child : block->second.shapes) emit(child, copy.then(outer), &inner);
      }
  }

  void add(const Shape& s, const Style& style, const std::vector<Point2>& local, const Affine& to_sheet,
           const Context* ctx) {
    DrawnLine line;
    line.where = where(s, ctx);
    line.closed = s.closed;
    for (const Point2& p : local) {
      const Point2 q = to_sheet.apply(p);
      if (!std::isfinite(q.x_mm) || !std::isfinite(q.v_mm) || std::abs(q.x_mm) > kMaxDrawingCoordinateMm ||
          std::abs(q.v_mm) > kMaxDrawingCoordinateMm)
        fail(line.where, "a point lies at (" + format_decimal(q.x_mm, 3) + ", " + format_decimal(q.v_mm, 3) +
                             ") mm, beyond the documented ±100 m");
      if (line.points.empty() || !(line.points.back() == q)) line.points.push_back(q);
    }
    if (line.closed && line.points.size() > 2 &&
        std::hypot(line.points.front().x_mm - line.points.back().x_mm,
                   line.points.front().v_mm - line.points.back().v_mm) < 1e-9)
      line.points.pop_back();
    if (line.points.size() < 2) fail(line.where, "a zero-length line: every point of it is the same");
    if ((points_ += line.points.size()) > kMaxDrawingSegments)
      fail(line.where,
           "the drawing has more than " + std::to_string(kMaxDrawingSegments) + " segments, the documented limit",
           ErrorCode::limit);
    line.kind = classify(style, line.why);
    out_.lines.push_back(std::move(line));
  }

  // The layer's name first, then its linetype (dashed valley, dash-dot mountain, as in SVG),
  // then its colour (white/black or green cut, red mountain or cut, blue valley).
  DrawnKind classify(const Style& s, std::string& why) const {
    const std::string on = " on layer \"" + s.layer + "\"";
    if (const auto kind = kind_of_layer_name(s.layer, options_)) {
      why = "layer \"" + s.layer + "\"";
      return *kind;
    }
    const std::string& lt = s.linetype;  // upper case since collect
    if (contains(lt, "DASHDOT") || contains(lt, "CENTER") || contains(lt, "PHANTOM") || contains(lt, "DIVIDE")) {
      why = "linetype \"" + s.linetype + "\"" + on;
      return DrawnKind::mountain;
    }
    if (contains(lt, "DASH") || contains(lt, "HIDDEN") || contains(lt, "DOT")) {
      why = "linetype \"" + s.linetype + "\"" + on;
      return DrawnKind::valley;
    }
    why = colour_name(s.colour) + on;
    if (s.colour == 7 || s.colour == 3) return DrawnKind::cut;
    if (s.colour == 1) return options_.red_is_cut ? DrawnKind::cut : DrawnKind::mountain;
    if (s.colour == 5) return DrawnKind::valley;
    why += " matches no convention (and the layer's name names no kind)";
    return DrawnKind::unknown;
  }

  const dxf::Collected& c_;
  const std::string& source_;
  const DrawingOptions& options_;
  LineDrawing& out_;
  std::size_t points_ = 0;
  std::size_t visits_ = 0;
};

std::string counted(const std::map<std::string, std::size_t>& m) {
  std::string s;
  for (const auto& [name, n] : m) s += (s.empty() ? "" : ", ") + std::to_string(n) + " " + name;
  return s;
}

}  // namespace

LineDrawing read_dxf_drawing(const std::string& text, const std::string& source, const DrawingOptions& options) {
  const dxf::Scan scan = dxf::scan(text, source, kMaxDrawingSegments);
  const std::optional<double> stated = insunits_mm(scan.insunits.value_or(0), source);
  const double mm = stated.value_or(options.unit_mm);
  const dxf::Collected collected = dxf::collect(scan, source);
  LineDrawing out;
  out.source = source;
  Expander expander(collected, source, options, out);
  expander.run({mm, 0, 0, mm, 0, 0});
  if (!stated)
    out.notes.push_back(std::string(scan.insunits ? "$INSUNITS is 0 (unitless)" : "no $INSUNITS") +
                        ": one drawing unit read as " + format_decimal(mm, 6) + " mm (--unit-mm says otherwise)");
  if (!scan.skipped.empty())
    out.notes.push_back(counted(scan.skipped) +
                        " entities not read: popcut reads lines, polylines, arcs, circles, ellipses, splines "
                        "and block inserts");
  if (scan.paper_space)
    out.notes.push_back(std::to_string(scan.paper_space) +
                        " entities on a paper-space layout ignored: popcut reads the model");
  if (!expander.hidden.empty())
    out.notes.push_back("lines on layers switched off or frozen ignored: " + counted(expander.hidden));
  if (out.lines.empty())
    throw Error(ErrorCode::invalid_input, source, "ENTITIES", "no lines to read in the model space");
  return out;
}

}  // namespace popcut
