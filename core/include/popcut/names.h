// One table per enum that maps its values to the names people and files use, and back.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace popcut {

// A fixed table of (value, name) pairs. Every enum that is written or read by name has exactly one
// of these next to its declaration; to_string, parsing and "expected one of ..." messages all read
// it, so adding a value is one line and the three can never disagree.
template <class E, std::size_t N>
struct EnumNames {
  std::array<std::pair<E, std::string_view>, N> entries;

  // The value's name; an empty view for a value missing from the table (a bug the tests catch).
  constexpr std::string_view name(E value) const {
    for (const auto& [v, n] : entries) {
      if (v == value) return n;
    }
    return {};
  }
  // The value with this exact (case-sensitive) name, if any.
  constexpr std::optional<E> find(std::string_view text) const {
    for (const auto& [v, n] : entries) {
      if (n == text) return v;
    }
    return std::nullopt;
  }
  // "a, b or c": the names in table order, for messages.
  std::string list(std::string_view last_joint = " or ") const {
    std::string out;
    for (std::size_t i = 0; i < N; ++i) {
      if (i > 0) out += (i + 1 == N) ? last_joint : std::string_view(", ");
      out += entries[i].second;
    }
    return out;
  }
  // "'a', 'b' or 'c'": the names quoted, for messages about a value in a file; JSON readers pass
  // quote '"' so the names read as the strings the file holds.
  std::string quoted_list(std::string_view last_joint = " or ", char quote = '\'') const {
    std::string out;
    for (std::size_t i = 0; i < N; ++i) {
      if (i > 0) out += (i + 1 == N) ? last_joint : std::string_view(", ");
      out += quote;
      out += entries[i].second;
      out += quote;
    }
    return out;
  }
};

// Deduces N: `constexpr auto kNames = enum_names<Colour>({{{Colour::red, "red"}, ...}});`
template <class E, std::size_t N>
constexpr EnumNames<E, N> enum_names(const std::pair<E, std::string_view> (&entries)[N]) {
  EnumNames<E, N> table{};
  for (std::size_t i = 0; i < N; ++i) table.entries[i] = entries[i];
  return table;
}

}  // namespace popcut
