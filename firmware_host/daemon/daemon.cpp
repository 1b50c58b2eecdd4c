// popcutd's threads: planners turn queued models into encoded-ready plans; each device worker
// claims ready jobs for its device and cuts them, committing every state change first.
#include "daemon.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "cut_job.h"
#include "device_link.h"
#include "log.h"
#include "model_limits.h"
#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/language.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/io/pattern_io.h"

namespace popcut::daemon {
namespace {

using namespace std::chrono_literals;

std::string jobs_db(const DaemonConfig& c) { return (std::filesystem::path(c.data_dir) / "jobs.db").string(); }

// Commits a cut's outcome as the job's final state (done, cancelled, interrupted or failed) with
// the message its user reads; `user_cancel`: the stop was a cancel, not popcutd shutting down.
void record_outcome(JobStore& store, const Job& job, const DeviceConfig& dev, bool user_cancel, const CutOutcome& out) {
  switch (out.kind) {
    case CutOutcome::Kind::complete: store.finish(job.id, JobState::done, "", "", out.sim_match); break;
    case CutOutcome::Kind::stopped:
      // What the device may still cut from its buffer: nothing after an abort it honours
      // (the profile's abort discards the buffer on HP-style devices), all of it when the abort
      // did not reach it.
      if (user_cancel) {
        store.finish(
            job.id, JobState::cancelled, to_string(out.abort_sent ? ApiError::cancelled : ApiError::device_error),
            out.abort_sent
                ? "cancelled during the cut; the knife was lifted" + (out.discarded.empty() ? "" : "; " + out.discarded)
                : "cancelled during the cut: " + out.error + "; the device may still cut " + out.still_buffered +
                      " from its buffer");
      } else {
        store.finish(job.id, JobState::interrupted,
                     to_string(out.abort_sent ? ApiError::interrupted : ApiError::device_error),
                     out.abort_sent ? "popcutd stopped during the cut; the knife was lifted" +
                                          (out.discarded.empty() ? "" : "; " + out.discarded)
                                    : "popcutd stopped during the cut: " + out.error + "; the device may still cut " +
                                          out.still_buffered + " from its buffer");
      }
      break;
    case CutOutcome::Kind::paused:
      store.mark_paused(job.id, "paused after stroke " + std::to_string(out.last_stroke_sent) +
                                    "; the knife was lifted and the device drained: continue cuts the rest");
      break;
    case CutOutcome::Kind::failed:
      if (out.bytes_lost) {
        // Not resumable: the device cut something else than the job.
        store.finish(
            job.id, JobState::failed, to_string(ApiError::device_error),
            out.error +
                "; what it cut is not the job: fix the device's profile (or the line) and submit the job again");
        log_line("job ", job.id, ": ", dev.name, " lost bytes: ", out.error);
        break;
      }
      // The cutter may be fixed and the job resumed from the last stroke fully sent.
      store.finish(job.id, JobState::interrupted, to_string(ApiError::device_error), out.error);
      log_line("job ", job.id, ": ", dev.name, " failed: ", out.error);
      break;
  }
}

}  // namespace

Daemon::DataDirLock::DataDirLock(const std::string& data_dir) {
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(data_dir) / "jobs", ec);
  if (ec)
    throw Error(ErrorCode::io, data_dir, "[server] data_dir", "cannot create the data directory: " + ec.message());
  const std::string path = (std::filesystem::path(data_dir) / "popcutd.lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw Error(ErrorCode::io, path, "[server] data_dir",
                std::string("cannot open the lock file: ") + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd_);
    throw Error(ErrorCode::io, data_dir, "[server] data_dir",
                err == EWOULDBLOCK
                    ? "in use by another popcutd (it holds " + path + "); stop it or give another --data-dir"
                    : std::string("cannot lock ") + path + ": " + std::strerror(err));
  }
}

Daemon::DataDirLock::~DataDirLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

Daemon::Daemon(DaemonConfig config) : config_(std::move(config)), lock_(config_.data_dir), store_(jobs_db(config_)) {
  notifier_ = std::make_unique<Notifier>(config_.notify);
  recovered_ = store_.recover([this](const Job& j) { return crashed_run_wear(j); });
  for (const std::int64_t id : recovered_.interrupted_ids) {
    emit_outcome(id);
    if (const std::optional<Job> j = store_.get(id); j && device(j->device)) sheet_after_job(*device(j->device), id);
  }
  for (int i = 0; i < config_.planners; ++i) planners_.emplace_back([this] { plan_loop(); });
  for (const DeviceConfig& d : config_.devices) {
    auto w = std::make_unique<Worker>();
    w->device = &d;
    workers_.push_back(std::move(w));
  }
  for (auto& w : workers_) w->thread = std::thread([this, wp = w.get()] { device_loop(*wp); });
}

