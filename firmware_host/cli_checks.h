// Command-line value checks that CLI11 lacks.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace popcut::cli {

// CLI::Range lets "nan" through (every comparison with NaN is false), and a NaN slowdown spins the
// simulator forever; this range accepts finite numbers only.
inline CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        if (!std::isfinite(v) || v < lo || v > hi) {
          return "'" + text + "' is not a number from " + CLI::detail::to_string(lo) + " to " + CLI::detail::to_string(hi);
        }
        return {};
      },
      "NUMBER in [" + CLI::detail::to_string(lo) + " - " + CLI::detail::to_string(hi) + "]");
}

}  // namespace popcut::cli
