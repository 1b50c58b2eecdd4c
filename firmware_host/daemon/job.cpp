// Names and HTTP statuses of job states and API error codes: the strings docs/api.md documents.
#include "job.h"

#include <algorithm>
#include <chrono>

namespace popcut::daemon {

const char* to_string(JobState state) { return kJobStateNames.name(state).data(); }

std::optional<JobState> parse_job_state(const std::string& text) { return kJobStateNames.find(text); }

const char* to_string(ResumePoint point) { return kResumePointNames.name(point).data(); }

std::optional<ResumePoint> parse_resume_point(const std::string& text) { return kResumePointNames.find(text); }

bool is_terminal(JobState s) { return s == JobState::done || s == JobState::failed || s == JobState::cancelled; }

const char* to_string(ApiError e) { return kApiErrorNames.name(e).data(); }

int http_status(ApiError e) {
  switch (e) {
    case ApiError::bad_json:
    case ApiError::bad_request:
    case ApiError::bad_name: return 400;
    case ApiError::unauthorized: return 401;
    case ApiError::forbidden: return 403;
    case ApiError::not_found: return 404;
    case ApiError::conflict: return 409;
    case ApiError::too_large:
    case ApiError::model_too_complex: return 413;
    case ApiError::bad_model:
    case ApiError::no_device: return 422;
    case ApiError::no_material:
    case ApiError::key_reused: return 422;
    case ApiError::length_required: return 411;
    case ApiError::method_not_allowed: return 405;
    case ApiError::queue_full:
    case ApiError::busy: return 503;
    case ApiError::cancelled:
    case ApiError::interrupted:
    case ApiError::device_error:
    case ApiError::internal: return 500;
  }
  return 500;
}

std::unordered_map<std::int64_t, double> forecast_done_s(const std::vector<WaitingJob>& waiting,
                                                         std::vector<ForecastDevice> devices) {
  std::unordered_map<std::int64_t, double> done_s;
  for (const WaitingJob& w : waiting) {
    ForecastDevice* first = nullptr;
    for (ForecastDevice& d : devices) {
      if (w.targets.may_go_to(d.name, d.profile) && (!first || d.busy_s < first->busy_s)) first = &d;
    }
    if (!first) continue;
    first->busy_s += w.left_s * first->time_factor;
    done_s[w.id] = first->busy_s;
  }
  return done_s;
}

double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double cut_left_s(const Job& j, double time_factor, double run_started_s, double now_s) {
  if (j.strokes_total <= 0) return j.est_time_s * time_factor;
  const auto share_after = [&](std::int64_t strokes) {
    return 1.0 - static_cast<double>(strokes) / static_cast<double>(j.strokes_total);
  };
  const double run_s = j.est_time_s * time_factor * share_after(j.resume_from);
  const double by_strokes = j.est_time_s * time_factor * share_after(std::max(j.strokes_sent, j.resume_from));
  const double by_time = run_s - std::max(0.0, now_s - run_started_s);
  return std::max({0.0, by_strokes, by_time});
}

}  // namespace popcut::daemon
