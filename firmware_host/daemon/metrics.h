// popcutd's /metrics: request counters, and the page in the Prometheus text format (0.0.4).
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace popcut::daemon {

// Counted by the HTTP API as it answers.
struct RequestCounters {
  std::atomic<std::uint64_t> requests{0}, errors_4xx{0}, errors_5xx{0}, submitted{0};
};

// What one scrape reports.
struct MetricsSample {
  struct Device {
    std::string name;
    bool busy = false;    // a job is cutting on it
    bool paused = false;  // an admin holds it
    // Knife-down wear over the device's life (never reset; survives restarts), and its blade's state.
    double cut_mm_total = 0;
    std::int64_t knife_down_strokes_total = 0;
    double blade_cut_mm = 0;  // since the blade was last changed
    bool blade_worn = false;
    bool awaiting_sheet = false;  // idle until someone confirms a fresh sheet
  };
  std::map<std::string, std::int64_t> jobs_by_state;
  std::uint64_t requests = 0, errors_4xx = 0, errors_5xx = 0, submitted = 0, cuts_completed = 0;
  std::vector<Device> devices;
  std::uint64_t notify_delivered = 0, notify_failures = 0, notify_dropped = 0;
  double uptime_s = 0;
};

std::string metrics_text(const MetricsSample& sample);

}  // namespace popcut::daemon
