// Walks PLY and OFF bodies before CGAL reads them, so no list or face count asks for more memory than the file holds.
#include "mesh/mesh_file_check.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string_view>
#include <vector>

#include "popcut/error.h"

namespace popcut {
namespace {

// CGAL's readers resize a face's index vector to the count the file states before reading the
// indices (PLY: PLY_read_typed_list::get; OFF: read_OFF → resize(polygons[i], n)), so one face
// saying 0xffffffff or 1e18 corners would take all the memory there is. Every list entry takes
// at least one byte (binary: its type's size; text: a digit and a separator), so a count larger
// than what is left of the file cannot be true and is refused here, naming the record.

[[noreturn]] void fail(const std::string& path, const std::string& where, const std::string& message) {
  throw Error(ErrorCode::invalid_input, path, where, message);
}

std::string record_name(const std::string& element, std::uint64_t index) {
  return element + " " + std::to_string(index + 1);
}

// ---- PLY ----

struct PlyProperty {
  bool list = false;
  int size = 0;        // scalar size, or a list entry's size
  int count_size = 0;  // a list's count type size
  bool count_signed = false;
  bool item_signed = false;
  bool item_float = false;
  std::string name;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// Size in bytes of a PLY scalar type and whether it is signed; 0 for an unknown name.
int ply_type_size(const std::string& type, bool* is_signed = nullptr) {
  struct Type {
    const char* name;
    int size;
    bool is_signed;
  };
  static const Type types[] = {{"char", 1, true},  {"int8", 1, true},    {"uchar", 1, false},  {"uint8", 1, false},
                               {"short", 2, true}, {"int16", 2, true},   {"ushort", 2, false}, {"uint16", 2, false},
                               {"int", 4, true},   {"int32", 4, true},   {"uint", 4, false},   {"uint32", 4, false},
                               {"float", 4, true}, {"float32", 4, true}, {"double", 8, true},  {"float64", 8, true}};
  for (const Type& t : types) {
    if (type == t.name) {
      if (is_signed) *is_signed = t.is_signed;
      return t.size;
    }
  }
  return 0;
}

// A list count in a binary PLY: the count type's bytes, in the file's byte order.
std::int64_t read_count(const std::string& bytes, std::size_t pos, int size, bool is_signed, bool big_endian) {
  std::uint64_t u = 0;
  for (int k = 0; k < size; ++k) {
    const auto b = static_cast<unsigned char>(bytes[pos + static_cast<std::size_t>(big_endian ? k : size - 1 - k)]);
    u = (u << 8) | b;
  }
  if (is_signed && size < 8 && (u >> (8 * size - 1)) != 0)
    return static_cast<std::int64_t>(u) - (std::int64_t{1} << (8 * size));
  return static_cast<std::int64_t>(u);
}

// The face list CGAL takes for corners, and the vertex count they must stay below.
bool is_corner_list(const PlyElement& e, const PlyProperty& p) {
  return e.name == "face" && p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

std::uint64_t vertex_count(const std::vector<PlyElement>& elements) {
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") return e.count;
  }
  return 0;
}

[[noreturn]] void bad_corner(const std::string& path, const std::string& where, std::uint64_t corner,
                             const std::string& value, std::uint64_t vertices) {
  fail(path, where,
       "corner " + std::to_string(corner + 1) + " is vertex " + value + ", but the file has " +
           std::to_string(vertices) + " vertices: expected " +
           (vertices > 0 ? "0 to " + std::to_string(vertices - 1) : "none, as there are no vertices"));
}

// A binary PLY body from `body`: every record within the file, every corner a vertex.
void walk_ply_binary(const std::string& path, const std::string& bytes, const std::vector<PlyElement>& elements,
                     std::size_t body, bool big) {
  const std::size_t size = bytes.size();
  const std::uint64_t vertices = vertex_count(elements);
  std::size_t at = body;
  const auto truncated = [&](const PlyElement& e, std::uint64_t i) {
    fail(path, record_name(e.name, i),
         "the file ends inside this " + e.name + " (it declares " + std::to_string(e.count) +
             "): the file is truncated");
  };
  for (const PlyElement& e : elements) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        if (!p.list) {
          if (size - at < static_cast<std::size_t>(p.size)) truncated(e, i);
          at += static_cast<std::size_t>(p.size);
          continue;
        }
        if (size - at < static_cast<std::size_t>(p.count_size)) truncated(e, i);
        const std::int64_t n = read_count(bytes, at, p.count_size, p.count_signed, big);
        at += static_cast<std::size_t>(p.count_size);
        const std::uint64_t room = (size - at) / static_cast<std::size_t>(p.size);
        if (n < 0 || static_cast<std::uint64_t>(n) > room) {
          fail(path, record_name(e.name, i),
               "list '" + p.name + "' says " + std::to_string(n) + " entries, but only " + std::to_string(size - at) +
                   " bytes (" + std::to_string(room) +
                   " entries) are left in the file: the file is truncated or corrupt");
        }
        if (is_corner_list(e, p) && !p.item_float) {
          for (std::int64_t k = 0; k < n; ++k) {
            const std::int64_t v =
                read_count(bytes, at + static_cast<std::size_t>(k * p.size), p.size, p.item_signed, big);
            if (v < 0 || static_cast<std::uint64_t>(v) >= vertices) {
              bad_corner(path, record_name(e.name, i), static_cast<std::uint64_t>(k), std::to_string(v), vertices);
            }
          }
        }
        at += static_cast<std::size_t>(n) * static_cast<std::size_t>(p.size);
      }
    }
  }
}

