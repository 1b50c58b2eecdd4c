// The knife keys a line kind shares between [tool.KIND] in profiles and a material's kinds: force, speed, passes.
#pragma once

#include "popcut/drivers/toml_section.h"
#include "popcut/lang/encoder.h"
#include "popcut/plan/plan.h"

namespace popcut::drivers {

// passes (1–10), then pass_force_g and pass_speed_cm_s: one value per pass, each in force_g's or
// speed_cm_s's range. Either list makes the passes separate strokes (KindPlan::separate_passes),
// each cut with its own values; without them every pass uses force_g and speed_cm_s.
void read_passes(TomlSection& s, ToolSetting& tool, KindPlan& kind);

inline constexpr double kMinForceG = 1, kMaxForceG = 2000;
inline constexpr double kMinSpeedCmS = 0.1, kMaxSpeedCmS = 200;

}  // namespace popcut::drivers
