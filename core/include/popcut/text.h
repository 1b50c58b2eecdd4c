// Numbers as people write them in messages and text formats: fixed decimals, trailing zeros cut.
#pragma once

#include <cstdio>
#include <string>

namespace popcut {

// format_decimal(12.5, 3) == "12.5", format_decimal(2.0, 3) == "2", never "-0".
inline std::string format_decimal(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s == "-0" ? "0" : s;
}

}  // namespace popcut
