// Motion schedule: runs the simulated cutter over a preloaded job and records when each command starts.
#include "popcut/drivers/motion_model.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "popcut/drivers/sim_cutter.h"

namespace popcut::drivers {

double longest_first_travel_mm(const HpglDialect& d) {
  const double x_mm = static_cast<double>(d.area_max_x_pu - d.area_min_x_pu) / d.units_per_mm_x;
  const double y_mm = static_cast<double>(d.area_max_y_pu - d.area_min_y_pu) / d.units_per_mm_y;
  // A roll runs along whichever axis is the longer: plotter y for HP-GL cutters, x for a GP-GL
  // device with its axes swapped.
  const double across_mm = std::min(x_mm, y_mm), along_mm = std::max(x_mm, y_mm);
  return std::hypot(across_mm, std::min(along_mm, 2 * across_mm));
}

namespace {

// The model's device: the profile's own, with a line that loses nothing (this is about time, not the buffer).
DeviceProfile model_device(const DeviceProfile& profile) {
  DeviceProfile p = profile;
  p.transport.flow = FlowControl::rts_cts;
  return p;
}

}  // namespace

double modelled_motion_s(std::string_view job, const DeviceProfile& profile) {
  SimCutter device(model_device(profile));
  device.preload(job);
  device.run_to_end();
  return device.now_s();
}

std::vector<MotionMark> motion_schedule(std::string_view job, const DeviceProfile& profile) {
  SimCutter device(model_device(profile));
  device.preload(job);
  std::vector<MotionMark> marks;
  // Each step starts the next command (and any that take no time after it).
  while (const std::optional<double> at = device.next_start_s()) {
    device.advance(*at);
    const std::size_t read = job.size() - device.buffer_used();
    if (!marks.empty() && marks.back().start_s == *at)
      marks.back().bytes_read = read;
    else
      marks.push_back({*at, read});
  }
  device.run_to_end();
  // Done: the last command's motion has ended (at once, when it takes none).
  if (!marks.empty() && marks.back().start_s == device.now_s())
    marks.back().bytes_read = job.size();
  else
    marks.push_back({device.now_s(), job.size()});
  // The model starts at the origin, but where the device is is unknown (a finish need not send it
  // home): its first travel may cross the usable area, so all that follows it may be later. Along
  // a roll feeder's length only twice its width: the next card's origin is near the last one.
  const double across_mm = longest_first_travel_mm(profile.dialect);
  const double first_travel_s =
      move_time_s(across_mm, profile.kinematics.travel_speed_mm_s, profile.kinematics.accel_mm_s2);
  // A calibrated device's measured pace: its real time over the model's (1 uncalibrated).
  const double factor = profile.calibration.time_factor;
  for (MotionMark& m : marks) {
    if (m.start_s > 0) m.start_s = (m.start_s + first_travel_s) * factor;
  }
  return marks;
}

}  // namespace popcut::drivers
