// One planning path for every caller that sends to a device (popcut cut, popcutd's planners).
#include "popcut/drivers/device_plan.h"

#include "popcut/drivers/language.h"
#include "popcut/error.h"

namespace popcut::drivers {

DevicePlan plan_for_device(const Pattern& pattern, const DeviceProfile& profile, const std::string& profile_source) {
  DevicePlan d;
  d.plan = plan_strokes(pattern, profile.plan);
  try {
    // Figures and the time estimate count only what is sent: strokes that round to one plotter
    // point are not.
    d.plan = drop_below_resolution(d.plan, profile.dialect);
    // Each stroke at its own speed: a kind's passes may differ.
    d.time = estimate_time(d.plan, profile.kinematics,
                           [&](const Stroke& s) { return tool_for_stroke(profile.tools, s).speed_cm_s * 10; });
    d.encoded = encode_for_device(d.plan, profile);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    throw Error(e.code(), profile_source, e.location(), e.message());
  }
  return d;
}

NamedMedia media_of(const DeviceProfile& profile, const std::string& name) {
  const HpglDialect& d = profile.dialect;
  const double margin_mm = 2 * profile.plan.blade_offset_mm;
  const double x_mm = static_cast<double>(d.area_max_x_pu - d.area_min_x_pu - 1) / d.units_per_mm_x - margin_mm;
  const double y_mm = static_cast<double>(d.area_max_y_pu - d.area_min_y_pu - 1) / d.units_per_mm_y - margin_mm;
  return d.swap_axes ? NamedMedia{name, y_mm, x_mm} : NamedMedia{name, x_mm, y_mm};
}

}  // namespace popcut::drivers
