// Reports for people and scripts: measured figures to the micrometre or millisecond.
#pragma once

#include <cmath>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "popcut/text.h"

namespace popcut {

// Three decimals (a micrometre in mm, a millisecond in s; unix times keep their milliseconds),
// six significant digits below 1 (shares, small times). The full double (1539.964200146484 mm,
// 9.00000000000002 s) claims a precision no figure has and makes reports of one job differ
// between machines in the last digits.
inline nlohmann::json rounded_numbers(nlohmann::json j) {
  if (j.is_number_float()) {
    const double v = j.get<double>();
    if (!std::isfinite(v) || v == 0) return j;
    if (std::abs(v) >= 1) return std::round(v * 1000) / 1000;
    return std::strtod(format_significant(v, 6).c_str(), nullptr);
  }
  if (j.is_structured()) {
    for (auto& item : j) item = rounded_numbers(std::move(item));
  }
  return j;
}

}  // namespace popcut
