// SVG reader for patterns drawn elsewhere: Inkscape layers, transforms, real units, line kinds by convention.
#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>

#include "io/svg_path.h"
#include "io/ascii_case.h"
#include "popcut/error.h"
#include "popcut/io/drawing_io.h"
#include "popcut/text.h"

namespace popcut {
namespace {

using tinyxml2::XMLElement;
constexpr double kMmPerPx = 25.4 / 96;
constexpr int kMaxDepth = 64;

// Inherited presentation state: what the ancestors say about the lines inside them.
struct Context {
  svg::Affine to_page;  // user units → page millimetres, y down
  std::optional<DrawnKind> layer;
  std::string layer_why;
  std::string stroke;
  std::string dasharray;
  std::string css_class;  // the nearest class attribute: a style sheet may set the stroke
  int depth = 0;
};

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// A style="a: b; c: d" declaration, or the attribute of the same name; style wins, as in CSS.
std::string presentation(const XMLElement& e, const char* name) {
  if (const char* style = e.Attribute("style")) {
    std::istringstream in(style);
    std::string decl;
    while (std::getline(in, decl, ';')) {
      const auto colon = decl.find(':');
      if (colon != std::string::npos && ascii_lower(trim(decl.substr(0, colon))) == name)
        return trim(decl.substr(colon + 1));
    }
  }
  const char* a = e.Attribute(name);
  return a ? trim(a) : "";
}

struct Rgb {
  int r = 0, g = 0, b = 0;
};

std::optional<Rgb> parse_colour(std::string c) {
  c = ascii_lower(c);
  static const std::map<std::string, Rgb> named = {
      {"black", {0, 0, 0}},      {"red", {255, 0, 0}},      {"blue", {0, 0, 255}},     {"green", {0, 128, 0}},
      {"lime", {0, 255, 0}},     {"gray", {128, 128, 128}}, {"grey", {128, 128, 128}}, {"magenta", {255, 0, 255}},
      {"yellow", {255, 255, 0}}, {"white", {255, 255, 255}}};
  if (const auto it = named.find(c); it != named.end()) return it->second;
  unsigned v = 0;
  if (c.size() == 7 && c[0] == '#' && std::sscanf(c.c_str() + 1, "%6x", &v) == 1)
    return Rgb{int(v >> 16), int(v >> 8 & 255), int(v & 255)};
  if (c.size() == 4 && c[0] == '#' && std::sscanf(c.c_str() + 1, "%3x", &v) == 1)
    return Rgb{int(v >> 8) * 17, int(v >> 4 & 15) * 17, int(v & 15) * 17};
  Rgb rgb;
  if (std::sscanf(c.c_str(), "rgb(%d ,%d ,%d )", &rgb.r, &rgb.g, &rgb.b) == 3) return rgb;
  return std::nullopt;
}

// The kind a stroke's dash pattern and colour mean: dashed valley, dash-dot mountain; solid
// black (or green, Origami Simulator's cut) cut, red mountain (or cut, laser convention), blue valley.
std::optional<DrawnKind> kind_of_style(const Context& c, const DrawingOptions& options, std::string& why) {
  if (!c.dasharray.empty() && ascii_lower(c.dasharray) != "none") {
    std::vector<double> dashes;
    try {
      dashes = svg::parse_number_list(c.dasharray);
    } catch (const std::invalid_argument&) {
    }
    if (dashes.size() % 2) dashes.insert(dashes.end(), dashes.begin(), dashes.end());
    if (dashes.size() >= 2) {
      why = "stroke-dasharray \"" + c.dasharray + "\"";
      return dashes.size() == 2 ? DrawnKind::valley : DrawnKind::mountain;
    }
  }
  const auto rgb = parse_colour(c.stroke.empty() ? "black" : c.stroke);
  why = "stroke " + (c.stroke.empty() ? std::string("black (the default)") : c.stroke);
  if (!rgb) return std::nullopt;
  const auto near = [&](int r, int g, int b) {
    return std::abs(rgb->r - r) < 64 && std::abs(rgb->g - g) < 64 && std::abs(rgb->b - b) < 64;
  };
  if (near(0, 0, 0)) return DrawnKind::cut;
  if (near(255, 0, 0) || near(214, 39, 40)) return options.red_is_cut ? DrawnKind::cut : DrawnKind::mountain;
  if (near(0, 0, 255) || near(31, 95, 214)) return DrawnKind::valley;
  if (near(0, 128, 0) || near(0, 255, 0)) return DrawnKind::cut;
  return std::nullopt;
}

// A length with an absolute unit, in millimetres ("210mm", "8.5in", "800" px).
double length_mm(const std::string& text, const std::string& what) {
  std::size_t end = 0;
  double v = 0;
  try {
    v = std::stod(text, &end);
  } catch (const std::exception&) {
    throw std::invalid_argument(what + ": expected a length such as 210mm, got \"" + text + "\"");
  }
  const std::string unit = ascii_lower(trim(text.substr(end)));
  static const std::map<std::string, double> mm = {{"", kMmPerPx}, {"px", kMmPerPx},  {"mm", 1},        {"cm", 10},
                                                   {"in", 25.4},   {"pt", 25.4 / 72}, {"pc", 25.4 / 6}, {"q", 0.25}};
  const auto it = mm.find(unit);
  if (it == mm.end())
    throw std::invalid_argument(what + ": unknown unit \"" + unit + "\" in \"" + text +
                                "\": expected mm, cm, in, pt, pc, px or none");
  if (!(v > 0) || !std::isfinite(v))
    throw std::invalid_argument(what + ": expected a positive length, got \"" + text + "\"");
  return v * it->second;
}

class SvgReader {
 public:
  SvgReader(const std::string& source, const DrawingOptions& options) : options_(options) { out_.source = source; }
  LineDrawing read(const std::string& text);

