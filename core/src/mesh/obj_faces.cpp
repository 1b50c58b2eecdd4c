// OBJ faces read strictly: CGAL's reader takes each corner as an int and stops a face at the first it cannot read
// (4294967300, "abc", a tab-separated corner), keeping the corners before it, so bad faces were dropped as degenerate.
#include "mesh/obj_faces.h"

#include <cstdint>
#include <string_view>

#include "popcut/error.h"

namespace popcut {
namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// The whitespace-separated words of a line.
std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// A whole number with an optional sign; false when it is not one or does not fit 18 digits
// (far beyond any vertex count a file under the size limit can hold).
bool parse_index(std::string_view text, std::int64_t& value) {
  std::size_t i = 0;
  bool negative = false;
  if (i < text.size() && (text[i] == '-' || text[i] == '+')) negative = text[i++] == '-';
  if (i == text.size() || text.size() - i > 18) return false;
  std::int64_t v = 0;
  for (; i < text.size(); ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
    v = v * 10 + (text[i] - '0');
  }
  value = negative ? -v : v;
  return true;
}

// What a corner may be: 1 to the file's vertex count, or back to the first vertex so far.
std::string expected(std::int64_t total, std::int64_t defined) {
  std::string out = total > 0 ? "1 to " + std::to_string(total) : "a vertex, but the file has none";
  if (defined > 0)
    out += defined == 1 ? " or -1 counting back" : " or -1 to -" + std::to_string(defined) + " counting back";
  return out;
}

}  // namespace

std::vector<std::vector<std::size_t>> read_obj_faces(const std::string& path, const std::string& bytes) {
  // Positive indices may name any vertex of the file (CGAL's reader, like most, allows a face
  // before its vertices); negative ones count back from where the face stands.
  std::int64_t total = 0;
  for (std::size_t pos = 0; pos < bytes.size();) {
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    const auto words = words_of(std::string_view(bytes).substr(pos, eol - pos));
    if (!words.empty() && words[0] == "v") ++total;
    pos = eol + 1;
  }
  std::vector<std::vector<std::size_t>> faces;
  std::int64_t defined = 0;
  int line_number = 0;
  for (std::size_t pos = 0; pos < bytes.size();) {
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    const auto words = words_of(std::string_view(bytes).substr(pos, eol - pos));
    pos = eol + 1;
    ++line_number;
    if (words.empty()) continue;
    if (words[0] == "v") ++defined;
    if (words[0] != "f") continue;
    const auto fail = [&](const std::string& message) {
      throw Error(ErrorCode::invalid_input, path, "line " + std::to_string(line_number), message);
    };
    std::vector<std::size_t>& face = faces.emplace_back();
    for (std::size_t k = 1; k < words.size(); ++k) {
      const std::string_view corner = words[k].substr(0, words[k].find('/'));
      const std::string shown(corner);
      std::int64_t index = 0;
      if (!parse_index(corner, index)) {
        const bool digits = !shown.empty() && shown.find_first_not_of("+-0123456789") == std::string::npos;
        fail(
            "corner " + std::to_string(k) + " '" + std::string(words[k]) + "': " +
            (digits ? "'" + shown + "' is far larger than any vertex index" : "'" + shown + "' is not a whole number") +
            ": expected a vertex index, " + expected(total, defined));
      }
      if (index == 0) fail("corner " + std::to_string(k) + ": vertex 0 does not exist: OBJ counts vertices from 1");
      if (index > total) {
        fail("face refers to vertex " + shown + ", but the file has only " + std::to_string(total) +
             " vertices: expected " + expected(total, defined));
      }
      if (index < 0 && -index > defined) {
        fail("face refers to vertex " + shown + " (counting back), but only " + std::to_string(defined) +
             " are defined before it: expected " + expected(total, defined));
      }
      face.push_back(static_cast<std::size_t>(index > 0 ? index - 1 : defined + index));
    }
  }
  return faces;
}

}  // namespace popcut
