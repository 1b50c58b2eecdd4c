// Strict JSON parsing and typed getters shared by the model and pattern readers.
#include "io/json_util.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <set>
#include <vector>

#include "popcut/error.h"

namespace popcut::json_util {
namespace {

constexpr int kMaxDepth = 64;

std::string position(const std::string& text, std::size_t byte) {
  // nlohmann reports the 1-based byte where parsing stopped.
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

std::string type_name(const json& j) {
  if (j.is_number_integer()) return "an integer";
  if (j.is_number()) return "a number";
  const std::string name = j.type_name();
  return (name == "array" || name == "object" ? "an " : "a ") + name;
}

}  // namespace

json parse(const std::string& text, const std::string& source) {
  std::vector<std::set<std::string>> keys;
  auto check = [&](int depth, json::parse_event_t event, json& parsed) {
    if (depth > kMaxDepth) {
      throw Error(ErrorCode::invalid_input, source, "",
                  "JSON nested deeper than " + std::to_string(kMaxDepth) + " levels");
    }
    switch (event) {
      case json::parse_event_t::object_start: keys.emplace_back(); break;
      case json::parse_event_t::object_end: keys.pop_back(); break;
      case json::parse_event_t::key:
        if (!keys.back().insert(parsed.get<std::string>()).second) {
          throw Error(ErrorCode::invalid_input, source, "",
                      "duplicate key \"" + parsed.get<std::string>() + "\" in one object");
        }
        break;
      default: break;
    }
    return true;
  };
  try {
    return json::parse(text, check);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    // Keep nlohmann's explanation, drop its "[json.exception.parse_error.101] parse error at line 1, column 2:" prefix.
    const auto colon = what.find(": ", what.find("parse error"));
    if (colon != std::string::npos) what = what.substr(colon + 2);
    throw Error(ErrorCode::invalid_input, source, position(text, e.byte), "malformed JSON: " + what);
  } catch (const json::exception& e) {
    // Anything else the parser rejects (a number like 1e400 that overflows a double) is still bad input.
    std::string what = e.what();
    const auto bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    // The parser names the token ("number overflow parsing '1e999'") but not where it is: find
    // the first place it stands as a whole token (not inside a longer number or a word).
    std::string where;
    const auto open = what.find('\''), close = what.rfind('\'');
    if (open != std::string::npos && close > open + 1) {
      const std::string token = what.substr(open + 1, close - open - 1);
      const auto is_token_char = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+';
      };
      for (auto at = text.find(token); at != std::string::npos; at = text.find(token, at + 1)) {
        const std::size_t end = at + token.size();
        if ((at == 0 || !is_token_char(text[at - 1])) && (end == text.size() || !is_token_char(text[end]))) {
          where = position(text, at + 1);
          break;
        }
      }
    }
    throw Error(ErrorCode::invalid_input, source, where, "malformed JSON: " + what);
  }
}

void Reader::fail(const std::string& field, const std::string& message) const {
  throw Error(ErrorCode::invalid_input, source_, field, message);
}

const json& Reader::require(const json& object, const char* key, const std::string& path) const {
  auto it = object.find(key);
  if (it == object.end()) fail(key_path(path, key), "is missing");
  return *it;
}

void Reader::require_object(const json& j, const std::string& path) const {
  if (!j.is_object()) fail(path, "expected an object, got " + type_name(j));
}

void Reader::require_array(const json& j, const std::string& path) const {
  if (!j.is_array()) fail(path, "expected an array, got " + type_name(j));
}

void Reader::only_keys(const json& object, std::initializer_list<const char*> allowed, const std::string& path) const {
  for (auto it = object.begin(); it != object.end(); ++it) {
    bool known = false;
    for (const char* a : allowed) known = known || it.key() == a;
    if (known) continue;
    std::string list;
    for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
    fail(key_path(path, it.key().c_str()), "unknown field (expected one of: " + list + ")");
  }
}

int Reader::integer(const json& j, const std::string& path, long long min, long long max) const {
  const std::string expected = "expected a whole number from " + std::to_string(min) + " to " + std::to_string(max);
  long long value = 0;
  if (j.is_number_integer()) {
    if (j.is_number_unsigned()) {
      const auto u = j.get<unsigned long long>();
      if (u > static_cast<unsigned long long>(max)) fail(path, expected + ", got " + std::to_string(u));
      value = static_cast<long long>(u);
    } else {
      value = j.get<long long>();
    }
  } else if (j.is_number_float()) {
    const double d = j.get<double>();
    if (!std::isfinite(d) || d != std::floor(d) || d < static_cast<double>(min) || d > static_cast<double>(max)) {
      fail(path, expected + ", got " + j.dump());
    }
    value = static_cast<long long>(d);
  } else {
    fail(path, expected + ", got " + type_name(j));
  }
  if (value < min || value > max) fail(path, expected + ", got " + std::to_string(value));
  return static_cast<int>(value);
}

double Reader::number(const json& j, const std::string& path, double min, double max) const {
  if (!j.is_number())
    fail(path, "expected a number from " + number_text(min) + " to " + number_text(max) + ", got " + type_name(j));
  const double d = j.get<double>();
  if (!std::isfinite(d) || d < min || d > max) {
    fail(path, "expected a number from " + number_text(min) + " to " + number_text(max) + ", got " + j.dump());
  }
  return d;
}

std::string Reader::string(const json& j, const std::string& path, std::size_t max_length) const {
  if (!j.is_string()) fail(path, "expected a string, got " + type_name(j));
  const auto& s = j.get_ref<const std::string&>();
  if (s.size() > max_length) fail(path, "is longer than " + std::to_string(max_length) + " bytes");
  return s;
}

bool Reader::boolean(const json& j, const std::string& path) const {
  if (!j.is_boolean()) fail(path, "expected true or false");
  return j.get<bool>();
}

std::vector<std::array<double, 2>> Reader::points(const json& j, const std::string& path, double limit,
                                                  std::size_t min_points, std::size_t max_points) const {
  require_array(j, path);
  if (j.size() < min_points) fail(path, "needs at least " + std::to_string(min_points) + " points");
  if (j.size() > max_points) fail(path, "has more than " + std::to_string(max_points) + " points");
  std::vector<std::array<double, 2>> out;
  out.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string p = index_path(path, i);
    if (!j[i].is_array() || j[i].size() != 2) fail(p, "expected a point: two numbers in mm");
    out.push_back({number(j[i][0], index_path(p, 0), -limit, limit), number(j[i][1], index_path(p, 1), -limit, limit)});
  }
  return out;
}