 private:
  [[noreturn]] void fail(const XMLElement& e, const std::string& message) const {
    throw Error(ErrorCode::invalid_input, out_.source, "line " + std::to_string(e.GetLineNum()) + ", " + name(e),
                message);
  }
  static std::string name(const XMLElement& e) {
    const char* id = e.Attribute("id");
    return std::string("<") + e.Name() + (id ? std::string(" id=\"") + id + "\"" : "") + ">";
  }
  double attr(const XMLElement& e, const char* key, double fallback, bool required = false) const;
  void root(const XMLElement& svg);
  void walk(const XMLElement& e, Context c);
  void shape(const XMLElement& e, const Context& c);
  std::vector<svg::Subpath> geometry(const XMLElement& e, double tolerance);
  void add(const XMLElement& e, const Context& c, const svg::Subpath& sub);

  const DrawingOptions& options_;
  LineDrawing out_;
  std::map<std::string, const XMLElement*> ids_;
  std::size_t points_ = 0;
  int ignored_text_ = 0, unstroked_ = 0;
  bool styled_ = false;  // the document has a <style> sheet
};

double SvgReader::attr(const XMLElement& e, const char* key, double fallback, bool required) const {
  const char* a = e.Attribute(key);
  if (!a) {
    if (required) fail(e, std::string("missing attribute ") + key);
    return fallback;
  }
  std::string s = trim(a);
  if (s.size() > 2 && ascii_lower(s.substr(s.size() - 2)) == "px") s.resize(s.size() - 2);
  std::size_t end = 0;
  double v = 0;
  try {
    v = std::stod(s, &end);
  } catch (const std::exception&) {
    end = 0;
  }
  if (end == 0 || end != s.size() || !std::isfinite(v))
    fail(e, std::string(key) + ": expected a number in user units, got \"" + a + "\"");
  return v;
}

void SvgReader::root(const XMLElement& svg) {
  const char* w = svg.Attribute("width");
  const char* h = svg.Attribute("height");
  const char* vb = svg.Attribute("viewBox");
  std::vector<double> box;
  try {
    if (vb) box = svg::parse_number_list(vb);
    if (vb && (box.size() != 4 || !(box[2] > 0) || !(box[3] > 0)))
      throw std::invalid_argument("viewBox: expected \"min-x min-y width height\" with positive sizes, got \"" +
                                  std::string(vb) + "\"");
    const bool percent =
        (w && std::string(w).find('%') != std::string::npos) || (h && std::string(h).find('%') != std::string::npos);
    double w_mm = 0, h_mm = 0;
    if (w && h && !percent) {
      w_mm = length_mm(w, "width");
      h_mm = length_mm(h, "height");
    } else if (!box.empty()) {
      w_mm = box[2] * kMmPerPx;
      h_mm = box[3] * kMmPerPx;
      out_.notes.push_back("the page has no absolute width and height: one user unit read as 1 px (1/96 in)");
    }
    svg::Affine m;
    if (!box.empty())
      m = svg::Affine{1, 0, 0, 1, -box[0], -box[1]}.then({w_mm / box[2], 0, 0, h_mm / box[3], 0, 0});
    else
      m = {kMmPerPx, 0, 0, kMmPerPx, 0, 0};
    if (w_mm > 0) out_.page = Rect{{0, 0}, {w_mm, h_mm}};
    walk(svg, Context{m, std::nullopt, "", "", "", "", 0});
  } catch (const std::invalid_argument& e) {
    fail(svg, e.what());
  }
}

void SvgReader::walk(const XMLElement& e, Context c) {
  if (++c.depth > kMaxDepth) fail(e, "elements nest deeper than " + std::to_string(kMaxDepth) + " (a <use> cycle?)");
  if (ascii_lower(presentation(e, "display")) == "none") return;
  if (const char* t = e.Attribute("transform")) {
    try {
      c.to_page = svg::parse_transform(t).then(c.to_page);
    } catch (const std::invalid_argument& x) {
      fail(e, std::string("transform: ") + x.what());
    }
  }
  if (const std::string s = presentation(e, "stroke"); !s.empty()) c.stroke = s;
  if (const char* cls = e.Attribute("class")) c.css_class = cls;
  if (const std::string s = presentation(e, "stroke-dasharray"); !s.empty()) c.dasharray = s;
  const std::string tag = e.Name();
  if (tag == "g" || tag == "svg" || tag == "a" || tag == "switch") {
    for (const char* key : {"inkscape:label", "id"}) {
      const char* label = e.Attribute(key);
      if (!label) continue;
      if (const auto kind = kind_of_layer_name(label, options_)) {
        c.layer = kind;
        c.layer_why = std::string("layer \"") + label + "\"";
        break;
      }
    }
    for (const XMLElement* child = e.FirstChildElement(); child; child = child->NextSiblingElement()) walk(*child, c);
  } else if (tag == "use") {
    const char* href = e.Attribute("href") ? e.Attribute("href") : e.Attribute("xlink:href");
    const auto it = href && href[0] == '#' ? ids_.find(href + 1) : ids_.end();
    if (it == ids_.end()) fail(e, std::string("href: no element with id \"") + (href ? href : "") + "\" to use");
    c.to_page = svg::Affine{1, 0, 0, 1, attr(e, "x", 0), attr(e, "y", 0)}.then(c.to_page);
    if (std::string(it->second->Name()) == "symbol") {
      for (const XMLElement* child = it->second->FirstChildElement(); child; child = child->NextSiblingElement())
        walk(*child, c);
    } else {
      walk(*it->second, c);
    }
  } else if (tag == "text") {
    ++ignored_text_;
  } else if (tag == "path" || tag == "line" || tag == "polyline" || tag == "polygon" || tag == "rect" ||
             tag == "circle" || tag == "ellipse") {
    shape(e, c);
  }
  // defs, symbol, title, metadata, sodipodi:namedview, clipPath, … hold no lines of the sheet.
}

std::vector<svg::Subpath> SvgReader::geometry(const XMLElement& e, double tol) {
  const std::string tag = e.Name();
  const std::size_t room = kMaxDrawingSegments - std::min(points_, kMaxDrawingSegments);
  if (tag == "path") {
    const char* d = e.Attribute("d");
    return d ? svg::parse_path_data(d, tol, room) : std::vector<svg::Subpath>{};
  }
  if (tag == "line") return {{{{attr(e, "x1", 0), attr(e, "y1", 0)}, {attr(e, "x2", 0), attr(e, "y2", 0)}}, false}};
  if (tag == "polyline" || tag == "polygon") {
    const char* pts = e.Attribute("points");
    const std::vector<double> v = pts ? svg::parse_number_list(pts) : std::vector<double>{};
    if (v.size() % 2) throw std::invalid_argument("points: an odd count of numbers (" + std::to_string(v.size()) + ")");
    if (v.size() / 2 > room) throw std::length_error("too many points");
    svg::Subpath s{{}, tag == "polygon"};
    for (std::size_t i = 0; i + 1 < v.size(); i += 2) s.points.push_back({v[i], v[i + 1]});
    return {s};
  }
  if (tag == "rect") {
    const double x = attr(e, "x", 0), y = attr(e, "y", 0), w = attr(e, "width", 0, true),
                 h = attr(e, "height", 0, true);
    if (!(w > 0) || !(h > 0)) throw std::invalid_argument("width and height must be positive");
    double rx = attr(e, "rx", -1), ry = attr(e, "ry", -1);
    if (rx < 0) rx = ry < 0 ? 0 : ry;
    if (ry < 0) ry = rx;
    rx = std::min(rx, w / 2);
    ry = std::min(ry, h / 2);
    std::ostringstream d;
    d.precision(17);
    d << "M" << x + rx << "," << y << " H" << x + w - rx << " A" << rx << "," << ry << " 0 0 1 " << x + w << ","
      << y + ry << " V" << y + h - ry << " A" << rx << "," << ry << " 0 0 1 " << x + w - rx << "," << y + h << " H"
      << x + rx << " A" << rx << "," << ry << " 0 0 1 " << x << "," << y + h - ry << " V" << y + ry << " A" << rx << ","
      << ry << " 0 0 1 " << x + rx << "," << y << " Z";
    return svg::parse_path_data(d.str(), tol, room);
  }
  const bool circle = tag == "circle";
  const double rx = circle ? attr(e, "r", 0, true) : attr(e, "rx", 0, true);
  const double ry = circle ? rx : attr(e, "ry", 0, true);
  if (!(rx > 0) || !(ry > 0)) throw std::invalid_argument("radii must be positive");
  return {{svg::ellipse_points({attr(e, "cx", 0), attr(e, "cy", 0)}, rx, ry, tol), true}};
}

void SvgReader::shape(const XMLElement& e, const Context& c) {
  if (ascii_lower(c.stroke) == "none" || ascii_lower(c.stroke) == "transparent") {
    ++unstroked_;
    return;
  }
  std::vector<svg::Subpath> subs;
  try {
    subs = geometry(e, options_.chord_tolerance_mm / std::max(c.to_page.max_scale(), 1e-12));
  } catch (const std::length_error&) {
    throw Error(ErrorCode::limit, out_.source, "line " + std::to_string(e.GetLineNum()) + ", " + name(e),
                "the drawing has more than " + std::to_string(kMaxDrawingSegments) + " segments, the documented limit");
  } catch (const std::invalid_argument& x) {
    fail(e, x.what());
  }
  for (const svg::Subpath& sub : subs) add(e, c, sub);
}

void SvgReader::add(const XMLElement& e, const Context& c, const svg::Subpath& sub) {
  DrawnLine line;
  line.closed = sub.closed;
  line.where = "line " + std::to_string(e.GetLineNum()) + ", " + name(e);
  const double page_h = out_.page ? out_.page->max.v_mm : 0;
  for (const Point2& p : sub.points) {
    const Point2 q = c.to_page.apply(p);
    if (!std::isfinite(q.x_mm) || !std::isfinite(q.v_mm) || std::abs(q.x_mm) > kMaxDrawingCoordinateMm ||
        std::abs(q.v_mm) > kMaxDrawingCoordinateMm)
      fail(e, "a point lies at (" + format_decimal(q.x_mm, 3) + ", " + format_decimal(q.v_mm, 3) +
                  ") mm, beyond the documented ±100 m");
    const Point2 v{q.x_mm, page_h - q.v_mm};  // SVG y runs down the page, the sheet's v up
    if (line.points.empty() || !(line.points.back() == v)) line.points.push_back(v);
  }
  if (line.closed && line.points.size() > 1 && line.points.front() == line.points.back()) line.points.pop_back();
  if (line.points.size() < 2) fail(e, "a zero-length line: every point of it is the same");
  // Circles and ellipses are flattened before any count: the limit holds over the whole drawing.
  if ((points_ += line.points.size()) > kMaxDrawingSegments)
    throw Error(ErrorCode::limit, out_.source, line.where,
                "the drawing has more than " + std::to_string(kMaxDrawingSegments) + " segments, the documented limit");
  if (c.layer) {
    line.kind = *c.layer;
    line.why = c.layer_why;
  } else if (c.stroke.empty() && c.dasharray.empty() && !c.css_class.empty() && styled_) {
    // Illustrator styles strokes by class from a <style> sheet, which popcut does not read:
    // taking the SVG default (black, a cut) would be a guess.
    line.kind = DrawnKind::unknown;
    line.why = "styled by CSS class \"" + c.css_class + "\" from a <style> sheet, which popcut does not read";
  } else if (const auto kind = kind_of_style(c, options_, line.why)) {
    line.kind = *kind;
  } else {
    line.kind = DrawnKind::unknown;
    line.why += " matches no convention (and no layer names a kind)";
  }
  out_.lines.push_back(std::move(line));
}

void index_ids(const XMLElement& e, std::map<std::string, const XMLElement*>& ids, bool& styled) {
  if (const char* id = e.Attribute("id")) ids.emplace(id, &e);
  styled |= std::string(e.Name()) == "style";
  for (const XMLElement* child = e.FirstChildElement(); child; child = child->NextSiblingElement())
    index_ids(*child, ids, styled);
}

LineDrawing SvgReader::read(const std::string& text) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw Error(ErrorCode::invalid_input, out_.source, "line " + std::to_string(doc.ErrorLineNum()),
                std::string("malformed XML: ") + doc.ErrorStr());
  const XMLElement* svg = doc.RootElement();
  if (!svg || std::string(svg->Name()) != "svg")
    throw Error(ErrorCode::invalid_input, out_.source, svg ? "line " + std::to_string(svg->GetLineNum()) : "",
                std::string("expected an <svg> document, got <") + (svg ? svg->Name() : "nothing") + ">");
  index_ids(*svg, ids_, styled_);
  root(*svg);
  if (ignored_text_)
    out_.notes.push_back(std::to_string(ignored_text_) + " <text> element(s) ignored: text is not cut");
  if (unstroked_)
    out_.notes.push_back(std::to_string(unstroked_) + " shape(s) without a stroke ignored (fills are not lines)");
  return std::move(out_);
}

}  // namespace

LineDrawing read_svg_drawing(const std::string& text, const std::string& source, const DrawingOptions& options) {
  return SvgReader(source, options).read(text);
}

}  // namespace popcut
