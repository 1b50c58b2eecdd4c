// The Prometheus text of popcutd's /metrics (docs/api.md lists the series).
#include "metrics.h"

#include <iomanip>
#include <sstream>

namespace popcut::daemon {
namespace {

// Millimetres to the micrometre: the stream's default 6 digits would print 123457 for 123456.789.
std::string mm(double v) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(3) << v;
  return o.str();
}

}  // namespace

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
  o << "# HELP popcut_device_cut_mm_total Knife-down millimetres cut through (cut mode) over the device's life.\n"
       "# TYPE popcut_device_cut_mm_total counter\n";
  for (const MetricsSample::Device& d : m.devices)
    o << "popcut_device_cut_mm_total{device=\"" << d.name << "\"} " << mm(d.cut_mm_total) << "\n";
  o << "# HELP popcut_device_knife_down_strokes_total Knife-down strokes of every mode over the device's life.\n"
       "# TYPE popcut_device_knife_down_strokes_total counter\n";
  for (const MetricsSample::Device& d : m.devices)
    o << "popcut_device_knife_down_strokes_total{device=\"" << d.name << "\"} " << d.knife_down_strokes_total << "\n";
  o << "# HELP popcut_device_blade_cut_mm Millimetres cut since the blade was last changed.\n"
       "# TYPE popcut_device_blade_cut_mm gauge\n";
  for (const MetricsSample::Device& d : m.devices)
    o << "popcut_device_blade_cut_mm{device=\"" << d.name << "\"} " << mm(d.blade_cut_mm) << "\n";
  o << "# HELP popcut_device_blade_worn 1 once the blade has cut past blade_life_m.\n"
       "# TYPE popcut_device_blade_worn gauge\n";
  for (const MetricsSample::Device& d : m.devices)
    o << "popcut_device_blade_worn{device=\"" << d.name << "\"} " << (d.blade_worn ? 1 : 0) << "\n";
  o << "# HELP popcut_device_awaiting_sheet 1 while the device waits for someone to confirm a fresh sheet.\n"
       "# TYPE popcut_device_awaiting_sheet gauge\n";
  for (const MetricsSample::Device& d : m.devices)
    o << "popcut_device_awaiting_sheet{device=\"" << d.name << "\"} " << (d.awaiting_sheet ? 1 : 0) << "\n";
  o << "# HELP popcut_notify_delivered_total Webhook deliveries answered 2xx.\n"
       "# TYPE popcut_notify_delivered_total counter\npopcut_notify_delivered_total "
    << m.notify_delivered << "\n"
    << "# HELP popcut_notify_failures_total Webhook deliveries given up (every attempt failed, or refused).\n"
       "# TYPE popcut_notify_failures_total counter\npopcut_notify_failures_total "
    << m.notify_failures << "\n"
    << "# HELP popcut_notify_dropped_total Webhook events never tried: a full queue dropped them, or popcutd stopped.\n"
       "# TYPE popcut_notify_dropped_total counter\npopcut_notify_dropped_total "
    << m.notify_dropped << "\n";
  o << "# HELP popcutd_uptime_seconds Seconds since popcutd started.\n# TYPE popcutd_uptime_seconds gauge\n"
    << "popcutd_uptime_seconds " << m.uptime_s << "\n";
  return o.str();
}

}  // namespace popcut::daemon
