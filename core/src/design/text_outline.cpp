// Text as outlines: fontconfig finds the font, FreeType reads its letters, curves become chords within a tolerance.
#include "popcut/design/text_outline.h"

#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <set>

#include "io/ascii_case.h"
#include "io/svg_path.h"
#include "popcut/error.h"
#include "popcut/text.h"
#include "popcut/utf8.h"

namespace popcut {
namespace {

std::string code_point_name(char32_t cp) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "U+%04X", static_cast<unsigned>(cp));
  return buf;
}

struct FontFile {
  std::string path;
  int index = 0;
};

// The file of an installed family. fontconfig always answers with its best substitute, so the
// match counts only when one of its family names is the one asked for.
FontFile find_font(const std::string& family, const std::string& where) {
  const std::unique_ptr<FcPattern, decltype(&FcPatternDestroy)> pattern(FcPatternCreate(), FcPatternDestroy);
  FcPatternAddString(pattern.get(), FC_FAMILY, reinterpret_cast<const FcChar8*>(family.c_str()));
  FcPatternAddBool(pattern.get(), FC_SCALABLE, FcTrue);
  FcConfigSubstitute(nullptr, pattern.get(), FcMatchPattern);
  FcDefaultSubstitute(pattern.get());
  FcResult result = FcResultNoMatch;
  const std::unique_ptr<FcPattern, decltype(&FcPatternDestroy)> match(FcFontMatch(nullptr, pattern.get(), &result),
                                                                      FcPatternDestroy);
  if (match) {
    FcChar8* name = nullptr;
    for (int i = 0; FcPatternGetString(match.get(), FC_FAMILY, i, &name) == FcResultMatch; ++i) {
      if (ascii_lower(reinterpret_cast<const char*>(name)) != ascii_lower(family)) continue;
      FcChar8* file = nullptr;
      int index = 0;
      if (FcPatternGetString(match.get(), FC_FILE, 0, &file) != FcResultMatch) break;
      FcPatternGetInteger(match.get(), FC_INDEX, 0, &index);
      return {reinterpret_cast<const char*>(file), index};
    }
  }
  std::string known;
  for (const std::string& f : installed_font_families()) known += (known.empty() ? "" : ", ") + f;
  throw Error(ErrorCode::invalid_input, "", where + ".font",
              "font \"" + family + "\" is not installed; installed: " + (known.empty() ? "none" : known));
}

// Contours of one letter in font units, curves flattened, each closed implicitly.
struct Flattener {
  double tolerance = 1;
  std::vector<Ring> rings;
  Point2 at;
  void to(Point2 p) {
    if (!rings.back().empty() && rings.back().back().x_mm == p.x_mm && rings.back().back().v_mm == p.v_mm) return;
    rings.back().push_back(p);
    at = p;
  }
};

Point2 pt(const FT_Vector* v) { return {static_cast<double>(v->x), static_cast<double>(v->y)}; }

Flattener* self(void* user) { return static_cast<Flattener*>(user); }

const FT_Outline_Funcs kOutlineFuncs = {
    [](const FT_Vector* to, void* user) {
      self(user)->rings.emplace_back();
      self(user)->to(pt(to));
      return 0;
    },
    [](const FT_Vector* to, void* user) {
      self(user)->to(pt(to));
      return 0;
    },
    [](const FT_Vector* c, const FT_Vector* to, void* user) {
      Flattener& f = *self(user);
      for (Point2 p : svg::quadratic_points(f.at, pt(c), pt(to), f.tolerance)) f.to(p);
      return 0;
    },
    [](const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to, void* user) {
      Flattener& f = *self(user);
      for (Point2 p : svg::cubic_points({f.at, pt(c1), pt(c2), pt(to)}, f.tolerance)) f.to(p);
      return 0;
    },
    0,
    0};

