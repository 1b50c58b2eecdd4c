// Text set in an installed font (fontconfig, FreeType) as closed outlines in mm, for letters cut or raised on a card.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "popcut/geometry.h"

namespace popcut {

// Limits of one text: a name or a greeting, not a page.
inline constexpr std::size_t kMaxTextChars = 200;
inline constexpr double kMinTextSizeMm = 2;
inline constexpr double kMaxTextSizeMm = 300;

struct TextSpec {
  std::string text;                  // UTF-8; "\n" starts a new line below
  std::string font = "DejaVu Sans";  // a fontconfig family name, installed on the machine that sets it
  double size_mm = 10;               // height of a capital letter (the font's "H")
  // A wall of letters: in a frame joined to every letter, cut out around them (true), or letters
  // standing free on a bar, held by their own flat tops (false).
  bool frame = true;
  friend bool operator==(const TextSpec&, const TextSpec&) = default;
};

// One letter's piece of paper: its outer edge counter-clockwise and its counters (the holes of
// "o", "A", "B") clockwise, x right and y up, the first line's baseline on y = 0 from x = 0.
struct TextShape {
  Ring outer;
  std::vector<Ring> holes;
};

// Text set: its letters' shapes and the metrics to place them by.
struct TextSetting {
  std::vector<TextShape> shapes;
  double descent_mm = 0;         // how far the font's letters reach below the baseline
  double line_height_mm = 0;     // from one baseline to the next line's, below
  std::vector<Rect> line_boxes;  // each line's letters' extent, first line first (an empty line: a point)
};

// Spec's text set, curves flattened so no chord strays more than tolerance_mm from the font's
// curve. Throws popcut::Error (limit past kMaxTextChars, invalid_input for text that is
// not UTF-8, a size out of range, a font not installed — listing those that are — or a character
// the font has no letter for), naming the field under `where` (where.string, where.font, where.size).
TextSetting set_text(const TextSpec& spec, double tolerance_mm, const std::string& where);

// The font families installed (fontconfig), sorted, for a font chooser.
std::vector<std::string> installed_font_families();

}  // namespace popcut
