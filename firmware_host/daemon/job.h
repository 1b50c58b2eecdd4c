// Job records, their documented states and the API's error-code catalogue (docs/api.md).
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "popcut/names.h"

namespace popcut::daemon {

// Life of a job (docs/api.md "Job states"). Terminal: done, failed, cancelled.
enum class JobState { queued, planning, ready, cutting, done, failed, cancelled, interrupted, paused };
inline constexpr auto kJobStateNames = enum_names<JobState>({{JobState::queued, "queued"},
                                                             {JobState::planning, "planning"},
                                                             {JobState::ready, "ready"},
                                                             {JobState::cutting, "cutting"},
                                                             {JobState::done, "done"},
                                                             {JobState::failed, "failed"},
                                                             {JobState::cancelled, "cancelled"},
                                                             {JobState::interrupted, "interrupted"},
                                                             {JobState::paused, "paused"}});
const char* to_string(JobState state);
std::optional<JobState> parse_job_state(const std::string& text);
bool is_terminal(JobState state);

// Where a resumed job continues (docs/api.md "Resuming"): after the strokes the device certainly
// received (it kept its buffer: the default), or after those it is known to have executed (it was
// reset or power-cycled and lost its buffer; strokes between may then be cut twice).
enum class ResumePoint { received, executed };
inline constexpr auto kResumePointNames =
    enum_names<ResumePoint>({{ResumePoint::received, "received"}, {ResumePoint::executed, "executed"}});
const char* to_string(ResumePoint point);
std::optional<ResumePoint> parse_resume_point(const std::string& text);

// Stable error codes (grbl-style catalogue): HTTP answers and failed jobs carry one of these.
enum class ApiError {
  bad_json,            // 400: the body is not JSON
  bad_request,         // 400: a field is missing, of the wrong type or out of range
  bad_model,           // 422: the model is not a valid popcut model (message names the field)
  model_too_complex,   // 413: the model exceeds [limits] model_cells or pattern_faces
  too_large,           // 413: the body exceeds [limits] upload_bytes
  bad_name,            // 400: a job or device name with path or shell structure in it
  unauthorized,        // 401: no token, or a token the daemon does not know
  forbidden,           // 403: the token may not do this (another's job, an admin action)
  not_found,           // 404: no such job, device or file
  conflict,            // 409: the job is not in a state that allows this (e.g. resume a done job)
  queue_full,          // 503: [limits] queue_length unfinished jobs already
  no_device,           // 422: no device of that name, or none with that profile
  no_material,         // 422: no material of that name, or none with values for the device's family
  key_reused,          // 422: an Idempotency-Key already used for a different submission
  length_required,     // 411: a POST without Content-Length (or chunked encoding)
  method_not_allowed,  // 405: the path exists, not with this method (Allow lists those it has)
  busy,                // 503: every preview-rendering slot is in use; retry shortly
  device_error,        // job only: the transport failed mid-cut
  cancelled,           // job only: cancelled by its owner or an admin (before or during the cut)
  interrupted,         // job only: popcutd stopped (SIGTERM, crash) during the cut; resumable
  internal,            // 500: a bug in popcutd
};
inline constexpr auto kApiErrorNames = enum_names<ApiError>({
    {ApiError::bad_json, "bad_json"},
    {ApiError::bad_request, "bad_request"},
    {ApiError::bad_model, "bad_model"},
    {ApiError::model_too_complex, "model_too_complex"},
    {ApiError::too_large, "too_large"},
    {ApiError::bad_name, "bad_name"},
    {ApiError::unauthorized, "unauthorized"},
    {ApiError::forbidden, "forbidden"},
    {ApiError::not_found, "not_found"},
    {ApiError::conflict, "conflict"},
    {ApiError::queue_full, "queue_full"},
    {ApiError::no_device, "no_device"},
    {ApiError::no_material, "no_material"},
    {ApiError::key_reused, "key_reused"},
    {ApiError::length_required, "length_required"},
    {ApiError::method_not_allowed, "method_not_allowed"},
    {ApiError::busy, "busy"},
    {ApiError::device_error, "device_error"},
    {ApiError::cancelled, "cancelled"},
    {ApiError::interrupted, "interrupted"},
    {ApiError::internal, "internal"},
});
const char* to_string(ApiError error);
int http_status(ApiError error);

// The wall clock in unix seconds, as jobs record their times.
double unix_now_s();

// A job's claim on the devices: the device it names, else any device with its profile.
struct Targets {
  std::string device, profile;
  bool may_go_to(const std::string& device_name, const std::string& device_profile) const {
    return device.empty() ? device_profile == profile : device_name == device;
  }
};

// When each waiting job should be done, as the device workers take the queue: oldest first, each
// goes to whichever of its devices frees up first (after its cut in progress and the jobs before
// it) and takes the cutting time it has left there. `devices` are those taking work; a job none
// of them may take has no entry. Wall-clock seconds from now, by job id.
struct WaitingJob {
  std::int64_t id = 0;
  Targets targets;
  double left_s = 0;  // the plan's estimate of what it has left to cut; 0 while not planned
};
struct ForecastDevice {
  std::string name, profile;
  double time_factor = 1;  // wall-clock seconds per planned second (a simulated cutter's time scale)
  double busy_s = 0;       // what its cut in progress has left
};
std::unordered_map<std::int64_t, double> forecast_done_s(const std::vector<WaitingJob>& waiting,
                                                         std::vector<ForecastDevice> devices);

// Wall-clock seconds a cut in progress has left, at the least: the strokes not yet sent, and the
// part of this run's estimate not yet elapsed. Strokes alone say 0 once a small job sits whole in
// the device's buffer; elapsed time alone says 0 when the device runs slower than planned.
struct Job;
double cut_left_s(const Job& job, double time_factor, double run_started_s, double now_s);

struct Job {
  std::int64_t id = 0;
  std::string owner;           // token name that submitted it
  std::string name;            // the user's label
  std::string target_device;   // empty: any device with target_profile
  std::string target_profile;  // the profile's device name (DeviceProfile::name)
  std::string material;        // configs/materials stem its forces come from; empty: the profile's
  std::string device;          // the device that cut (or is cutting) it
  JobState state = JobState::queued;
  std::string error_code, error_message;
  std::int64_t strokes_total = 0, strokes_sent = 0;  // strokes_sent: fully sent to the device
  std::int64_t resume_from = 0;                      // the stroke the next cut starts at
  std::optional<ResumePoint> resume_point;           // how the last resume chose resume_from (nullopt: never resumed)
  // After a cut: the last stroke the device is known to have executed (nullopt: unknown, or
  // the device cannot be asked); after a reset or power cycle only these are certainly cut.
  std::optional<std::int64_t> strokes_executed;
  double est_time_s = 0;
  double created_at = 0, started_at = 0, finished_at = 0;  // unix seconds; 0 = not yet
  // Knife-down millimetres of cut-mode strokes and knife-down strokes of every mode, over the
  // runs that ended (each counts only the strokes it certainly got to the device; wear.h).
  double cut_mm = 0;
  std::int64_t knife_down_strokes = 0;
  bool sim_match = false;  // sim devices: what it cut equals the plan (strokes from resume_from on)
  // Its place in the queue (docs/api.md "The queue"): higher priority first, then lower rank;
  // rank starts as the id (first come, first served) and an admin's `before` puts it between two.
  int priority = 0;
  double queue_rank = 0;
  int copies = 1;                // cards nested on its sheets
  bool pause_requested = false;  // cutting: a pause was asked; the worker stops at the stroke in flight
  // More copies than one sheet holds: sheet_copies cards on each sheet but the last, whose strokes
  // sheet k (from 0) numbers from k * sheet_strokes + 1 on. 0 while unplanned or on one sheet.
  int sheet_copies = 0;
  std::int64_t sheet_strokes = 0;

  int sheets() const { return sheet_copies > 0 ? (copies + sheet_copies - 1) / sheet_copies : 1; }
  // The sheet (from 0) stroke `stroke` (from 1) is on.
  int sheet_of(std::int64_t stroke) const {
    if (sheets() <= 1 || sheet_strokes <= 0) return 0;
    return static_cast<int>(
        std::min<std::int64_t>(std::max<std::int64_t>(stroke - 1, 0) / sheet_strokes, sheets() - 1));
  }

  // The device holding this job's half-cut sheet: an interrupted job, or one resumed and waiting,
  // continues there and nowhere else ("" when no sheet of it is on a device).
  std::string bound_device() const {
    return state == JobState::interrupted || state == JobState::ready || state == JobState::paused ? device
                                                                                                   : std::string();
  }
  // Where it may be cut: the device holding its sheet, else the one it names, else its profile's.
  Targets targets() const {
    const std::string bound = bound_device();
    return {bound.empty() ? target_device : bound, target_profile};
  }
};

}  // namespace popcut::daemon
