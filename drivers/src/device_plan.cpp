// One planning path for every caller that sends to a device (popcut cut, popcutd's planners).
#include "popcut/drivers/device_plan.h"

#include "popcut/error.h"

namespace popcut::drivers {

DevicePlan plan_for_device(const Pattern& pattern, const DeviceProfile& profile, const std::string& profile_source) {
  DevicePlan d;
  d.plan = plan_strokes(pattern, profile.plan);
  try {
    // Figures and the time estimate count only what is sent: strokes that round to one plotter
    // point are not.
    d.plan = drop_below_resolution(d.plan, profile.dialect);
    d.time = estimate_time(d.plan, profile.kinematics, profile.cut_speed_mm_s());
    d.encoded = encode_job(d.plan, profile.dialect, profile.tools);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    throw Error(e.code(), profile_source, e.location(), e.message());
  }
  return d;
}

}  // namespace popcut::drivers