std::vector<std::vector<std::array<double, 2>>> Reader::point_rings(const json& j, const std::string& path,
                                                                    double limit, std::size_t max_rings,
                                                                    std::size_t max_points) const {
  require_array(j, path);
  if (j.size() > max_rings) fail(path, "has more than " + std::to_string(max_rings) + " rings");
  std::vector<std::vector<std::array<double, 2>>> out;
  std::size_t total = 0;
  for (std::size_t k = 0; k < j.size(); ++k) {
    out.push_back(points(j[k], index_path(path, k), limit, 3, max_points - total));
    total += out.back().size();
  }
  return out;
}

void Reader::require_document(const json& root, const char* expected,
                              std::initializer_list<const char*> allowed) const {
  require_object(root, "document");
  // The tag first: a file of another format is named as such, not as a list of unknown fields.
  const std::string format = string(require(root, "format", ""), "format");
  if (format != expected) fail("format", "expected \"" + std::string(expected) + "\", got \"" + format + "\"");
  only_keys(root, allowed, "");
}

std::string index_path(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }

std::string key_path(const std::string& base, const char* key) { return base.empty() ? key : base + "." + key; }

std::string number_text(double value) {
  if (value == 0) value = 0;  // no "-0" in files
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, value).ptr;
  return std::string(buf, end);
}

void put_points(std::ostream& o, const std::vector<std::array<double, 2>>& points) {
  o << "[";
  for (std::size_t i = 0; i < points.size(); ++i)
    o << (i ? ", " : "") << "[" << number_text(points[i][0]) << ", " << number_text(points[i][1]) << "]";
  o << "]";
}

void put_point_rings(std::ostream& o, const std::vector<std::vector<std::array<double, 2>>>& rings) {
  o << "[";
  for (std::size_t k = 0; k < rings.size(); ++k) {
    if (k) o << ", ";
    put_points(o, rings[k]);
  }
  o << "]";
}

}  // namespace popcut::json_util
