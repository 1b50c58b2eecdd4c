// Strict JSON reading for popcut's file formats: positions for syntax errors, typed field getters.
#pragma once

#include <array>
#include <initializer_list>
#include <vector>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "popcut/names.h"

namespace popcut::json_util {

using nlohmann::json;

// Parses text; syntax errors, duplicate keys and nesting deeper than 64 throw popcut::Error
// naming `source` and the line and column.
json parse(const std::string& text, const std::string& source);

// Field access that names the field path in every error.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& message) const;

  const json& require(const json& object, const char* key, const std::string& path) const;
  void require_object(const json& j, const std::string& path) const;
  void require_array(const json& j, const std::string& path) const;
  // Rejects keys not in `allowed`, naming the first unknown one and listing the allowed ones.
  void only_keys(const json& object, std::initializer_list<const char*> allowed, const std::string& path) const;
  // A whole number in [min, max]; integral floats such as 3.0 are accepted, 3.5 is not.
  int integer(const json& j, const std::string& path, long long min, long long max) const;
  double number(const json& j, const std::string& path, double min, double max) const;
  bool boolean(const json& j, const std::string& path) const;
  std::string string(const json& j, const std::string& path, std::size_t max_length = 4096) const;
  // A string naming one value of `names`; anything else fails with: expected "a", "b" or "c", got "x".
  template <class E, std::size_t N>
  E named(const EnumNames<E, N>& names, const json& j, const std::string& path) const {
    const std::string text = string(j, path);
    if (const auto value = names.find(text)) return *value;
    fail(path, "expected " + names.quoted_list(" or ", '"') + ", got \"" + text + "\"");
  }
  // A list of points, each two numbers within ±limit (mm), at most max_points long.
  std::vector<std::array<double, 2>> points(const json& j, const std::string& path, double limit,
                                            std::size_t min_points, std::size_t max_points) const;
  // A list of at most max_rings such lists (a polygon's holes), together at most max_points long.
  std::vector<std::vector<std::array<double, 2>>> point_rings(const json& j, const std::string& path, double limit,
                                                              std::size_t max_rings, std::size_t max_points) const;
  // The document must be an object with only `allowed` keys and "format" equal to `expected`.
  void require_document(const json& root, const char* expected, std::initializer_list<const char*> allowed) const;

  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

std::string index_path(const std::string& base, std::size_t i);
std::string key_path(const std::string& base, const char* key);

// Shortest text that reads back as the same double.
std::string number_text(double value);
// Points as a JSON list of [a, b] pairs, each number as number_text writes it.
void put_points(std::ostream& o, const std::vector<std::array<double, 2>>& points);
// Rings of points as a JSON list of such lists.
void put_point_rings(std::ostream& o, const std::vector<std::vector<std::array<double, 2>>>& rings);

}  // namespace popcut::json_util