Daemon::~Daemon() { shutdown(); }

void Daemon::notify() {
  {
    std::lock_guard lock(mutex_);
    ++generation_;
  }
  wake_.notify_all();
}

bool Daemon::wait_for_work() {
  std::unique_lock lock(mutex_);
  const std::uint64_t seen = generation_;
  // The timeout covers changes made by another process on the same database (none today) and
  // keeps a lost wake-up from stalling a queue.
  wake_.wait_for(lock, 1s, [&] { return stopping_ || generation_ != seen; });
  return !stopping_;
}

void Daemon::shutdown() {
  if (stopping_.exchange(true)) return;
  for (auto& w : workers_) w->stop_cut = true;
  wake_.notify_all();
  for (auto& t : planners_) t.join();
  for (auto& w : workers_) w->thread.join();
}

std::string Daemon::profile_key(const DeviceConfig& d) { return std::filesystem::path(d.profile_path).stem().string(); }

bool Daemon::has_profile(const std::string& key) const {
  for (const DeviceConfig& d : config_.devices) {
    if (profile_key(d) == key) return true;
  }
  return false;
}

const DeviceConfig* Daemon::device(const std::string& name) const {
  for (const DeviceConfig& d : config_.devices) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

std::string Daemon::job_dir(std::int64_t id) const {
  return (std::filesystem::path(config_.data_dir) / "jobs" / std::to_string(id)).string();
}

const char* to_string(CancelStage stage) { return kCancelStageNames.name(stage).data(); }

CancelResult Daemon::cancel(std::int64_t id) {
  CancelResult r = store_.cancel(id);
  if (r == CancelResult::requested) {
    std::lock_guard lock(mutex_);
    for (auto& w : workers_) {
      if (w->job != id) continue;
      // The second cancel gives up only a wait the user was told of (the job showed
      // waiting_for_device), as a second Ctrl-C does in popcut cut; earlier it is absorbed.
      if (w->user_cancel && w->cancel_waiting) {
        w->give_up = true;
        r = CancelResult::giving_up;
      }
      w->user_cancel = true;
      w->stop_cut = true;
    }
  }
  return r;
}

void Daemon::set_paused(const std::string& device, bool paused) {
  store_.set_paused(device, paused);
  notify();
}

std::vector<DeviceStatus> Daemon::devices() {
  std::vector<DeviceStatus> out;
  for (auto& w : workers_) {
    const DeviceConfig& d = *w->device;
    const double time_factor = d.transport == "sim" ? d.sim_slowdown * d.sim_time_scale : 1.0;
    CancelStage cancel = CancelStage::none;
    {
      std::lock_guard lock(mutex_);
      if (w->user_cancel) {
        cancel = w->give_up          ? CancelStage::giving_up
                 : w->cancel_waiting ? CancelStage::waiting_for_device
                                     : CancelStage::requested;
      }
    }
    out.push_back({d.name, profile_key(d), d.transport, store_.paused(d.name), w->job.load(), w->run_started_s.load(),
                   time_factor, cancel});
  }
  return out;
}

void Daemon::plan_loop() {
  while (!stopping_) {
    std::optional<Job> job = store_.claim_for_planning();
    if (!job) {
      wait_for_work();
      continue;
    }
    plan_one(*job);
    notify();
  }
}

const drivers::Material* Daemon::material(const std::string& name) const {
  for (const drivers::Material& m : config_.materials) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

std::string Daemon::material_list() const {
  std::string out;
  for (const drivers::Material& m : config_.materials) out += (out.empty() ? "" : ", ") + m.name;
  return out.empty() ? "none" : out;
}

drivers::DeviceProfile Daemon::job_profile(const DeviceConfig& device, const std::string& material_name) const {
  drivers::DeviceProfile profile = device.profile;
  if (material_name.empty()) return profile;
  const drivers::Material* m = material(material_name);
  if (!m) {
    throw Error(ErrorCode::invalid_input, "job", "material",
                "unknown material \"" + material_name + "\" (known: " + material_list() + ")");
  }
  drivers::apply_material(profile, *m);
  return profile;
}

const DeviceConfig* Daemon::planning_device(const std::string& target_device, const std::string& target_profile) const {
  for (const DeviceConfig& d : config_.devices) {
    if (target_device.empty() ? profile_key(d) == target_profile : d.name == target_device) return &d;
  }
  return nullptr;
}

void Daemon::plan_one(const Job& job) {
  try {
    const DeviceConfig* dev = planning_device(job.target_device, job.target_profile);
    if (!dev) throw Error(ErrorCode::invalid_input, "job", "device", "no configured device for this job any more");
    const std::optional<std::string> text = store_.model_json(job.id);
    if (!text) throw Error(ErrorCode::internal, "job", "model", "the model is missing from the database");
    const Pattern pattern = checked_pattern(*text, "job " + std::to_string(job.id), config_.limits);
    // As `popcut cut` plans it; a sheet that does not fit the device is refused now, not at the cutter.
    // More copies than a sheet holds go on as many sheets as they take (cut_job.h, sheet_run).
    const drivers::SheetPlans planned =
        drivers::plan_sheets_for_device(pattern, job_profile(*dev, job.material), dev->profile_path, {job.copies});
    const std::filesystem::path dir = job_dir(job.id);
    std::filesystem::create_directories(dir);
    write_text_file((dir / "pattern.svg").string(), [&](std::ostream& o) { write_pattern_svg(o, pattern, {true}); });
    write_text_file((dir / "plan.json").string(), [&](std::ostream& o) { o << plan_to_json(planned.full.plan); });
    if (planned.last) {
      write_text_file((dir / "plan-last.json").string(),
                      [&](std::ostream& o) { o << plan_to_json(planned.last->plan); });
    }
    // Committed last: a job is ready only once its files are on disk.
    const bool sheets = planned.sheets > 1;
    store_.set_planned(job.id, static_cast<std::int64_t>(planned.total_strokes()), planned.total_time_s(),
                       sheets ? planned.per_sheet : 0,
                       sheets ? static_cast<std::int64_t>(planned.full.encoded.total_strokes) : 0);
  } catch (const Error& e) {
    const bool user = e.code() == ErrorCode::invalid_input || e.code() == ErrorCode::limit;
    store_.finish(job.id, JobState::failed,
                  to_string(user ? (e.code() == ErrorCode::limit ? ApiError::model_too_complex : ApiError::bad_model)
                                 : ApiError::internal),
                  e.what());
    log_line("job ", job.id, ": planning failed: ", e.what());
    emit_outcome(job.id);
  } catch (const std::exception& e) {
    store_.finish(job.id, JobState::failed, to_string(ApiError::internal), e.what());
    log_line("job ", job.id, ": planning failed: ", e.what());
    emit_outcome(job.id);
  }
}

void Daemon::device_loop(Worker& w) {
  const std::string profile = profile_key(*w.device);
  while (!stopping_) {
    // A device paced by time may still be cutting what a stopped job left in its buffer.
    if (const auto now = std::chrono::steady_clock::now(); now < w.busy_until) {
      std::this_thread::sleep_for(
          std::min<std::chrono::steady_clock::duration>(w.busy_until - now, std::chrono::milliseconds(200)));
      continue;
    }
    ask_again_for_sheet(w);
    std::optional<Job> job;
    // A paused job holds its half-cut sheet on the device: nothing else is cut onto it.
    if (!store_.paused(w.device->name) && !store_.holds_paused_job(w.device->name))
      job = store_.claim_for_device(w.device->name, profile, w.device->confirm_sheet);
    if (!job) {
      wait_for_work();
      continue;
    }
    {
      std::lock_guard lock(mutex_);
      w.job = job->id;
      w.run_started_s = unix_now_s();
      w.user_cancel = false;
      w.cancel_waiting = false;
      w.give_up = false;
      w.stop_cut = stopping_.load();
      w.pause_cut = false;
    }
    // Likewise a pause (the job was claimed between the request and now).
    if (store_.pause_requested(job->id)) w.pause_cut = true;
    // A cancel that arrived between the claim and now is in the database only.
    if (store_.cancel_requested(job->id)) {
      std::lock_guard lock(mutex_);
      w.user_cancel = true;
      w.stop_cut = true;
    }
    cut_one(w, *job);
    {
      std::lock_guard lock(mutex_);
      w.job = 0;
    }
    sheet_after_job(*w.device, job->id);
    notify();
  }
}

void Daemon::cut_one(Worker& w, const Job& job) {
  const DeviceConfig& dev = *w.device;
  try {
    // resume_from strokes were fully sent by an earlier run: this one starts at the next.
    const std::int64_t done_before = job.resume_from;
    if (done_before >= job.strokes_total) {
      // Killed after the last byte went out but before the drain was confirmed: nothing to send.
      // A done job carries no error; this run's (empty) remainder trivially matches the plan.
      log_line("job ", job.id, ": every stroke had been received before the restart; done");
      store_.finish(job.id, JobState::done, "", "", true);
      emit_outcome(job.id);
      return;
    }
    // The run in its sheet's own numbering (the job's less sheet.offset): one sheet per run.
    const SheetRun sheet = sheet_run(job_dir(job.id), job, done_before);
    Job local = job;
    local.resume_from = done_before - sheet.offset;
    const std::size_t first = static_cast<std::size_t>(local.resume_from) + 1;
    const drivers::DeviceProfile profile = job_profile(dev, job.material);
    const EncodedJob cut = drivers::encode_for_device(sheet.plan, profile, first);
    log_line("job ", job.id, ": cutting on ", dev.name, " from stroke ", done_before + 1, " of ", job.strokes_total,
             job.sheets() > 1
                 ? " (sheet " + std::to_string(sheet.sheet + 1) + " of " + std::to_string(job.sheets()) + ")"
                 : std::string());
    const std::unique_ptr<DeviceLink> link = make_device_link(dev);
    // Logged before the job shows it: whoever sees waiting_for_device finds the line in the log.
    const CutControl control{
        w.stop_cut, w.give_up,
        [&] {
          // A user's cancel can be given up by cancelling again; popcutd's own stop waits it out.
          log_line("job ", job.id, ": ", dev.name, " holds the line (XOFF or CTS): waiting up to ",
                   dev.profile.transport.hold_timeout_ms / 1000, " s (hold_timeout_ms) for it to take the abort",
                   stopping_ ? " before popcutd stops"
                             : "; cancelling again gives up, and the device may then cut everything its buffer holds");
          w.cancel_waiting = true;
        },
        &w.pause_cut};
    // Held against the whole plan from the resumed stroke on, worked out apart from the bytes
    // sent: a resume that started at the wrong stroke shows in sim_match.
    const std::vector<PlotterPath> planned = drivers::planned_paths(sheet.plan, dev.profile.dialect, first);
    const CutOutcome out = link->cut(cut, planned, control, [&](std::size_t last) {
      store_.set_progress(job.id, sheet.offset + static_cast<std::int64_t>(last));
    });
    if (sheet_reported_empty(w, job, out)) return;
    if (out.busy_for_s > 0) {
      w.busy_until =
          std::chrono::steady_clock::now() + std::chrono::milliseconds(static_cast<long>(out.busy_for_s * 1000) + 1);
      log_line("job ", job.id, ": ", dev.name, " has no handshake and may go on cutting for up to ",
               static_cast<long>(out.busy_for_s + 0.999), " s by the profile's pace: no job is sent to it before then");
    }
    commit_run_wear(local, dev, sheet.plan, profile, out);
    close_run(w, job, sheet, out);
  } catch (const std::exception& e) {
    store_.finish(job.id, JobState::failed, to_string(ApiError::internal), e.what());
    log_line("job ", job.id, ": ", e.what());
    emit_outcome(job.id);
  }
}

void Daemon::close_run(Worker& w, const Job& job, const SheetRun& sheet, const CutOutcome& run) {
  const DeviceConfig& dev = *w.device;
  CutOutcome out = run;  // in the job's stroke numbers
  const auto offset = static_cast<std::size_t>(sheet.offset);
  out.last_stroke_sent += offset;
  if (out.last_stroke_executed) *out.last_stroke_executed += offset;
  store_.set_progress(job.id, static_cast<std::int64_t>(out.last_stroke_sent));
  store_.set_executed(job.id, out.last_stroke_executed
                                  ? std::optional<std::int64_t>(static_cast<std::int64_t>(*out.last_stroke_executed))
                                  : std::nullopt);
  if (out.kind == CutOutcome::Kind::complete) ++cuts_completed_;
  bool user_cancel;
  {
    std::lock_guard lock(mutex_);
    user_cancel = w.user_cancel;
  }
  if (out.kind == CutOutcome::Kind::complete && sheet.sheet + 1 < job.sheets() && user_cancel) {
    // Cancelled as the sheet's last strokes went out: that sheet is whole, no other is cut.
    store_.finish(job.id, JobState::cancelled, to_string(ApiError::cancelled),
                  "cancelled during sheet " + std::to_string(sheet.sheet + 1) + " of " + std::to_string(job.sheets()) +
                      ", which was cut whole; the sheets after it were not cut");
    emit_outcome(job.id);
    return;
  }
  if (out.kind == CutOutcome::Kind::complete && sheet.sheet + 1 < job.sheets()) {
    // A full sheet and more to come: the job waits in its place for the next (device_loop's
    // sheet_after_job asks for a fresh one where sheets are confirmed).
    store_.sheet_full(job.id, dev.name, sheet.offset + job.sheet_strokes, dev.confirm_sheet);
    log_line("job ", job.id, ": sheet ", sheet.sheet + 1, " of ", job.sheets(), " cut on ", dev.name,
             dev.confirm_sheet ? "; its next sheet waits for a fresh one" : "");
    return;
  }
  record_outcome(store_, job, dev, user_cancel, out);
  if (out.kind == CutOutcome::Kind::paused) {
    log_line("job ", job.id, ": paused on ", dev.name, " after stroke ", out.last_stroke_sent);
    emit_event(EventKind::job_paused, job.id, dev.name);
  }
  emit_outcome(job.id);
}

}  // namespace popcut::daemon
