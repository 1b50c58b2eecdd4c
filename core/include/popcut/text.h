// Numbers as people write them in messages and text formats: the one formatter every unit uses.
#pragma once

#include <cstdio>
#include <string>

namespace popcut {

// Fixed decimals, trailing zeros cut: format_decimal(12.5, 3) == "12.5", format_decimal(2.0, 3)
// == "2", never "-0".
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

// Fixed decimals, zeros kept, for columns and file formats that want them: format_fixed(2.0, 1)
// == "2.0", and a value that rounds to zero is "0.0", never "-0.0".
inline std::string format_fixed(double value, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  std::string s = buf;
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

// At most `digits` significant digits, as printf's %g writes them: format_significant(0.1, 6) ==
// "0.1", format_significant(1e-7, 6) == "1e-07". For values whose scale is not known in advance.
inline std::string format_significant(double value, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

// Decimal text as people write numbers ("90", "-45.5", "1e2"): std::stod alone would also take
// "0x5A", "inf" and "nan".
inline bool is_decimal_text(const std::string& text) {
  return !text.empty() && text.find_first_not_of("0123456789.+-eE") == std::string::npos &&
         text.find_first_of("0123456789") != std::string::npos;
}

}  // namespace popcut
