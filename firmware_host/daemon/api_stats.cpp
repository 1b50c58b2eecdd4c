// GET /api/v1/stats (admin): jobs per day, and per device jobs, cutting time and failure rate.
#include <cmath>

#include "api_handlers.h"
#include "stats.h"

namespace popcut::daemon {
namespace {

int days_param(const Req& req) {
  const std::optional<std::string> given = query_param(req, "days");
  if (!given) return 7;
  const std::string& d = *given;
  if (d.empty() || d.size() > 3 || d.find_first_not_of("0123456789") != std::string::npos || std::stoi(d) < 1 ||
      std::stoi(d) > 366)
    fail(ApiError::bad_request, "days must be a whole number from 1 to 366", "days");
  return std::stoi(d);
}

}  // namespace

void get_stats(ApiContext& api, const Caller&, const Req& req, Res& res) {
  const int days = days_param(req);
  Daemon& d = api.daemon();
  const double now = unix_now_s();
  std::vector<std::string> configured;
  for (const DeviceConfig& dev : d.config().devices) configured.push_back(dev.name);
  const StatsReport r = job_stats(d.store().stats_rows(stats_window_start(days, now)), days, now, configured);
  json day_list = json::array();
  for (const DayStats& day : r.days) {
    day_list.push_back({{"date", day.date},
                        {"jobs", day.submitted},
                        {"done", day.done},
                        {"failed", day.failed},
                        {"cancelled", day.cancelled}});
  }
  json device_list = json::array();
  for (const DeviceStats& dev : r.devices) {
    device_list.push_back(
        {{"name", dev.name},
         {"configured", dev.configured},
         {"jobs", dev.jobs},
         {"done", dev.done},
         {"failed", dev.failed},
         {"cancelled", dev.cancelled},
         {"cutting_s", std::round(dev.cutting_s * 10) / 10},
         {"failure_rate", dev.failure_rate ? json(std::round(*dev.failure_rate * 1000) / 1000) : json(nullptr)}});
  }
  send_json(res, {{"since", r.since_s}, {"days", day_list}, {"devices", device_list}});
}

}  // namespace popcut::daemon