// Contours into letters by nesting: a contour inside an even number of others is paper's outer
// edge, inside an odd number a counter of the smallest outer around it. Fonts wind contours
// either way (TrueType clockwise, CFF counter-clockwise), so nesting, not winding, decides.
std::vector<TextShape> shapes_of(std::vector<Ring> rings) {
  std::erase_if(rings, [](const Ring& r) { return r.size() < 3 || std::abs(signed_area_mm2(r)) < 1e-9; });
  std::vector<int> depth(rings.size(), 0);
  for (std::size_t i = 0; i < rings.size(); ++i)
    for (std::size_t j = 0; j < rings.size(); ++j)
      if (i != j && inside_ring(rings[i][0], rings[j])) ++depth[i];
  std::vector<TextShape> shapes;
  std::vector<std::size_t> shape_of(rings.size(), 0);
  for (std::size_t i = 0; i < rings.size(); ++i) {
    if (depth[i] % 2 != 0) continue;
    if (signed_area_mm2(rings[i]) < 0) std::reverse(rings[i].begin(), rings[i].end());
    shape_of[i] = shapes.size();
    shapes.push_back({rings[i], {}});
  }
  for (std::size_t i = 0; i < rings.size(); ++i) {
    if (depth[i] % 2 == 0) continue;
    std::optional<std::size_t> best;
    for (std::size_t j = 0; j < rings.size(); ++j) {
      if (depth[j] != depth[i] - 1 || !inside_ring(rings[i][0], rings[j])) continue;
      if (!best || std::abs(signed_area_mm2(rings[j])) < std::abs(signed_area_mm2(rings[*best]))) best = j;
    }
    if (!best) continue;
    if (signed_area_mm2(rings[i]) > 0) std::reverse(rings[i].begin(), rings[i].end());
    shapes[shape_of[*best]].holes.push_back(rings[i]);
  }
  return shapes;
}

std::u32string checked_text(const TextSpec& spec, const std::string& where) {
  if (spec.text.size() > 4 * kMaxTextChars)
    throw Error(ErrorCode::limit, "", where + ".string",
                "text of " + std::to_string(spec.text.size()) + " bytes; at most " + std::to_string(kMaxTextChars) +
                    " characters");
  const std::optional<std::u32string> cps = decode_utf8(spec.text);
  if (!cps) throw Error(ErrorCode::invalid_input, "", where + ".string", "text is not UTF-8");
  if (cps->size() > kMaxTextChars)
    throw Error(ErrorCode::limit, "", where + ".string",
                "text of " + std::to_string(cps->size()) + " characters; at most " + std::to_string(kMaxTextChars));
  if (std::all_of(cps->begin(), cps->end(), [](char32_t c) { return c == ' ' || c == '\n'; }))
    throw Error(ErrorCode::invalid_input, "", where + ".string", "text has no letters");
  for (std::size_t i = 0; i < cps->size(); ++i) {
    const char32_t c = (*cps)[i];
    if ((c < 0x20 && c != '\n') || (c >= 0x7f && c <= 0x9f))
      throw Error(ErrorCode::invalid_input, "", where + ".string",
                  "character " + std::to_string(i + 1) + " is the control character " + code_point_name(c));
  }
  if (!(spec.size_mm >= kMinTextSizeMm && spec.size_mm <= kMaxTextSizeMm))
    throw Error(ErrorCode::invalid_input, "", where + ".size",
                "letter height " + format_decimal(spec.size_mm, 3) + " mm; expected " +
                    format_decimal(kMinTextSizeMm, 0) + "–" + format_decimal(kMaxTextSizeMm, 0) + " mm");
  return *cps;
}

using Library = std::unique_ptr<FT_LibraryRec_, decltype(&FT_Done_FreeType)>;
using Face = std::unique_ptr<FT_FaceRec_, decltype(&FT_Done_Face)>;

// Font units per mm: the letter "H" is spec.size_mm tall (0.7 em when the font has no H).
double units_per_mm(FT_Face face, double size_mm) {
  double cap = 0.7 * face->units_per_EM;
  const FT_UInt h = FT_Get_Char_Index(face, 'H');
  if (h != 0 && FT_Load_Glyph(face, h, FT_LOAD_NO_SCALE | FT_LOAD_NO_BITMAP) == 0) {
    FT_BBox box;
    FT_Outline_Get_CBox(&face->glyph->outline, &box);
    if (box.yMax > 0) cap = static_cast<double>(box.yMax);
  }
  return cap / size_mm;
}

}  // namespace

