// The device's pace through a job by the simulated cutter's motion model, for the sender's time pacing and drain.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "popcut/drivers/profile.h"
#include "popcut/lang/encoder.h"

namespace popcut::drivers {

// A point of a device's progress through a job at the pace of the motion model: after start_s
// seconds of motion it starts a command, having read the first bytes_read bytes of the job out of
// its buffer (that command's among them).
struct MotionMark {
  double start_s = 0;
  std::size_t bytes_read = 0;
};
// One mark per moment a command starts, ascending in both; the last is {when the job's motion
// ends, job size}. By the simulated cutter's model (the profile's kinematics, the job's VS), the
// one the plan's time estimate uses, with the whole job there from the start and a long PA/PD
// read pair by pair. Where the device starts is unknown: everything after the first command is
// later by a travel of longest_first_travel_mm. A calibrated profile's [kinematics] time_factor
// (real / modelled, as popcut calibrate measures it) scales every mark.
std::vector<MotionMark> motion_schedule(std::string_view job, const DeviceProfile& profile);
// The same for an encoded job: a profile whose [kinematics] starts_at is "origin" starts the model
// where its finish leaves the head, with no first-travel allowance (a resumed job keeps the
// allowance: it starts where its interrupted run stopped). Throws popcut::Error(invalid_input)
// naming starts_at when the finish, or a cancel's knife-up and finish, leave the head elsewhere.
std::vector<MotionMark> motion_schedule(const EncodedJob& job, const DeviceProfile& profile);
// A profile's [kinematics] starts_at = "origin" checked on a two-stroke job (motion_schedule
// checks each real job too): throws as motion_schedule does; nothing for "anywhere".
void check_starts_at(const DeviceProfile& profile);
// The job's motion time by the same model from the origin, unscaled and without the first-travel
// allowance: what calibrate holds a device's measured time against.
double modelled_motion_s(std::string_view job, const DeviceProfile& profile);
// The usable area's diagonal; on a roll feeder (more than twice as long as wide, along either
// plotter axis) that of a piece twice as long as wide.
double longest_first_travel_mm(const HpglDialect& dialect);

}  // namespace popcut::drivers
