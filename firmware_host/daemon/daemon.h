// popcutd's engine: the job store, planner threads and one worker thread per device.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "config.h"
#include "device_link.h"
#include "notifier.h"
#include "store.h"

namespace popcut::daemon {

struct SheetRun;

// Where a user's cancel of a cut stands (docs/api.md "Cancelling a cut"): asked; waiting for a
// device that holds the line to take the abort; the wait given up by a second cancel.
enum class CancelStage { none, requested, waiting_for_device, giving_up };
inline constexpr auto kCancelStageNames =
    enum_names<CancelStage>({{CancelStage::none, "none"},
                             {CancelStage::requested, "requested"},
                             {CancelStage::waiting_for_device, "waiting_for_device"},
                             {CancelStage::giving_up, "giving_up"}});
const char* to_string(CancelStage stage);

struct DeviceStatus {
  std::string name, profile, transport;
  bool paused = false;
  std::int64_t job = 0;      // the job cutting, 0 = idle
  double run_started_s = 0;  // unix seconds this run of it began (a resumed job's started_at is its first run's)
  double time_factor = 1;    // wall-clock seconds per planned second: a simulated cutter's slowdown and time scale
  CancelStage cancel = CancelStage::none;  // of the job being cut
};

// The events a job's committed state raises: job_done, job_failed, job_interrupted, and with
// them device_error when the device or its line failed (error code device_error).
std::vector<EventKind> outcome_events(const Job& job);
// A job as an event carries it: what it is, where it stands, what it cut.
nlohmann::json event_job_json(const Job& job);

class Daemon {
 public:
  // Opens data_dir/jobs.db, recovers after a crash (cutting -> interrupted), starts the threads.
  explicit Daemon(DaemonConfig config);
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  const DaemonConfig& config() const { return config_; }
  JobStore& store() { return store_; }

  // Wakes planners and workers: a job was queued or resumed, or a device resumed.
  void notify();
  // Cancel: queued..ready/interrupted at once; cutting: the device stops at a command boundary,
  // lifts the knife, and the worker records `cancelled`. Cancelled again while that stop waits
  // for a device holding the line: the wait is given up (giving_up); before then it changes nothing.
  CancelResult cancel(std::int64_t id);
  // Pause and continue of a job (daemon_pause.cpp; docs/api.md "Pausing a cut"): a cutting job
  // stops after the stroke in flight, drains, lifts the knife and is recorded paused.
  PauseResult pause(std::int64_t id);
  ContinueResult continue_job(std::int64_t id);
  void set_paused(const std::string& device, bool paused);
  std::vector<DeviceStatus> devices();
  const DeviceConfig* device(const std::string& name) const;
  // Profile key: the profile file's stem ("sim" for devices/sim.toml).
  static std::string profile_key(const DeviceConfig& d);
  bool has_profile(const std::string& key) const;
  // The device whose profile a job is planned for: the one it names, or the first with the
  // profile it names (every device with that profile cuts the same bytes). Null if none.
  const DeviceConfig* planning_device(const std::string& target_device, const std::string& target_profile) const;

  std::string job_dir(std::int64_t id) const;

  // The material of that name ([server] materials_dir), or null; the known names for messages.
  const drivers::Material* material(const std::string& name) const;
  std::string material_list() const;
  // The device's profile with the job's material applied (none: the profile as it is). Planning
  // and every cut or resume of the job use it, so a resume cuts with the same forces.
  drivers::DeviceProfile job_profile(const DeviceConfig& device, const std::string& material) const;

  // SIGTERM: stop planning, stop every cut safely (it becomes `interrupted`, resumable), join.
  void shutdown();
  JobStore::Recovered recovered() const { return recovered_; }
  std::uint64_t cuts_completed() const { return cuts_completed_; }

  // Raises an event for the webhooks (docs/api.md "Webhooks") and returns at once: the job as
  // committed (0: none) and the device ("": none). daemon_events.cpp.
  void emit_event(EventKind kind, std::int64_t job_id, const std::string& device);
  NotifyCounts notify_counts() const { return notifier_->counts(); }
  // The blade was changed: the device's blade counters start again. False while it cuts (a run
  // in progress would put its wear on the new blade).
  bool reset_blade(const std::string& device);
  // {"cut_mm", "knife_down_strokes", "score_mm", "perforate_mm", "life_m", "worn", "since"}.
  nlohmann::json blade(const std::string& device);

