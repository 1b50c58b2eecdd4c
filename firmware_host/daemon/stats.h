// Shop statistics (GET /api/v1/stats): jobs per local calendar day and, per device, jobs, cutting time and failure
// rate.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "job.h"

namespace popcut::daemon {

// What the statistics need of one job (JobStore::stats_rows).
struct StatsRow {
  JobState state = JobState::queued;
  std::string device;         // the device that took it ("" if none did)
  double created_at = 0;      // unix seconds
  double finished_at = 0;     // 0 unless done, failed or cancelled
  double last_cut_at = 0;     // the last moment a run of it is known to have cut (0: never cut)
  double cutting_s = 0;       // the runs ended so far (each from its start to its end)
  double run_started_at = 0;  // the run in progress, while `cutting`
};

struct DayStats {
  std::string date;  // YYYY-MM-DD, local time
  std::int64_t submitted = 0, done = 0, failed = 0, cancelled = 0;
};

struct DeviceStats {
  std::string name;
  bool configured = true;                                      // false: only in the history (a device since removed)
  std::int64_t jobs = 0, done = 0, failed = 0, cancelled = 0;  // jobs it took that ended in the window
  double cutting_s = 0;
  // failed / (done + failed): a cancel is someone's decision, not a failure; none while neither.
  std::optional<double> failure_rate;
};

struct StatsReport {
  std::vector<DayStats> days;        // oldest first, `days` of them ending with today
  std::vector<DeviceStats> devices;  // the configured ones in their order, then others by name
  double since_s = 0;                // local midnight starting the first day
};

// Local midnight (the TZ popcutd runs in) that starts the window of `days` days ending today.
double stats_window_start(int days, double now_s);

// The statistics of `rows` over the `days` local days ending with the one holding `now_s`.
// A job counts as submitted on the day it was created and as done, failed or cancelled on the day
// it finished; a device counts the jobs it took that finished in the window, and the cutting time
// of every job it cut whose last run ended in it (all of that job's runs; a run in progress up to now).
StatsReport job_stats(const std::vector<StatsRow>& rows, int days, double now_s,
                      const std::vector<std::string>& configured_devices);

}  // namespace popcut::daemon
