// A pattern planned for one device profile exactly as it will be sent: the figures `popcut cut` and popcutd report.
#pragma once

#include <string>

#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/mesh/import_request.h"
#include "popcut/pattern/pattern.h"
#include "popcut/plan/plan.h"

namespace popcut::drivers {

struct DevicePlan {
  StrokePlan plan;     // strokes below the plotter's resolution dropped: what is sent
  TimeEstimate time;   // of `plan`, with the profile's kinematics and speeds
  EncodedJob encoded;  // the whole job, from stroke 1
};

// plan_strokes -> drop_below_resolution -> estimate_time -> encode_for_device (in the profile's
// language). A sheet that does not fit the device's usable area throws popcut::Error(invalid_input)
// naming `profile_source`: the pattern is fine, it is this device that is too small.
DevicePlan plan_for_device(const Pattern& pattern, const DeviceProfile& profile, const std::string& profile_source);

// The largest sheet the device takes, as plan_for_device places it: the usable area with the
// sheet's x along the plotter's x (its y with swap_axes), less the blade offset on every side
// (a drag knife's corner arcs reach that far past the sheet's edge) and one plotter unit for rounding.
NamedMedia media_of(const DeviceProfile& profile, const std::string& name);

}  // namespace popcut::drivers
