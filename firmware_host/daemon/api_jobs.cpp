// Job routes: submit, list, one job with its pattern and preview, cancel and resume (docs/api.md).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>
#include <unordered_map>

#include "../report_json.h"
#include "api_handlers.h"
#include "api_queue.h"
#include "mesh_upload.h"
#include "model_limits.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/error.h"
#include "popcut/io/files.h"

namespace popcut::daemon {
namespace {

namespace fs = std::filesystem;

// The queue played forward once per request (docs/api.md eta_s), shared by every job listed.
using Forecast = std::unordered_map<std::int64_t, double>;

// What the cut on `device` has left, by the device's clock; 0 when it is idle.
double busy_s(const DeviceStatus& device, const std::vector<Job>& cutting) {
  for (const Job& j : cutting) {
    if (j.id == device.job) return cut_left_s(j, device.time_factor, device.run_started_s, unix_now_s());
  }
  return 0;
}

Forecast forecast(Daemon& d) {
  const std::vector<Job> cutting = d.store().cutting();
  std::vector<ForecastDevice> taking;  // devices that start new cuts
  for (const DeviceStatus& dev : d.devices()) {
    if (!dev.paused) taking.push_back({dev.name, dev.profile, dev.time_factor, busy_s(dev, cutting)});
  }
  return forecast_done_s(d.store().waiting(), std::move(taking));
}

json optional_text(const std::string& s) { return s.empty() ? json(nullptr) : json(s); }

json job_json(Daemon& d, const Job& j, const Forecast* shared = nullptr) {
  json r = {{"id", j.id},
            {"name", j.name},
            {"owner", j.owner},
            {"device", optional_text(j.target_device)},
            {"profile", j.target_profile},
            {"material", optional_text(j.material)},
            {"cut_on", optional_text(j.device)},
            {"bound_to", optional_text(j.bound_device())},
            {"state", to_string(j.state)},
            {"strokes_total", j.strokes_total},
            {"strokes_sent", j.strokes_sent},
            {"resume_from", j.resume_from},
            {"resume_point", j.resume_point ? json(to_string(*j.resume_point)) : json(nullptr)},
            {"strokes_executed", j.strokes_executed ? json(*j.strokes_executed) : json(nullptr)},
            {"progress",
             j.strokes_total > 0 ? static_cast<double>(j.strokes_sent) / static_cast<double>(j.strokes_total) : 0.0},
            {"est_time_s", j.est_time_s},
            {"cut_mm", j.cut_mm},
            {"knife_down_strokes", j.knife_down_strokes},
            {"created_at", j.created_at},
            {"started_at", j.started_at > 0 ? json(j.started_at) : json(nullptr)},
            {"finished_at", j.finished_at > 0 ? json(j.finished_at) : json(nullptr)},
            {"priority", j.priority},
            {"copies", j.copies},
            {"sheets", j.sheets()},
            // The sheet being cut or next to cut (from 1); the last once done.
            {"sheet", j.sheet_of(std::min(j.strokes_sent + 1, std::max<std::int64_t>(j.strokes_total, 1))) + 1},
            {"place_in_line", nullptr},
            {"eta_s", nullptr}};
  if (!j.error_code.empty() || !j.error_message.empty())
    r["error"] = {{"code", j.error_code}, {"message", j.error_message}};
  // Only a simulated cutter reports what it cut; for a real one there is nothing to compare.
  const DeviceConfig* cut_on = d.device(j.device);
  if (j.state == JobState::done && cut_on && cut_on->transport == "sim") r["sim_match"] = j.sim_match;
  if (j.state == JobState::queued || j.state == JobState::planning || j.state == JobState::ready) {
    r["place_in_line"] = d.store().place_in_line(j);
    if (j.state == JobState::ready) {
      const Forecast own = shared ? Forecast() : forecast(d);
      const Forecast& f = shared ? *shared : own;
      if (const auto it = f.find(j.id); it != f.end()) r["eta_s"] = it->second;
    }
  } else if (j.state == JobState::cutting) {
    r["cancel"] = nullptr;
    r["pause_requested"] = j.pause_requested;
    for (const DeviceStatus& dev : d.devices()) {
      if (dev.job != j.id) continue;
      r["eta_s"] = busy_s(dev, {j});
      if (dev.cancel != CancelStage::none) r["cancel"] = to_string(dev.cancel);
    }
  }
  return rounded_numbers(std::move(r));
}

json current_job(Daemon& d, std::int64_t id) { return job_json(d, *d.store().get(id)); }

void set_target(Daemon& d, NewJob& nj, const std::string& device, const std::string& profile) {
  if (!is_job_label(nj.name)) {
    fail(ApiError::bad_name,
         "job names are 1 to 64 characters of text in any script, without control characters, direction overrides, "
         "'/', '\\', '..', a leading '.' or a space at either end",
         "name");
  }
  nj.target_device = device;
  nj.target_profile = profile;
  if (nj.target_device.empty() == nj.target_profile.empty()) {
    fail(ApiError::bad_request, "name either a device or a profile (any device with it)", "device");
  }
  if (!nj.target_device.empty()) {
    if (!is_safe_name(nj.target_device)) fail(ApiError::bad_name, "not a device name: " + nj.target_device, "device");
    const DeviceConfig* dev = d.device(nj.target_device);
    if (!dev) fail(ApiError::no_device, "no device named " + nj.target_device, "device");
    nj.target_profile = Daemon::profile_key(*dev);
  } else {
    if (!is_safe_name(nj.target_profile))
      fail(ApiError::bad_name, "not a profile name: " + nj.target_profile, "profile");
    if (!d.has_profile(nj.target_profile))
      fail(ApiError::no_device, "no device has the profile " + nj.target_profile, "profile");
  }
}

// The job's material: one popcutd knows, with values for the family of the device it plans for.
void set_material(Daemon& d, NewJob& nj, const std::string& material) {
  nj.material = material;
  if (material.empty()) return;
  const drivers::Material* m = d.material(material);
  if (!m)
    fail(ApiError::no_material, "unknown material \"" + material + "\" (known: " + d.material_list() + ")", "material");
  const DeviceConfig* dev = d.planning_device(nj.target_device, nj.target_profile);
  if (!dev) fail(ApiError::no_device, "no device for this job", "device");
  const drivers::DeviceFamily family = dev->profile.family;
  if (!m->families[static_cast<std::size_t>(family)]) {
    fail(ApiError::no_material,
         "material \"" + material + "\" has no values for the " +
             std::string(drivers::kDeviceFamilyNames.name(family)) + " family of " + dev->profile.name +
             "; it has values for " + m->family_list(),
         "material");
  }
  try {
    // Its values out of this device's range (a force above its FX maximum) refuse the material, not the model.
    (void)d.job_profile(*dev, material);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    fail(ApiError::no_material, e.what(), "material");
  }
}

// The checks planning would make, made before the job is accepted: a model that is not a card,
// is over [limits], or whose sheet does not fit the device is refused now (4xx), not failed later.
// Returns the devices whose media the sheet is too big for (the job may still go to another).
std::vector<std::string> check_for_device(ApiContext& api, const NewJob& nj, const std::string& source) {
  Daemon& d = api.daemon();
  const Pattern p = checked_pattern(nj.model_json, source, d.config().limits);
  const DeviceConfig* dev = d.planning_device(nj.target_device, nj.target_profile);
  if (!dev) fail(ApiError::no_device, "no device for this job", "device");
  try {
    // More copies than a sheet holds are cut sheet after sheet.
    drivers::plan_sheets_for_device(p, d.job_profile(*dev, nj.material), dev->profile_path, {nj.copies});
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    fail(ApiError::bad_model,
         "the pattern does not fit " + (nj.target_device.empty() ? "profile " + nj.target_profile : nj.target_device) +
             ": " + e.message(),
         "model");
  }
  return media_warnings(p.sheet, api.media());
}

// A mesh with popcut import's options: imported now, so its errors answer this request; the
// job then holds the imported model like any other. Returns the model's source for messages.
std::string job_from_upload(ApiContext& api, const Req& req, NewJob& nj) {
  MeshUpload u = import_upload(api, req, {"name", "device", "profile", "material", "copies"});
  if (u.fields.count("copies")) nj.copies = copies_field(json::parse(u.fields["copies"], nullptr, false));
  // Unnamed, the job is named after the file (house.obj: "house").
  if (u.fields.count("name") && u.fields["name"].empty())
    fail(ApiError::bad_request, "'name' is empty: leave it out to name the job after its file", "name");
  nj.name = u.fields.count("name") ? u.fields["name"] : fs::path(u.filename).stem().string();
  set_target(api.daemon(), nj, u.fields["device"], u.fields["profile"]);
  set_material(api.daemon(), nj, u.fields["material"]);
  nj.model_json = std::move(u.imported.model_json);
  return u.filename;
}

// {"name", "device" | "profile", "material", "model"}.
void job_from_json(ApiContext& api, const json& body, NewJob& nj) {
  if (!body.is_object()) fail(ApiError::bad_request, "the body must be a JSON object");
  for (const auto& [k, v] : body.items()) {
    if (k != "name" && k != "device" && k != "profile" && k != "material" && k != "model" && k != "copies")
      fail(ApiError::bad_request, "unknown field '" + k + "'", k);
  }
  if (body.contains("copies")) nj.copies = copies_field(body["copies"]);
  if (!body.contains("model")) fail(ApiError::bad_request, "missing field 'model'", "model");
  if (!body["model"].is_object())
    fail(ApiError::bad_request, "'model' must be a popcut.voxel.v1, popcut.faces.v1 or popcut.pattern.v1 object",
         "model");
  nj.name = string_field(body, "name", false);
  const bool named = body.contains("name") && !body["name"].is_null();
  if (named && nj.name.empty())
    fail(ApiError::bad_request, "'name' is empty: leave it out to name the job after its model", "name");
  if (!named) {
    // Unnamed, the job takes its model's name ("Castle gatehouse with towers"), else "card".
    const json& model_name = body["model"].value("name", json());
    const std::string label = model_name.is_string() ? job_label_from(model_name.get<std::string>()) : "";
    nj.name = label.empty() ? "card" : label;
  }
  set_target(api.daemon(), nj, string_field(body, "device", false), string_field(body, "profile", false));
  set_material(api.daemon(), nj, string_field(body, "material", false));
  nj.model_json = body["model"].dump();
}

// POST resume's optional body {"from": "received" | "executed"}; none (or {}) is "received".
ResumePoint resume_point(const Req& req) {
  if (req.body.empty()) return ResumePoint::received;
  const json body = parse_body(req);
  if (!body.is_object())
    fail(ApiError::bad_request, "the body must be a JSON object such as {\"from\": \"executed\"}, or empty");
  for (const auto& [k, v] : body.items()) {
    if (k != "from") fail(ApiError::bad_request, "unknown field '" + k + "' (resume takes 'from')", k);
  }
  const std::string from = string_field(body, "from", false);
  if (!body.contains("from") || body["from"].is_null()) return ResumePoint::received;
  const std::optional<ResumePoint> point = parse_resume_point(from);
  if (!point)
    fail(ApiError::bad_request,
         "'from' must be \"received\" (after the strokes the device certainly received, the default) or \"executed\" "
         "(after those it is known to have executed: for a device that was reset or power-cycled)",
         "from");
  return *point;
}

// Polls until job `id` is in a final state (or interrupted), at most `limit`.
void wait_for_final(Daemon& d, std::int64_t id, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    const std::optional<Job> j = d.store().get(id);
    if (!j || j->state != JobState::cutting) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace

void submit_job(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  NewJob nj;
  nj.owner = caller.name;
  nj.idempotency_key = idempotency_key(req);
  std::string source = "model";
  if (req.is_multipart_form_data()) {
    source = job_from_upload(api, req, nj);
  } else {
    job_from_json(api, parse_body(req), nj);
  }
  queue_job(api, nj, source, res);
}

void submit_json_job(ApiContext& api, const Caller& caller, const Req& req, const json& body, Res& res) {
  NewJob nj;
  nj.owner = caller.name;
  nj.idempotency_key = idempotency_key(req);
  job_from_json(api, body, nj);
  queue_job(api, nj, "model", res);
}

void queue_job(ApiContext& api, NewJob& nj, const std::string& source, Res& res) {
  Daemon& d = api.daemon();
  const std::vector<std::string> warnings = check_for_device(api, nj, source);
  if (!nj.idempotency_key.empty()) nj.request_sha256 = request_digest(nj);
  const SubmitResult r = d.store().submit(nj, d.config().limits.queue_length);
  switch (r.outcome) {
    case Submitted::created: break;
    case Submitted::replayed: {
      // The first answer again, as it stands now: a retry learns where its job is.
      res.set_header("Idempotent-Replayed", "true");
      json answer = current_job(d, r.id);
      answer["warnings"] = warnings;
      return send_json(res, answer, 200);
    }
    case Submitted::key_reused:
      fail(ApiError::key_reused,
           "this Idempotency-Key was used for job " + std::to_string(r.id) +
               ", a different submission; send a new key for a new job",
           "Idempotency-Key");
    case Submitted::queue_full:
      fail(ApiError::queue_full,
           "the queue holds " + std::to_string(d.config().limits.queue_length) + " unfinished jobs; try later");
  }
  ++api.counters().submitted;
  d.notify();
  json answer = current_job(d, r.id);
  answer["warnings"] = warnings;
  send_json(res, answer, 201);
}

void list_jobs(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  JobFilter filter = job_filter(req);
  if (!caller.admin()) filter.owner = caller.name;
  Daemon& d = api.daemon();
  json list = json::array();
  const std::vector<Job> jobs = d.store().list(filter);
  const bool any_ready = std::any_of(jobs.begin(), jobs.end(), [](const Job& j) { return j.state == JobState::ready; });
  const Forecast f = any_ready ? forecast(d) : Forecast();
  for (const Job& j : jobs) list.push_back(job_json(d, j, &f));
  send_json(res, {{"jobs", list}});
}

void patch_job(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  Daemon& d = api.daemon();
  const Job j = api.visible_job(req, caller);
  const Reorder to = reorder_request(req);
  const std::string id = "job " + std::to_string(j.id);
  if (to.before && *to.before == j.id) fail(ApiError::bad_request, "a job cannot be moved ahead of itself", "before");
  const std::string other = to.before ? "job " + std::to_string(*to.before) : "";
  switch (d.store().reorder(j.id, to)) {
    case ReorderResult::moved: break;
    case ReorderResult::not_found: fail(ApiError::not_found, "no " + id);
    case ReorderResult::not_waiting:
      fail(ApiError::conflict, "only a waiting job (queued, planning or ready) moves in the queue; " + id + " is " +
                                   to_string(d.store().get(j.id)->state));
    case ReorderResult::before_not_found: fail(ApiError::bad_request, "no " + other + " to move ahead of", "before");
    case ReorderResult::before_not_waiting:
      fail(ApiError::conflict,
           other + " is " + to_string(d.store().get(*to.before)->state) + ": a job moves only ahead of a waiting one",
           "before");
    case ReorderResult::priority_mismatch:
      fail(ApiError::bad_request,
           other + " has priority " + std::to_string(d.store().get(*to.before)->priority) +
               ": a job moved ahead of it takes that priority; leave 'priority' out or give the same",
           "priority");
  }
  d.notify();
  send_json(res, current_job(d, j.id));
}

void get_job(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  send_json(res, job_json(api.daemon(), api.visible_job(req, caller)));
}

void get_job_pattern(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const Job j = api.visible_job(req, caller);
  const fs::path svg = fs::path(api.daemon().job_dir(j.id)) / "pattern.svg";
  if (!fs::exists(svg))
    fail(ApiError::conflict, "job " + std::to_string(j.id) + " has no pattern (state " + to_string(j.state) + ")");
  res.set_content(read_text_file(svg.string(), std::size_t{64} << 20), "image/svg+xml");
}

void get_job_preview(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const Job j = api.visible_job(req, caller);
  const int angle = angle_param(req);
  Daemon& d = api.daemon();
  res.set_content(api.preview("job " + std::to_string(j.id) + " " + std::to_string(angle), angle,
                              [&] {
                                const std::optional<std::string> model = d.store().model_json(j.id);
                                if (!model) fail(ApiError::not_found, "no model for job " + std::to_string(j.id));
                                return checked_pattern(*model, "job", d.config().limits);
                              }),
                  "image/png");
}

void cancel_job(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  Daemon& d = api.daemon();
  const Job j = api.visible_job(req, caller);
  switch (d.cancel(j.id)) {
    case CancelResult::cancelled:
    case CancelResult::requested: break;
    case CancelResult::giving_up: {
      // The sender notices within one write slice (a quarter second) and the worker records the
      // job: answer with that outcome (200), or, should it take longer, with the job as it is (202).
      wait_for_final(d, j.id, std::chrono::seconds(10));
      const Job now = *d.store().get(j.id);
      return send_json(res, job_json(d, now), is_terminal(now.state) ? 200 : 202);
    }
    case CancelResult::already_final:
      fail(ApiError::conflict, "job " + std::to_string(j.id) + " is already " + to_string(d.store().get(j.id)->state));
    case CancelResult::not_found: fail(ApiError::not_found, "no job " + std::to_string(j.id));
  }
  send_json(res, current_job(d, j.id), 202);
}

void resume_job(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  Daemon& d = api.daemon();
  const Job j = api.visible_job(req, caller);
  const ResumePoint from = resume_point(req);
  // The rest of a half-cut sheet is cut on the device holding it: without that device, a
  // resume would wait for good.
  if (const std::string bound = j.bound_device();
      j.state == JobState::interrupted && !bound.empty() && !d.device(bound)) {
    fail(ApiError::conflict, "job " + std::to_string(j.id) + " was cut on " + bound +
                                 ", which holds its half-cut sheet and is not " +
                                 "configured any more; only that device may finish it: configure it again, or cancel "
                                 "the job and submit it anew");
  }
  switch (d.store().resume(j.id, from)) {
    case ResumeResult::resumed: break;
    case ResumeResult::not_interrupted:
      fail(ApiError::conflict, "only an interrupted job resumes; job " + std::to_string(j.id) + " is " +
                                   to_string(d.store().get(j.id)->state));
    case ResumeResult::executed_unknown:
      fail(ApiError::conflict,
           "job " + std::to_string(j.id) +
               ": the strokes the device executed are unknown (its transport gives no "
               "status answers, or the cut ended without asking, e.g. popcutd was killed), so there is no "
               "executed point to resume from; resume from \"received\" if the device kept its buffer",
           "from");
  }
  d.notify();
  send_json(res, current_job(d, j.id), 202);
}

// A pause keeps everything the device holds and cuts it: unlike a cancel it drops nothing, and
// the job is continued (not resumed) from the stroke after the last one cut.
void pause_job(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  Daemon& d = api.daemon();
  const Job j = api.visible_job(req, caller);
  switch (d.pause(j.id)) {
    case PauseResult::paused: return send_json(res, current_job(d, j.id), 200);
    case PauseResult::requested: return send_json(res, current_job(d, j.id), 202);
    case PauseResult::conflict:
      fail(ApiError::conflict, "only a ready or cutting job pauses; job " + std::to_string(j.id) + " is " +
                                   to_string(d.store().get(j.id)->state) +
                                   (d.store().get(j.id)->state == JobState::cutting ? " and being cancelled" : ""));
    case PauseResult::not_found: fail(ApiError::not_found, "no job " + std::to_string(j.id));
  }
}

void continue_job(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  Daemon& d = api.daemon();
  const Job j = api.visible_job(req, caller);
  // The rest of a half-cut sheet is cut on the device holding it, as for a resume.
  if (!j.device.empty() && !d.device(j.device)) {
    fail(ApiError::conflict, "job " + std::to_string(j.id) + " was paused on " + j.device +
                                 ", which is not configured any more; configure it again, or cancel the job");
  }
  switch (d.continue_job(j.id)) {
    case ContinueResult::continued: return send_json(res, current_job(d, j.id), 200);
    case ContinueResult::not_paused:
      fail(ApiError::conflict,
           "only a paused job continues; job " + std::to_string(j.id) + " is " + to_string(d.store().get(j.id)->state) +
               (d.store().get(j.id)->state == JobState::interrupted ? " (POST .../resume resumes it)" : ""));
    case ContinueResult::not_found: fail(ApiError::not_found, "no job " + std::to_string(j.id));
  }
}

}  // namespace popcut::daemon
