// Reports for people and scripts: measured figures printed to six significant digits.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

namespace popcut {

// Six significant digits: a micrometre on a metre-long sheet, a millisecond on a 15-minute job.
// The full double (1539.964200146484 mm, 9.00000000000002 s) claims a precision no figure has and
// makes reports of one job differ between machines in the last digits.
inline nlohmann::json rounded_numbers(nlohmann::json j) {
  if (j.is_number_float()) {
    const double v = j.get<double>();
    if (!std::isfinite(v) || v == 0) return j;
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return std::strtod(text, nullptr);
  }
  if (j.is_structured()) {
    for (auto& item : j) item = rounded_numbers(std::move(item));
  }
  return j;
}

}  // namespace popcut
