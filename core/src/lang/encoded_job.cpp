// EncodedJob's lookups from "bytes sent" to strokes and command boundaries, the same for every language.
#include <algorithm>

#include "popcut/lang/encoder.h"

namespace popcut {

std::size_t EncodedJob::last_stroke_within(std::size_t bytes_sent) const {
  const auto it = std::upper_bound(stroke_end.begin(), stroke_end.end(), bytes_sent);
  return first_stroke - 1 + static_cast<std::size_t>(it - stroke_end.begin());
}

std::size_t EncodedJob::command_boundary_at_or_after(std::size_t offset) const {
  if (offset == 0) return 0;  // before the first command
  const auto it = std::lower_bound(command_end.begin(), command_end.end(), offset);
  return it == command_end.end() ? bytes.size() : *it;
}

ToolSetting tool_for_stroke(const std::array<ToolSetting, 4>& tools, const Stroke& stroke) {
  const ToolSetting& kind = tools[index_of(stroke.kind)];
  const auto pass_value = [&](const std::vector<double>& per_pass, double fallback) {
    const auto pass = static_cast<std::size_t>(std::max(0, stroke.pass));
    return pass < per_pass.size() ? per_pass[pass] : fallback;
  };
  return {
      kind.pen, pass_value(kind.pass_force_g, kind.force_g), pass_value(kind.pass_speed_cm_s, kind.speed_cm_s), {}, {}};
}

}  // namespace popcut
