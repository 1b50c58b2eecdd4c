// Drawings by file type, and the layer names people give their cut and fold lines.
#include <algorithm>
#include <map>

#include "io/ascii_case.h"
#include "popcut/error.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/files.h"

namespace popcut {
namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// Built-in names, lower case: English, German, French, Spanish, Italian and Japanese.
const std::map<std::string, DrawnKind>& builtin_names() {
  static const std::map<std::string, DrawnKind> names = {
      {"cut", DrawnKind::cut},           {"cuts", DrawnKind::cut},
      {"cutting", DrawnKind::cut},       {"schnitt", DrawnKind::cut},
      {"schneiden", DrawnKind::cut},     {"coupe", DrawnKind::cut},
      {"découpe", DrawnKind::cut},       {"corte", DrawnKind::cut},
      {"taglio", DrawnKind::cut},        {"カット", DrawnKind::cut},
      {"切り取り", DrawnKind::cut},      {"切り込み", DrawnKind::cut},
      {"mountain", DrawnKind::mountain}, {"mountains", DrawnKind::mountain},
      {"berg", DrawnKind::mountain},     {"bergfalte", DrawnKind::mountain},
      {"montagne", DrawnKind::mountain}, {"montaña", DrawnKind::mountain},
      {"monte", DrawnKind::mountain},    {"山折り", DrawnKind::mountain},
      {"山", DrawnKind::mountain},       {"valley", DrawnKind::valley},
      {"valleys", DrawnKind::valley},    {"tal", DrawnKind::valley},
      {"talfalte", DrawnKind::valley},   {"vallée", DrawnKind::valley},
      {"valle", DrawnKind::valley},      {"谷折り", DrawnKind::valley},
      {"谷", DrawnKind::valley},         {"score", DrawnKind::fold},
      {"scores", DrawnKind::fold},       {"crease", DrawnKind::fold},
      {"creases", DrawnKind::fold},      {"fold", DrawnKind::fold},
      {"folds", DrawnKind::fold},        {"perforate", DrawnKind::fold},
      {"perforation", DrawnKind::fold},  {"perf", DrawnKind::fold},
      {"rill", DrawnKind::fold},         {"rillen", DrawnKind::fold},
      {"falz", DrawnKind::fold},         {"pli", DrawnKind::fold},
      {"rainure", DrawnKind::fold},      {"pliegue", DrawnKind::fold},
      {"piega", DrawnKind::fold},        {"折り線", DrawnKind::fold},
      {"折り", DrawnKind::fold},         {"outline", DrawnKind::outline},
      {"border", DrawnKind::outline},    {"sheet", DrawnKind::outline},
      {"boundary", DrawnKind::outline},  {"umriss", DrawnKind::outline},
      {"contour", DrawnKind::outline},   {"bord", DrawnKind::outline},
      {"borde", DrawnKind::outline},     {"外形", DrawnKind::outline},
      {"flat", DrawnKind::flat}};
  return names;
}

// Words of a name: runs of letters and non-ASCII characters ("Layer 2 - Valley folds" → layer,
// valley, folds), so a layer is recognised by any one word that names a kind.
std::vector<std::string> words(const std::string& name) {
  std::vector<std::string> out(1);
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 128 || std::isalpha(u))
      out.back() += c;
    else if (!out.back().empty())
      out.emplace_back();
  }
  if (out.back().empty()) out.pop_back();
  return out;
}

}  // namespace

const char* to_string(DrawnKind kind) { return kDrawnKindNames.name(kind).data(); }

std::optional<DrawnKind> kind_of_layer_name(const std::string& name, const DrawingOptions& options) {
  const std::string whole = ascii_lower(name);
  for (const auto& [custom, kind] : options.layer_names)
    if (ascii_lower(custom) == whole) return kind;
  const auto& names = builtin_names();
  if (const auto it = names.find(whole); it != names.end()) return it->second;
  std::optional<DrawnKind> found;
  for (const std::string& w : words(whole)) {
    const auto it = names.find(w);
    if (it == names.end()) continue;
    // "Mountain folds": a direction word outranks the generic fold words; "cut and fold" names
    // two kinds and so neither.
    if (found && *found == DrawnKind::fold && (it->second == DrawnKind::mountain || it->second == DrawnKind::valley))
      found.reset();
    if (found && (*found == DrawnKind::mountain || *found == DrawnKind::valley) && it->second == DrawnKind::fold)
      continue;
    if (found && *found != it->second) return std::nullopt;
    found = it->second;
  }
  return found;
}

bool is_drawing_path(const std::string& path) {
  const std::string p = ascii_lower(path);
  return ends_with(p, ".svg") || ends_with(p, ".dxf") || ends_with(p, ".fold");
}

namespace {
[[noreturn]] void not_a_drawing(const std::string& source) {
  throw Error(ErrorCode::invalid_input, source, "", "not a drawing popcut reads: expected a .svg, .dxf or .fold file");
}
}  // namespace

LineDrawing read_drawing(const std::string& text, const std::string& source, const DrawingOptions& options) {
  const std::string name = ascii_lower(source);
  if (ends_with(name, ".fold")) return read_fold_drawing(text, source, options);
  if (ends_with(name, ".svg")) return read_svg_drawing(text, source, options);
  if (ends_with(name, ".dxf")) return read_dxf_drawing(text, source, options);
  not_a_drawing(source);
}

LineDrawing load_drawing(const std::string& path, const DrawingOptions& options) {
  if (!is_drawing_path(path)) not_a_drawing(path);  // before reading the file
  return read_drawing(read_text_file(path, kMaxModelFileBytes * 4), path, options);
}

std::size_t segment_count(const LineDrawing& drawing) {
  std::size_t n = 0;
  for (const DrawnLine& l : drawing.lines)
    if (!l.points.empty()) n += l.points.size() - (l.closed ? 0 : 1);
  return n;
}

}  // namespace popcut