  // Sheets (sheets.cpp, docs/api.md "Sheets"): the device's as stored; a fresh one loaded (nullopt
  // while a job cuts on the device: nothing changed).
  DeviceSheet sheet(const std::string& device);
  SheetConfirmation confirm_sheet(const std::string& device);

 private:
  struct Worker {
    const DeviceConfig* device = nullptr;
    std::thread thread;
    std::atomic<std::int64_t> job{0};
    std::atomic<double> run_started_s{0};
    std::atomic<bool> stop_cut{false};
    std::atomic<bool> cancel_waiting{false};  // the stop waits for the device to let the abort through
    std::atomic<bool> give_up{false};         // ... and a second cancel gave that wait up
    std::atomic<bool> pause_cut{false};       // a pause of the job being cut (daemon_pause.cpp)
    bool user_cancel = false;                 // guarded by mutex_: why stop_cut was set
    // The device thread's own: until when a device paced by time may still be cutting what the
    // last job left in its buffer (no job is sent to it before).
    std::chrono::steady_clock::time_point busy_until{};
    // A device without confirm_sheet whose tray may be reported empty (at start, or since it was):
    // asked again before its next claim.
    bool sheet_check = true;
  };
  // How long a device without confirm_sheet that said "no sheet loaded" is left before it is asked again.
  static constexpr std::chrono::seconds kNoSheetRetry{5};
  void plan_loop();
  void plan_one(const Job& job);
  void device_loop(Worker& w);
  void cut_one(Worker& w, const Job& job);
  // A run's outcome (`run` in its sheet's stroke numbers) recorded for the job: the next sheet, or
  // the job's end, pause or interruption, and its events.
  void close_run(Worker& w, const Job& job, const SheetRun& sheet, const CutOutcome& run);
  bool wait_for_work();
  // After a run: its wear committed, then the events its outcome calls for (daemon_events.cpp).
  void commit_run_wear(const Job& job, const DeviceConfig& dev, const StrokePlan& plan,
                       const drivers::DeviceProfile& profile, const CutOutcome& out);
  void emit_outcome(std::int64_t job_id);
  // A job on `dev` ended (or was found cut short at a restart): a confirm_sheet device now awaits
  // a fresh sheet, which is logged and raised as awaiting_sheet.
  void sheet_after_job(const DeviceConfig& dev, std::int64_t job_id);
  // The device said "no sheet loaded" before the job's first byte: the job goes back in line, the
  // sheet is `empty`, awaiting_sheet is raised (true); false for any other outcome (sheets.cpp).
  bool sheet_reported_empty(Worker& w, const Job& job, const CutOutcome& out);
  // Before a claim: an empty tray on a device that confirms no sheets is asked about again.
  void ask_again_for_sheet(Worker& w);
  // A run cut short by a crash: the strokes it certainly got to the device (after resume_from,
  // up to strokes_sent), counted at the restart.
  Wear crashed_run_wear(const Job& job) const;

  // Held for the daemon's life: a second popcutd on the same data_dir would take over (and
  // mark interrupted) jobs this one is cutting.
  class DataDirLock {
   public:
    explicit DataDirLock(const std::string& data_dir);
    ~DataDirLock();
    DataDirLock(const DataDirLock&) = delete;
    DataDirLock& operator=(const DataDirLock&) = delete;

   private:
    int fd_ = -1;
  };

  DaemonConfig config_;
  DataDirLock lock_;
  JobStore store_;
  JobStore::Recovered recovered_;
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> cuts_completed_{0};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::uint64_t generation_ = 0;  // bumped by notify(): a wait that saw it change has work to look at
  std::vector<std::thread> planners_;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::unique_ptr<Notifier> notifier_;  // outlives the threads: they are joined in ~Daemon's body
};

}  // namespace popcut::daemon
