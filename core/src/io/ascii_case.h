// Case folding for names in drawings (layers, linetypes, units): ASCII letters only, UTF-8 bytes kept.
#pragma once

#include <algorithm>
#include <cctype>
#include <string>

namespace popcut {

inline std::string ascii_lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return c < 128 ? static_cast<char>(std::tolower(c)) : static_cast<char>(c); });
  return s;
}

inline std::string ascii_upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return c < 128 ? static_cast<char>(std::toupper(c)) : static_cast<char>(c); });
  return s;
}

}  // namespace popcut
