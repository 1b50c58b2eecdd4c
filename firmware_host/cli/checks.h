// Command-line value checks that CLI11 lacks.
#pragma once

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
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
          return "'" + text + "' is not a number from " + CLI::detail::to_string(lo) + " to " +
                 CLI::detail::to_string(hi);
        }
        return {};
      },
      "NUMBER in [" + CLI::detail::to_string(lo) + " - " + CLI::detail::to_string(hi) + "]");
}

// A positive whole number such as a job id. CLI::PositiveNumber's message spells out its upper
// bound (DBL_MAX, 300 digits) and lets "1.5" through.
inline CLI::Validator positive_whole(const std::string& what) {
  return CLI::Validator(
      [what](std::string& text) -> std::string {
        long long v = 0;
        const char* end = text.c_str() + text.size();
        char* stop = nullptr;
        errno = 0;
        v = std::strtoll(text.c_str(), &stop, 10);
        if (text.empty() || stop != end || errno == ERANGE || v < 1)
          return "'" + text + "' is not " + what + " (a whole number from 1)";
        return {};
      },
      "WHOLE NUMBER >= 1");
}

}  // namespace popcut::cli