TextSetting set_text(const TextSpec& spec, double tolerance_mm, const std::string& where) {
  const std::u32string text = checked_text(spec, where);
  const FontFile file = find_font(spec.font, where);
  FT_Library raw_lib = nullptr;
  if (FT_Init_FreeType(&raw_lib) != 0) throw Error(ErrorCode::internal, "", where, "FreeType did not start");
  const Library lib(raw_lib, FT_Done_FreeType);
  FT_Face raw_face = nullptr;
  if (FT_New_Face(lib.get(), file.path.c_str(), file.index, &raw_face) != 0)
    throw Error(ErrorCode::io, file.path, where + ".font", "FreeType could not read the font file");
  const Face face(raw_face, FT_Done_Face);
  if (!FT_IS_SCALABLE(face.get()))
    throw Error(ErrorCode::invalid_input, file.path, where + ".font", "the font has no outlines (a bitmap font)");
  const double per_mm = units_per_mm(face.get(), spec.size_mm);
  const auto line_units = static_cast<double>(face->height);  // the font's own line spacing
  double pen = 0, baseline = 0;
  TextSetting out;
  out.descent_mm = std::abs(static_cast<double>(face->descender)) / per_mm;
  out.line_height_mm = line_units / per_mm;
  std::optional<Rect> box;
  const auto end_line = [&] {
    const double baseline_mm = baseline / per_mm;
    out.line_boxes.push_back(box ? *box : Rect{{0, baseline_mm}, {0, baseline_mm}});
    box.reset();
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') {
      end_line();
      pen = 0;
      baseline -= line_units;
      continue;
    }
    const FT_UInt glyph = FT_Get_Char_Index(face.get(), text[i]);
    if (glyph == 0)
      throw Error(ErrorCode::invalid_input, "", where + ".string",
                  "font \"" + spec.font + "\" has no letter for character " + std::to_string(i + 1) + " (" +
                      code_point_name(text[i]) + ")");
    if (FT_Load_Glyph(face.get(), glyph, FT_LOAD_NO_SCALE | FT_LOAD_NO_BITMAP) != 0)
      throw Error(ErrorCode::io, file.path, where + ".string",
                  "FreeType could not read the letter for " + code_point_name(text[i]));
    Flattener f;
    f.tolerance = tolerance_mm * per_mm;
    if (FT_Outline_Decompose(&face->glyph->outline, &kOutlineFuncs, &f) != 0)
      throw Error(ErrorCode::io, file.path, where + ".string",
                  "FreeType could not read the outline of the letter for " + code_point_name(text[i]));
    for (Ring& r : f.rings) {
      if (r.size() > 1 && r.front().x_mm == r.back().x_mm && r.front().v_mm == r.back().v_mm) r.pop_back();
      for (Point2& p : r) p = {(pen + p.x_mm) / per_mm, (baseline + p.v_mm) / per_mm};
    }
    for (TextShape& s : shapes_of(std::move(f.rings))) {
      const Rect b = bounds(s.outer);
      box = box ? Rect{{std::min(box->min.x_mm, b.min.x_mm), std::min(box->min.v_mm, b.min.v_mm)},
                       {std::max(box->max.x_mm, b.max.x_mm), std::max(box->max.v_mm, b.max.v_mm)}}
                : b;
      out.shapes.push_back(std::move(s));
    }
    pen += static_cast<double>(face->glyph->advance.x);
  }
  end_line();
  return out;
}

std::vector<std::string> installed_font_families() {
  const std::unique_ptr<FcPattern, decltype(&FcPatternDestroy)> pattern(FcPatternCreate(), FcPatternDestroy);
  FcPatternAddBool(pattern.get(), FC_SCALABLE, FcTrue);
  const std::unique_ptr<FcObjectSet, decltype(&FcObjectSetDestroy)> fields(FcObjectSetBuild(FC_FAMILY, nullptr),
                                                                           FcObjectSetDestroy);
  const std::unique_ptr<FcFontSet, decltype(&FcFontSetDestroy)> fonts(FcFontList(nullptr, pattern.get(), fields.get()),
                                                                      FcFontSetDestroy);
  std::set<std::string> names;
  for (int i = 0; fonts && i < fonts->nfont; ++i) {
    FcChar8* name = nullptr;
    if (FcPatternGetString(fonts->fonts[i], FC_FAMILY, 0, &name) == FcResultMatch)
      names.insert(reinterpret_cast<const char*>(name));
  }
  return {names.begin(), names.end()};
}

}  // namespace popcut

#if defined(__SANITIZE_ADDRESS__)
// fontconfig keeps its configuration and caches for the life of the process, and frees them only
// in FcFini, which a library may not call (the program may use fontconfig elsewhere): LeakSanitizer
// would report them at every exit of a program that set text. Linked in with this file, so only
// into programs that use fontconfig through it.
// NOLINTNEXTLINE(readability-identifier-naming): the name LeakSanitizer looks for
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig.so\n"; }
#endif