// A text PLY body from `body`: no list claims more numbers than are left, every corner a vertex.
void walk_ply_text(const std::string& path, const std::string& bytes, const std::vector<PlyElement>& elements,
                   std::size_t body) {
  const std::size_t size = bytes.size();
  const std::uint64_t vertices = vertex_count(elements);
  // Text: count the tokens once, then walk them; a list may not claim more than are left.
  const auto is_space = [](char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
  };
  std::uint64_t total = 0;
  for (std::size_t k = body; k < size; ++k) {
    if (!is_space(bytes[k]) && (k == body || is_space(bytes[k - 1]))) ++total;
  }
  std::size_t at = body;
  std::uint64_t used = 0;
  const auto next = [&]() -> std::string_view {
    while (at < size && is_space(bytes[at])) ++at;
    const std::size_t start = at;
    while (at < size && !is_space(bytes[at])) ++at;
    ++used;
    return std::string_view(bytes).substr(start, at - start);
  };
  for (const PlyElement& e : elements) {
    for (std::uint64_t i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        if (used >= total) {
          fail(path, record_name(e.name, i),
               "the file ends inside this " + e.name + " (it declares " + std::to_string(e.count) +
                   "): the file is truncated");
        }
        const std::string_view token = next();
        if (!p.list) continue;
        const std::string text(token);
        char* end = nullptr;
        const double n = std::strtod(text.c_str(), &end);
        const std::uint64_t left = total - used;
        if (end != text.c_str() + text.size() || !(n >= 0) || n != std::floor(n) || n > static_cast<double>(left)) {
          fail(path, record_name(e.name, i),
               "list '" + p.name + "' says '" + text + "' entries, but only " + std::to_string(left) +
                   " numbers are left in the file: expected a whole number of entries that follow");
        }
        for (std::uint64_t k = 0; k < static_cast<std::uint64_t>(n); ++k) {
          const std::string_view entry = next();
          if (!is_corner_list(e, p)) continue;
          const std::string value(entry);
          const double v = std::strtod(value.c_str(), &end);
          if (end != value.c_str() + value.size() || !(v >= 0) || v != std::floor(v) ||
              v >= static_cast<double>(vertices)) {
            bad_corner(path, record_name(e.name, i), k, "'" + value + "'", vertices);
          }
        }
      }
    }
  }
}

