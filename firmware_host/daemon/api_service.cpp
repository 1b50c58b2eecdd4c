// Routes without a token: /healthz, /metrics and the kiosk and operator pages' fixed files.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "api_handlers.h"

namespace popcut::daemon {
namespace {

// The kiosk page: a fixed list of files, so no request path ever reaches the file system.
void page_file(const std::string& dir, const std::string& name, const char* type, const char* what, Res& res) {
  std::ifstream in(std::filesystem::path(dir) / name, std::ios::binary);
  if (!in) fail(ApiError::not_found, std::string(what) + " is not installed at " + dir);
  std::ostringstream o;
  o << in.rdbuf();
  res.set_content(o.str(), type);
}

void kiosk_file(ApiContext& api, const std::string& name, const char* type, Res& res) {
  page_file(api.daemon().config().kiosk_dir, name, type, "the kiosk page", res);
}

}  // namespace

void get_health(ApiContext& api, const Caller&, const Req&, Res& res) {
  send_json(res, {{"ok", true}, {"devices", api.daemon().config().devices.size()}});
}

void get_metrics(ApiContext& api, const Caller&, const Req&, Res& res) {
  Daemon& d = api.daemon();
  const RequestCounters& counters = api.counters();
  MetricsSample m;
  m.jobs_by_state = d.store().count_by_state();
  m.requests = counters.requests;
  m.errors_4xx = counters.errors_4xx;
  m.errors_5xx = counters.errors_5xx;
  m.submitted = counters.submitted;
  m.cuts_completed = d.cuts_completed();
  for (const DeviceStatus& s : d.devices()) {
    const DeviceWear w = d.store().device_wear(s.name);
    m.devices.push_back({s.name, s.job != 0, s.paused, w.lifetime.cut_mm, w.lifetime.knife_down_strokes, w.blade.cut_mm,
                         blade_worn(w, d.device(s.name)->blade_life_m)});
    m.devices.back().awaiting_sheet = s.job == 0 && d.sheet(s.name).awaiting();
  }
  const NotifyCounts n = d.notify_counts();
  m.notify_delivered = n.delivered;
  m.notify_failures = n.failures;
  m.notify_dropped = n.dropped;
  m.uptime_s = api.uptime_s();
  res.set_content(metrics_text(m), "text/plain; version=0.0.4");
}

void get_kiosk_page(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "index.html", "text/html; charset=utf-8", res);
}
void get_kiosk_script(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "app.js", "text/javascript", res);
}
void get_kiosk_style(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "app.css", "text/css", res);
}
// The operator page lives beside the kiosk's files; it asks for the admin token itself.
void get_operator_page(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "operator.html", "text/html; charset=utf-8", res);
}
void get_operator_script(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "operator.js", "text/javascript", res);
}
void get_operator_style(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "operator.css", "text/css", res);
}

// The designer page lives beside the kiosk's files; it reads its token from ?token=.
void get_design_page(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "design.html", "text/html; charset=utf-8", res);
}
void get_design_script(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "design.js", "text/javascript", res);
}
void get_design_style(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "design.css", "text/css", res);
}
void get_design_view_script(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "design_view3d.js", "text/javascript", res);
}
void get_design_files_script(ApiContext& api, const Caller&, const Req&, Res& res) {
  kiosk_file(api, "design_files.js", "text/javascript", res);
}
void get_three_script(ApiContext& api, const Caller&, const Req&, Res& res) {
  page_file(api.daemon().config().three_dir + "/build", "three.min.js", "text/javascript", "three.js (libjs-three)",
            res);
}
void get_orbit_controls(ApiContext& api, const Caller&, const Req&, Res& res) {
  page_file(api.daemon().config().three_dir + "/examples/js/controls", "OrbitControls.js", "text/javascript",
            "three.js (libjs-three)", res);
}

}  // namespace popcut::daemon
