// Typed, range-checked reading of one TOML section; every key read is remembered so the rest are refused.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <toml++/toml.h>

#include "popcut/error.h"
#include "popcut/names.h"
#include "popcut/text.h"

namespace popcut::drivers {

// Errors name the file, "[section] key" and what was expected (Klipper's style: each section is
// read by its owner). Shared by device profiles and the daemon's configuration.
class TomlSection {
 public:
  TomlSection(const toml::table* table, std::string name, std::string source)
      : table_(table), name_(std::move(name)), source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw Error(ErrorCode::invalid_input, source_, "[" + name_ + "] " + key, message);
  }

  const toml::node* node(const std::string& key) {
    seen_.insert(key);
    return table_ ? table_->get(key) : nullptr;
  }

  double number(const std::string& key, double fallback, double lo, double hi) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    if (!n->is_number()) fail(key, "expected a number");
    const double v = n->value<double>().value_or(0);
    if (!std::isfinite(v) || v < lo || v > hi)
      fail(key, format_significant(v) + " is out of range " + format_significant(lo) + " to " + format_significant(hi));
    return v;
  }
  std::optional<double> optional_number(const std::string& key, double lo, double hi) {
    if (!node(key)) return std::nullopt;
    return number(key, 0, lo, hi);
  }
  int integer(const std::string& key, int fallback, int lo, int hi) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    if (!n->is_integer()) fail(key, "expected a whole number");
    const std::int64_t v = n->value<std::int64_t>().value_or(0);
    if (v < lo || v > hi)
      fail(key, std::to_string(v) + " is out of range " + std::to_string(lo) + " to " + std::to_string(hi));
    return static_cast<int>(v);
  }
  bool boolean(const std::string& key, bool fallback) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    if (!n->is_boolean()) fail(key, "expected true or false");
    return n->value<bool>().value_or(false);
  }
  std::string text(const std::string& key, const std::string& fallback, std::size_t max_len = 256) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    if (!n->is_string()) fail(key, "expected a string");
    std::string s = n->value<std::string>().value_or("");
    if (s.size() > max_len) fail(key, "longer than " + std::to_string(max_len) + " bytes");
    return s;
  }
  // One of the table's names; returns its value. Messages list the names in table order.
  template <class E, std::size_t N>
  E choice(const std::string& key, E fallback, const EnumNames<E, N>& table) {
    const toml::node* n = node(key);
    if (!n) return fallback;
    const std::string allowed = table.quoted_list(", ", '"');
    if (!n->is_string()) fail(key, "expected one of " + allowed);
    const std::string s = n->value<std::string>().value_or("");
    if (const std::optional<E> value = table.find(s)) return *value;
    fail(key, "\"" + s + "\" is not one of " + allowed);
  }
  const toml::array* array(const std::string& key) {
    const toml::node* n = node(key);
    if (n && !n->is_array()) fail(key, "expected an array");
    return n ? n->as_array() : nullptr;
  }
  void reject_unknown() const {
    if (!table_) return;
    for (const auto& [k, v] : *table_) {
      if (!seen_.count(std::string(k.str()))) fail(std::string(k.str()), "unknown key");
    }
  }

 private:
  const toml::table* table_;
  std::string name_, source_;
  std::set<std::string> seen_;
};

// Parses a whole TOML document; syntax errors name `source`, line and column.
inline toml::table parse_toml(const std::string& text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw Error(ErrorCode::invalid_input, source,
                "line " + std::to_string(b.line) + ", column " + std::to_string(b.column),
                std::string(e.description()));
  }
}

}  // namespace popcut::drivers
