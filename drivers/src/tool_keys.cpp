// Per-pass force and speed lists, read the same way for device profiles and materials.
#include "tool_keys.h"

#include <string>
#include <vector>

namespace popcut::drivers {
namespace {

// `key`'s list: exactly `passes` numbers in lo..hi; empty when the key is absent.
std::vector<double> per_pass(TomlSection& s, const std::string& key, int passes, double lo, double hi) {
  const toml::array* list = s.array(key);
  if (!list) return {};
  const auto count = static_cast<std::size_t>(passes);
  if (list->size() != count) {
    s.fail(key, "has " + std::to_string(list->size()) + " values for " + std::to_string(passes) +
                    " passes (passes = " + std::to_string(passes) + "): give one per pass");
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < count; ++i) {
    const toml::node& n = *list->get(i);
    const std::string which = "value " + std::to_string(i + 1) + " (pass " + std::to_string(i + 1) + ")";
    if (!n.is_number()) s.fail(key, which + ": expected a number");
    const double v = n.value<double>().value_or(0);
    if (!std::isfinite(v) || v < lo || v > hi) {
      s.fail(key, which + ": " + format_significant(v) + " is out of range " + format_significant(lo) + " to " +
                      format_significant(hi));
    }
    out.push_back(v);
  }
  return out;
}

}  // namespace

void read_passes(TomlSection& s, ToolSetting& tool, KindPlan& kind) {
  kind.passes = s.integer("passes", 1, 1, 10);
  tool.pass_force_g = per_pass(s, "pass_force_g", kind.passes, kMinForceG, kMaxForceG);
  tool.pass_speed_cm_s = per_pass(s, "pass_speed_cm_s", kind.passes, kMinSpeedCmS, kMaxSpeedCmS);
  kind.separate_passes = !tool.pass_force_g.empty() || !tool.pass_speed_cm_s.empty();
}

}  // namespace popcut::drivers
