// Device routes: the devices and what each cuts, the materials jobs may name, an admin's pause and resume.
#include "api_handlers.h"

namespace popcut::daemon {
namespace {

void set_paused(ApiContext& api, const Req& req, Res& res, bool paused) {
  const std::string name = req.matches[1];
  if (!api.daemon().device(name)) fail(ApiError::not_found, "no device named " + name);
  api.daemon().set_paused(name, paused);
  send_json(res, {{"device", name}, {"paused", paused}});
}

}  // namespace

void list_devices(ApiContext& api, const Caller& caller, const Req&, Res& res) {
  Daemon& d = api.daemon();
  json list = json::array();
  for (const DeviceStatus& s : d.devices()) {
    // A kiosk sees which of its own jobs a device cuts; another's id would only answer 404.
    std::optional<Job> cutting;
    if (s.job && !caller.admin()) cutting = d.store().get(s.job);
    const bool shown = s.job && (caller.admin() || (cutting && cutting->owner == caller.name));
    // The job that last used the sheet, to its owner (whose kiosk offers "Sheet loaded") and the admin.
    const DeviceSheet sheet = d.sheet(s.name);
    std::optional<Job> last;
    if (sheet.last_job && !caller.admin()) last = d.store().get(sheet.last_job);
    const bool last_shown = sheet.last_job && (caller.admin() || (last && last->owner == caller.name));
    list.push_back({{"name", s.name},
                    {"profile", s.profile},
                    {"model", d.device(s.name)->profile.name},
                    {"state", s.paused ? (s.job ? "pausing" : "paused") : (s.job ? "cutting" : "idle")},
                    {"paused", s.paused},
                    {"job", shown ? json(s.job) : json(nullptr)},
                    {"blade", d.blade(s.name)},
                    {"confirm_sheet", d.device(s.name)->confirm_sheet},
                    {"sheet", sheet_label(sheet, s.job != 0)},
                    {"tray_empty", sheet.state == SheetState::empty},
                    {"sheet_job", last_shown ? json(sheet.last_job) : json(nullptr)}});
  }
  send_json(res, {{"devices", list}});
}

void list_materials(ApiContext& api, const Caller&, const Req&, Res& res) {
  json list = json::array();
  for (const drivers::Material& m : api.daemon().config().materials) {
    json families = json::array();
    for (const auto& [family, name] : drivers::kDeviceFamilyNames.entries) {
      if (m.families[static_cast<std::size_t>(family)]) families.push_back(std::string(name));
    }
    list.push_back({{"name", m.name}, {"description", m.description}, {"families", families}});
  }
  send_json(res, {{"materials", list}});
}

// The body may be empty or {}: there is nothing to say but that the blade was changed.
void reset_blade(ApiContext& api, const Caller&, const Req& req, Res& res) {
  const std::string name = req.matches[1];
  if (!req.body.empty()) {
    const json body = parse_body(req);
    if (!body.is_object()) fail(ApiError::bad_request, "the body must be {} or empty");
    for (const auto& [k, v] : body.items()) fail(ApiError::bad_request, "unknown field '" + k + "' (takes none)", k);
  }
  Daemon& d = api.daemon();
  if (!d.device(name)) fail(ApiError::not_found, "no device named " + name);
  if (!d.reset_blade(name))
    fail(ApiError::conflict, name + " is cutting: change the blade, and reset its counters, between jobs");
  send_json(res, {{"device", name}, {"blade", d.blade(name)}});
}

// A fresh sheet is loaded: an admin, or the owner of the job that last used the sheet (the kiosk
// shows that user the button). The body may be empty or {}.
void confirm_sheet(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::string name = req.matches[1];
  if (!req.body.empty()) {
    const json body = parse_body(req);
    if (!body.is_object()) fail(ApiError::bad_request, "the body must be {} or empty");
    for (const auto& [k, v] : body.items()) fail(ApiError::bad_request, "unknown field '" + k + "' (takes none)", k);
  }
  Daemon& d = api.daemon();
  if (!d.device(name)) fail(ApiError::not_found, "no device named " + name);
  if (!caller.admin()) {
    const DeviceSheet sheet = d.sheet(name);
    const std::optional<Job> last = sheet.last_job ? d.store().get(sheet.last_job) : std::nullopt;
    if (!last || last->owner != caller.name)
      fail(ApiError::forbidden, "confirming " + name + "'s sheet needs the admin token or the owner of its last job");
  }
  const SheetConfirmation c = d.confirm_sheet(name);
  if (c.held_state == "cutting") fail(ApiError::conflict, name + " is cutting: load a fresh sheet after the job ends");
  if (!c.sheet)
    fail(ApiError::conflict, "job " + std::to_string(c.held_by) + " is " + c.held_state +
                                 " with its half-cut sheet on " + name +
                                 ": continue or resume it to finish that sheet, or cancel it, before a fresh one");
  send_json(res, {{"device", name}, {"sheet", sheet_label(*c.sheet, false)}});
}

void pause_device(ApiContext& api, const Caller&, const Req& req, Res& res) { set_paused(api, req, res, true); }
void resume_device(ApiContext& api, const Caller&, const Req& req, Res& res) { set_paused(api, req, res, false); }

}  // namespace popcut::daemon
