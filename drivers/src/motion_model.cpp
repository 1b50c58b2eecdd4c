// Motion schedule: runs the simulated cutter over a preloaded job and records when each command starts.
#include "popcut/drivers/motion_model.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"
#include "popcut/text.h"

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

namespace {

// The model's run through `job` from where `start` leaves the device, in seconds from there.
struct ModelRun {
  std::vector<MotionMark> marks;
  std::array<std::int64_t, 2> start_pu{}, end_pu{};
};

ModelRun run_model(std::string_view start, std::string_view job, const DeviceProfile& profile) {
  SimCutter device(model_device(profile));
  device.preload(start);
  device.run_to_end();
  const double t0_s = device.now_s();
  ModelRun run;
  run.start_pu = device.position();
  device.preload(job);
  std::vector<MotionMark>& marks = run.marks;
  // Each step starts the next command (and any that take no time after it).
  while (const std::optional<double> at = device.next_start_s()) {
    device.advance(*at);
    const std::size_t read = job.size() - device.buffer_used();
    if (!marks.empty() && marks.back().start_s == *at - t0_s)
      marks.back().bytes_read = read;
    else
      marks.push_back({*at - t0_s, read});
  }
  device.run_to_end();
  // Done: the last command's motion has ended (at once, when it takes none).
  if (!marks.empty() && marks.back().start_s == device.now_s() - t0_s)
    marks.back().bytes_read = job.size();
  else
    marks.push_back({device.now_s() - t0_s, job.size()});
  run.end_pu = device.position();
  return run;
}

// Every mark after the start later by `allowance_s`, then scaled by a calibrated device's
// measured pace (its real time over the model's; 1 uncalibrated).
std::vector<MotionMark> scaled(std::vector<MotionMark> marks, double allowance_s, const DeviceProfile& profile) {
  const double factor = profile.calibration.time_factor;
  for (MotionMark& m : marks) {
    if (m.start_s > 0) m.start_s = (m.start_s + allowance_s) * factor;
  }
  return marks;
}

std::string mm_text(const std::array<std::int64_t, 2>& pu, const HpglDialect& d) {
  return format_decimal(static_cast<double>(pu[0]) / d.units_per_mm_x, 1) + ", " +
         format_decimal(static_cast<double>(pu[1]) / d.units_per_mm_y, 1) + " mm";
}

// A starts_at = "origin" profile whose finish (or cancel) leaves the head elsewhere would have
// the next job paced from the wrong place: refused before the first byte.
void check_parks(const ModelRun& run, std::string_view what, const DeviceProfile& profile) {
  if (run.end_pu == run.start_pu) return;
  throw Error(ErrorCode::invalid_input, profile.source, "[kinematics] starts_at",
              "\"origin\" says every job starts where the finish leaves the head (" +
                  mm_text(run.start_pu, profile.dialect) + "), but " + std::string(what) + " leaves it at " +
                  mm_text(run.end_pu, profile.dialect) +
                  ": make the finish go there absolutely (HP-GL: end [hpgl] finish with PA0,0;) or say \"anywhere\"");
}

// The checks for one job: its finish, and a cancel after its first stroke.
void check_job_parks(const EncodedJob& job, const std::string& park, const ModelRun& run,
                     const DeviceProfile& profile) {
  check_parks(run, "the job's finish", profile);
  if (job.stroke_end.empty()) return;
  const std::string cancelled = job.bytes.substr(0, job.stroke_end.front()) + send_options(profile).abort_bytes;
  check_parks(run_model(park, cancelled, profile), "a cancel's knife-up and finish", profile);
}

}  // namespace

void check_starts_at(const DeviceProfile& profile) {
  if (profile.starts_at == StartsAt::anywhere) return;
  // Two cuts far apart on a small sheet: a finish that moves relatively ends near each.
  StrokePlan plan;
  plan.sheet = {{0, 0}, {50, 50}};
  plan.strokes = {{PlanKind::cut, {{5, 5}, {10, 5}}}, {PlanKind::cut, {{45, 45}, {40, 45}}}};
  const EncodedJob job = encode_for_device(plan, profile);
  const std::string park = language_unit(profile.language).park(profile);
  check_job_parks(job, park, run_model(park, job.bytes, profile), profile);
}

std::vector<MotionMark> motion_schedule(std::string_view job, const DeviceProfile& profile) {
  // Where the device is is unknown (a finish need not send it home): its first travel may cross
  // the usable area, so all that follows it may be later. Along a roll feeder's length only twice
  // its width: the next card's origin is near the last one.
  const double first_travel_s = move_time_s(longest_first_travel_mm(profile.dialect),
                                            profile.kinematics.travel_speed_mm_s, profile.kinematics.accel_mm_s2);
  return scaled(run_model("", job, profile).marks, first_travel_s, profile);
}

std::vector<MotionMark> motion_schedule(const EncodedJob& job, const DeviceProfile& profile) {
  // A resumed job starts where the interrupted run left the head.
  if (profile.starts_at == StartsAt::anywhere || job.first_stroke > 1) return motion_schedule(job.bytes, profile);
  const std::string park = language_unit(profile.language).park(profile);
  ModelRun run = run_model(park, job.bytes, profile);
  check_job_parks(job, park, run, profile);
  return scaled(std::move(run.marks), 0, profile);
}

}  // namespace popcut::drivers
