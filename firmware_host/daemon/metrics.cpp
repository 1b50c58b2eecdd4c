// The Prometheus text of popcutd's /metrics (docs/api.md lists the series).
#include "metrics.h"

#include <sstream>

namespace popcut::daemon {

std::string metrics_text(const MetricsSample& m) {
  std::ostringstream o;
  o << "# HELP popcutd_jobs Jobs in the store by state.\n# TYPE popcutd_jobs gauge\n";
  for (const auto& [state, n] : m.jobs_by_state) o << "popcutd_jobs{state=\"" << state << "\"} " << n << "\n";
  o << "# HELP popcutd_http_requests_total API requests answered.\n# TYPE popcutd_http_requests_total counter\n"
    << "popcutd_http_requests_total " << m.requests << "\n"
    << "# HELP popcutd_http_errors_total Requests answered with an error, by class.\n# TYPE popcutd_http_errors_total "
       "counter\n"
    << "popcutd_http_errors_total{class=\"4xx\"} " << m.errors_4xx << "\n"
    << "popcutd_http_errors_total{class=\"5xx\"} " << m.errors_5xx << "\n"
    << "# HELP popcutd_jobs_submitted_total Jobs accepted since start.\n# TYPE popcutd_jobs_submitted_total counter\n"
    << "popcutd_jobs_submitted_total " << m.submitted << "\n"
    << "# HELP popcutd_cuts_completed_total Cuts finished since start.\n# TYPE popcutd_cuts_completed_total counter\n"
    << "popcutd_cuts_completed_total " << m.cuts_completed << "\n"
    << "# HELP popcutd_device_busy 1 while the device cuts.\n# TYPE popcutd_device_busy gauge\n";
  for (const MetricsSample::Device& d : m.devices)
    o << "popcutd_device_busy{device=\"" << d.name << "\"} " << (d.busy ? 1 : 0) << "\n";
  o << "# HELP popcutd_device_paused 1 while an admin holds the device.\n# TYPE popcutd_device_paused gauge\n";
  for (const MetricsSample::Device& d : m.devices)
    o << "popcutd_device_paused{device=\"" << d.name << "\"} " << (d.paused ? 1 : 0) << "\n";
  o << "# HELP popcutd_uptime_seconds Seconds since popcutd started.\n# TYPE popcutd_uptime_seconds gauge\n"
    << "popcutd_uptime_seconds " << m.uptime_s << "\n";
  return o.str();
}

}  // namespace popcut::daemon
