// What popcutd tells the webhooks: the events of a job's outcome, the wear of each run, and their bodies.
#include <filesystem>

#include "../report_json.h"
#include "cut_job.h"
#include "daemon.h"
#include "log.h"
#include "popcut/io/files.h"

namespace popcut::daemon {

std::vector<EventKind> outcome_events(const Job& j) {
  std::vector<EventKind> out;
  switch (j.state) {
    case JobState::done: out.push_back(EventKind::job_done); break;
    case JobState::failed: out.push_back(EventKind::job_failed); break;
    case JobState::interrupted: out.push_back(EventKind::job_interrupted); break;
    default: break;  // cancelled: its user asked for it; the rest are not outcomes
  }
  if (j.error_code == to_string(ApiError::device_error)) out.push_back(EventKind::device_error);
  return out;
}

nlohmann::json event_job_json(const Job& j) {
  const auto text = [](const std::string& s) { return s.empty() ? nlohmann::json(nullptr) : nlohmann::json(s); };
  nlohmann::json r = {
      {"id", j.id},
      {"name", j.name},
      {"owner", j.owner},
      {"state", to_string(j.state)},
      {"device", text(j.target_device)},
      {"profile", j.target_profile},
      {"material", text(j.material)},
      {"cut_on", text(j.device)},
      {"strokes_total", j.strokes_total},
      {"strokes_sent", j.strokes_sent},
      {"strokes_executed", j.strokes_executed ? nlohmann::json(*j.strokes_executed) : nlohmann::json(nullptr)},
      {"resume_from", j.resume_from},
      {"cut_mm", j.cut_mm},
      {"knife_down_strokes", j.knife_down_strokes},
      {"created_at", j.created_at},
      {"started_at", j.started_at > 0 ? nlohmann::json(j.started_at) : nlohmann::json(nullptr)},
      {"finished_at", j.finished_at > 0 ? nlohmann::json(j.finished_at) : nlohmann::json(nullptr)},
      {"error", nullptr}};
  if (!j.error_code.empty() || !j.error_message.empty())
    r["error"] = {{"code", j.error_code}, {"message", j.error_message}};
  return rounded_numbers(std::move(r));
}

nlohmann::json Daemon::blade(const std::string& name) {
  const DeviceConfig* d = device(name);
  const DeviceWear w = store_.device_wear(name);
  const std::optional<double> life_m = d ? d->blade_life_m : std::nullopt;
  return rounded_numbers({{"cut_mm", w.blade.cut_mm},
                          {"knife_down_strokes", w.blade.knife_down_strokes},
                          {"score_mm", w.blade.score_mm},
                          {"perforate_mm", w.blade.perforate_mm},
                          {"life_m", life_m ? nlohmann::json(*life_m) : nlohmann::json(nullptr)},
                          {"worn", blade_worn(w, life_m)},
                          {"since", w.since_s > 0 ? nlohmann::json(w.since_s) : nlohmann::json(nullptr)}});
}

bool Daemon::reset_blade(const std::string& name) {
  for (auto& w : workers_) {
    if (w->device->name == name && w->job != 0) return false;
  }
  store_.reset_blade(name);
  log_line(name, ": blade changed; its counters start again");
  return true;
}

void Daemon::emit_event(EventKind kind, std::int64_t job_id, const std::string& device_name) {
  if (!notifier_->wants(kind)) return;  // no endpoint takes it: nothing to read
  Event e{kind, unix_now_s(), nullptr, nullptr};
  if (job_id != 0) {
    if (const std::optional<Job> j = store_.get(job_id)) e.job = event_job_json(*j);
  }
  if (const DeviceConfig* d = device(device_name)) {
    e.device = {{"name", d->name}, {"profile", profile_key(*d)}, {"blade", blade(d->name)}};
  }
  notifier_->emit(std::move(e));
}

void Daemon::emit_outcome(std::int64_t job_id) {
  const std::optional<Job> j = store_.get(job_id);
  if (!j) return;
  for (const EventKind kind : outcome_events(*j)) emit_event(kind, job_id, j->device);
}

void Daemon::commit_run_wear(const Job& job, const DeviceConfig& dev, const StrokePlan& plan,
                             const drivers::DeviceProfile& profile, const CutOutcome& out) {
  const std::size_t first = static_cast<std::size_t>(job.resume_from) + 1;
  const Wear run = wear_of(plan, profile.plan.kinds, first, wear_counted_through(out, first));
  const JobStore::WearAdded added = store_.add_run_wear(job.id, dev.name, run, dev.blade_life_m);
  if (added.newly_worn) {
    log_line(dev.name, ": the blade has cut ", added.device.blade.cut_mm / 1000, " m, past blade_life_m ",
             dev.blade_life_m.value_or(0), ": change it, then POST /api/v1/devices/", dev.name, "/blade");
    emit_event(EventKind::blade_worn, job.id, dev.name);
  }
}

Wear Daemon::crashed_run_wear(const Job& j) const {
  const DeviceConfig* dev = device(j.device);
  if (!dev) return {};  // no longer configured: nowhere to count it
  try {
    // A run stays on one sheet: its strokes in that sheet's numbers.
    const SheetRun sheet = sheet_run(job_dir(j.id), j, j.resume_from);
    return wear_of(sheet.plan, job_profile(*dev, j.material).plan.kinds,
                   static_cast<std::size_t>(j.resume_from - sheet.offset) + 1,
                   static_cast<std::size_t>(j.strokes_sent - sheet.offset));
  } catch (const std::exception& e) {
    log_line("job ", j.id, ": the wear of its run cut short is not counted: ", e.what());
    return {};
  }
}

}  // namespace popcut::daemon