void check_ply(const std::string& path, const std::string& bytes) {
  std::size_t pos = 0;
  std::string format;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (pos < bytes.size()) {
    std::size_t eol = bytes.find('\n', pos);
    if (eol == std::string::npos) eol = bytes.size();
    std::istringstream words(bytes.substr(pos, eol - pos));
    pos = eol + 1;
    std::string keyword;
    words >> keyword;
    if (keyword == "end_header") {
      ended = true;
      break;
    }
    if (keyword == "format") {
      words >> format;
    } else if (keyword == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      if (!words) return;  // CGAL reports the malformed header
      elements.push_back(e);
    } else if (keyword == "property" && !elements.empty()) {
      PlyProperty p;
      std::string type;
      words >> type;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type >> p.name;
        p.list = true;
        p.count_size = ply_type_size(count_type, &p.count_signed);
        p.size = ply_type_size(item_type, &p.item_signed);
        p.item_float = item_type.find("float") != std::string::npos || item_type.find("double") != std::string::npos;
        if (p.count_size == 0 || p.size == 0) return;  // an unknown type: CGAL reports it
      } else {
        words >> p.name;
        p.size = ply_type_size(type);
        if (p.size == 0) return;
      }
      elements.back().properties.push_back(p);
    }
  }
  if (!ended) return;  // CGAL reports the missing end_header
  const std::size_t body = pos;
  const std::size_t size = bytes.size();

  // Elements without properties take no bytes; CGAL would still loop over their count.
  for (const PlyElement& e : elements) {
    if (e.properties.empty() && e.count > size) {
      fail(path, "header",
           "element '" + e.name + "' has no properties but a count of " + std::to_string(e.count) +
               ", more than the file's " + std::to_string(size) + " bytes: the file is corrupt");
    }
  }

  if (format == "binary_little_endian" || format == "binary_big_endian") {
    walk_ply_binary(path, bytes, elements, body, format == "binary_big_endian");
  } else if (format == "ascii") {
    walk_ply_text(path, bytes, elements, body);
  }  // else CGAL reports an unknown format
}

// ---- OFF ----

std::string strip_comment(std::string line) {
  const std::size_t hash = line.find('#');
  if (hash != std::string::npos) line.erase(hash);
  return line;
}

std::uint32_t read_be32(const std::string& bytes, std::size_t pos) {
  std::uint32_t u = 0;
  for (int k = 0; k < 4; ++k) u = (u << 8) | static_cast<unsigned char>(bytes[pos + static_cast<std::size_t>(k)]);
  return u;
}

// What an OFF header says: the keyword ([ST][C][N][4][n]OFF, maybe followed by BINARY), then vertex,
// face and edge counts, on one line or several. `checked` false: a layout left to CGAL.
struct OffHeader {
  bool checked = true;
  bool binary = false;
  std::string keyword;
  std::vector<std::string> counts;
  int line_number = 0;  // the last header line read
};

OffHeader read_off_header(std::istringstream& in) {
  OffHeader h;
  for (std::string line; std::getline(in, line);) {
    ++h.line_number;
    std::istringstream words(strip_comment(line));
    for (std::string w; words >> w;) {
      if (h.keyword.empty()) {
        h.keyword = w;
        // Not OFF: CGAL reports it. nOFF (a dimension first, rare) is left to CGAL too.
        if (w.find("OFF") == std::string::npos || w.find('n') != std::string::npos) h.checked = false;
        if (!h.checked) return h;
      } else if (w == "BINARY" && h.counts.empty()) {
        h.binary = true;
        return h;  // binary counts follow the newline
      } else {
        h.counts.push_back(w);
      }
    }
    if (h.counts.size() >= 3) return h;
  }
  return h;
}

