// SVG writer: real millimetres, one group per line kind in the conventions cutters and people expect.
#include <cstdio>
#include <sstream>
#include <string>

#include "popcut/io/pattern_io.h"
#include "popcut/text.h"

namespace popcut {
namespace {

// Four decimals (0.1 µm) is finer than any cutter, and keeps files small and diffable.
std::string num(double v) { return format_decimal(v, 4); }

struct Frame {
  Rect sheet;
  std::string x(double x_mm) const { return num(x_mm - sheet.min.x_mm); }
  std::string y(double v_mm) const { return num(sheet.max.v_mm - v_mm); }  // v up, SVG y down
};

void ring_path(std::ostream& o, const Frame& f, const Ring& ring) {
  for (std::size_t i = 0; i < ring.size(); ++i) o << (i ? " L" : "M") << f.x(ring[i].x_mm) << " " << f.y(ring[i].v_mm);
  o << " Z";
}

void line_group(std::ostream& o, const Frame& f, const Pattern& p, LineKind kind, const char* attrs) {
  o << "  <g id=\"" << to_string(kind) << "\" inkscape:label=\"" << to_string(kind)
    << "\" inkscape:groupmode=\"layer\" " << attrs << ">\n";
  for (const Segment& s : p.lines) {
    if (s.kind != kind) continue;
    o << "    <line x1=\"" << f.x(s.a.x_mm) << "\" y1=\"" << f.y(s.a.v_mm) << "\" x2=\"" << f.x(s.b.x_mm) << "\" y2=\""
      << f.y(s.b.v_mm) << "\"/>\n";
  }
  o << "  </g>\n";
}

}  // namespace

std::string to_pattern_svg(const Pattern& p, const SvgOptions& options) {
  std::ostringstream o;
  write_pattern_svg(o, p, options);
  return o.str();
}

void write_pattern_svg(std::ostream& o, const Pattern& p, const SvgOptions& options) {
  const Frame f{p.sheet};
  const std::string w = num(p.sheet.max.x_mm - p.sheet.min.x_mm);
  const std::string h = num(p.sheet.max.v_mm - p.sheet.min.v_mm);
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" "
    << "width=\"" << w << "mm\" height=\"" << h << "mm\" viewBox=\"0 0 " << w << " " << h << "\">\n"
    << "  <title>popcut pattern: cut (black), mountain (red dash-dot), valley (blue dashed)</title>\n";
  if (options.shade_faces) {
    o << "  <g id=\"faces\" inkscape:label=\"faces\" inkscape:groupmode=\"layer\" stroke=\"none\" "
         "fill-rule=\"evenodd\">\n";
    for (const PatternFace& face : p.faces) {
      o << "    <path fill=\"" << (face.kind == FaceKind::vertical ? "#dfe6ee" : "#f4efe2") << "\" d=\"";
      ring_path(o, f, face.outer);
      for (const Ring& hole : face.holes) {
        o << " ";
        ring_path(o, f, hole);
      }
      o << "\"/>\n";
    }
    o << "  </g>\n";
  }
  o << "  <g id=\"outline\" inkscape:label=\"outline\" inkscape:groupmode=\"layer\" fill=\"none\" stroke=\"#999999\" "
       "stroke-width=\"0.1\">\n"
    << "    <rect x=\"0\" y=\"0\" width=\"" << w << "\" height=\"" << h << "\"/>\n  </g>\n";
  // Dash periods stay under 3 mm so a fold one small voxel long (2–3 mm) still shows its
  // pattern, and a printed mountain never passes for a cut.
  const char* common = "fill=\"none\" stroke-width=\"0.25\" stroke-linecap=\"round\"";
  line_group(o, f, p, LineKind::valley,
             (std::string(common) + " stroke=\"#1f5fd6\" stroke-dasharray=\"1.5 0.75\"").c_str());
  line_group(o, f, p, LineKind::mountain,
             (std::string(common) + " stroke=\"#d62728\" stroke-dasharray=\"2 0.5 0.4 0.5\"").c_str());
  line_group(o, f, p, LineKind::cut, (std::string(common) + " stroke=\"#000000\"").c_str());
  o << "</svg>\n";
}

}  // namespace popcut
