// popcut.pattern.v1 JSON (read and write) and SVG for people and cutter software (docs/formats.md).
#pragma once

#include <iosfwd>
#include <string>

#include "popcut/pattern/pattern.h"

namespace popcut {

inline constexpr const char* kPatternFormat = "popcut.pattern.v1";

// Writers stream, so a pattern of millions of faces never exists twice in memory.
void write_pattern_json(std::ostream& out, const Pattern& pattern);
std::string to_pattern_json(const Pattern& pattern);
Pattern parse_pattern(const std::string& text, const std::string& source);

struct SvgOptions {
  bool shade_faces = false;  // fill VFaces and HFaces in two light greys, for reading a design
};

// Millimetre-sized SVG (width/height in mm, viewBox in mm, y pointing down the sheet): one group
// per kind: cut solid black, mountain red dash-dot, valley blue dashed, sheet outline thin grey.
void write_pattern_svg(std::ostream& out, const Pattern& pattern, const SvgOptions& options = {});
std::string to_pattern_svg(const Pattern& pattern, const SvgOptions& options = {});

// FOLD 1.1 crease pattern in mm (y up, origin at the sheet's lower left): edges split wherever
// lines meet, assigned B (sheet edge), C (cut), M and V with the card's fold angles at 90° open.
void write_pattern_fold(std::ostream& out, const Pattern& pattern);

// DXF (R2000, ASCII) in mm, y up, origin at the sheet's lower left: LINEs on layers CUT (colour
// 7), MOUNTAIN (red, DASHDOT) and VALLEY (blue, DASHED), the sheet edge a closed LWPOLYLINE on
// OUTLINE; written through dxflib.
void write_pattern_dxf(std::ostream& out, const Pattern& pattern);

// PDF at true size (a page the sheet's size, 1 mm to 1 mm: print at 100 %), lines as the SVG's;
// written through cairo. Throws popcut::Error (io) when the stream fails.
void write_pattern_pdf(std::ostream& out, const Pattern& pattern);

}  // namespace popcut