// Binary OFF from `at`: big-endian counts, 3 float coordinates a vertex, then each face's corner
// count and corners, colour count and components.
void walk_off_binary(const std::string& path, const std::string& bytes, std::size_t at) {
  const std::size_t size = bytes.size();
  if (size - at < 12) return;  // CGAL reports the short header
  const std::uint32_t vertices = read_be32(bytes, at), faces = read_be32(bytes, at + 4);
  at += 12;
  if (std::uint64_t{vertices} * 12 > size - at) {
    fail(path, "header",
         "declares " + std::to_string(vertices) + " vertices, more than the file's " + std::to_string(size) +
             " bytes can hold: the file is truncated or corrupt");
  }
  at += std::size_t{vertices} * 12;
  for (std::uint32_t f = 0; f < faces; ++f) {
    for (int part = 0; part < 2; ++part) {  // the corners, then the colour components
      if (size - at < 4) fail(path, record_name("face", f), "the file ends inside this face: the file is truncated");
      const auto n = static_cast<std::int32_t>(read_be32(bytes, at));
      at += 4;
      if (n < 0 || static_cast<std::uint64_t>(n) > (size - at) / 4) {
        fail(path, record_name("face", f),
             std::string(part == 0 ? "says " : "has ") + std::to_string(n) +
                 (part == 0 ? " corners" : " colour components") + ", but only " + std::to_string((size - at) / 4) +
                 " numbers are left in the file: the file is truncated or corrupt");
      }
      for (std::int32_t k = 0; part == 0 && k < n; ++k) {
        const auto v = static_cast<std::int32_t>(read_be32(bytes, at + static_cast<std::size_t>(k) * 4));
        if (v < 0 || static_cast<std::uint32_t>(v) >= vertices) {
          bad_corner(path, record_name("face", f), static_cast<std::uint64_t>(k), std::to_string(v), vertices);
        }
      }
      at += static_cast<std::size_t>(n) * 4;
    }
  }
}

// Text OFF after the header: one vertex a line, then one face a line ("n i1 … in [colour]"); CGAL
// reads a face's whole line and sizes the face by its first number, so that number may not exceed
// the numbers on the line.
void walk_off_text(const std::string& path, std::istringstream& in, const OffHeader& h) {
  std::uint64_t vertices = 0, faces = 0;
  try {
    vertices = std::stoull(h.counts[0]);
    faces = std::stoull(h.counts[1]);
  } catch (const std::exception&) {
    return;  // CGAL reports it
  }
  int line_number = h.line_number;
  std::uint64_t record = 0;
  for (std::string line; record < vertices + faces && std::getline(in, line);) {
    ++line_number;
    std::istringstream words(strip_comment(line));
    std::vector<std::string> numbers;
    for (std::string w; words >> w;) numbers.push_back(w);
    if (numbers.empty()) continue;
    if (record++ < vertices) continue;
    const std::uint64_t face = record - vertices - 1;
    char* end = nullptr;
    const double n = std::strtod(numbers[0].c_str(), &end);
    if (end != numbers[0].c_str() + numbers[0].size() || !(n >= 0) || n != std::floor(n) ||
        n > static_cast<double>(numbers.size() - 1)) {
      fail(path, "line " + std::to_string(line_number) + " (" + record_name("face", face) + ")",
           "says '" + numbers[0] + "' corners, but the line has " + std::to_string(numbers.size() - 1) +
               " more numbers: expected the corner count, then that many vertex indices");
    }
    for (std::size_t k = 1; k <= static_cast<std::size_t>(n); ++k) {
      const double v = std::strtod(numbers[k].c_str(), &end);
      if (end != numbers[k].c_str() + numbers[k].size() || !(v >= 0) || v != std::floor(v) ||
          v >= static_cast<double>(vertices)) {
        bad_corner(path, "line " + std::to_string(line_number) + " (" + record_name("face", face) + ")", k - 1,
                   "'" + numbers[k] + "'", vertices);
      }
    }
  }
}

void check_off(const std::string& path, const std::string& bytes) {
  std::istringstream in(bytes);
  const OffHeader h = read_off_header(in);
  if (!h.checked) return;
  if (h.binary) {
    // Only the plain layout (3 float coordinates a vertex) is walked; CGAL's big-endian int32
    // face counts would be negative or huge otherwise.
    if (h.keyword != "OFF" || in.tellg() < 0) return;
    walk_off_binary(path, bytes, static_cast<std::size_t>(in.tellg()));
  } else if (h.counts.size() >= 3) {
    walk_off_text(path, in, h);
  }
}

}  // namespace

void check_mesh_list_counts(const std::string& path, const std::string& ext, const std::string& bytes) {
  if (ext == "ply") check_ply(path, bytes);
  if (ext == "off") check_off(path, bytes);
}

}  // namespace popcut
