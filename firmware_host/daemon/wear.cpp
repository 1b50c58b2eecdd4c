// Wear counted per stroke from a job's plan: knife-down lengths by mode, and the strokes a run may claim.
#include "wear.h"

#include <algorithm>

#include "popcut/plan/tool_paths.h"

namespace popcut::daemon {

Wear& Wear::operator+=(const Wear& o) {
  cut_mm += o.cut_mm;
  score_mm += o.score_mm;
  perforate_mm += o.perforate_mm;
  knife_down_strokes += o.knife_down_strokes;
  return *this;
}

Wear wear_of(const StrokePlan& plan, const std::array<KindPlan, 4>& kinds, std::size_t first, std::size_t last) {
  Wear w;
  last = std::min(last, plan.strokes.size());
  for (std::size_t n = std::max<std::size_t>(first, 1); n <= last; ++n) {
    const Stroke& s = plan.strokes[n - 1];
    const double mm = path_length_mm(s.points);
    switch (kinds[index_of(s.kind)].mode) {
      case ToolMode::score: w.score_mm += mm; break;
      case ToolMode::perforate: w.perforate_mm += mm; break;
      case ToolMode::cut:
      case ToolMode::skip: w.cut_mm += mm; break;  // skip: never planned, so never here
    }
    ++w.knife_down_strokes;
  }
  return w;
}

std::size_t wear_counted_through(const CutOutcome& out, std::size_t first_stroke) {
  const std::size_t none = first_stroke - 1;
  if (out.kind == CutOutcome::Kind::complete) return std::max(out.last_stroke_sent, none);
  if (out.last_stroke_executed) return std::max(*out.last_stroke_executed, none);
  return std::max(out.last_stroke_sent, none);
}

bool blade_worn(const DeviceWear& w, std::optional<double> blade_life_m) {
  return blade_life_m && w.blade.cut_mm >= *blade_life_m * 1000;
}

}  // namespace popcut::daemon
