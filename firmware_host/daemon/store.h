// The job queue in SQLite (WAL): every state change is one committed transaction before anyone acts on it.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "job.h"
#include "stats.h"
#include "wear.h"

struct sqlite3;

namespace popcut::daemon {

struct NewJob {
  std::string owner, name, target_device, target_profile;
  std::string model_json;  // the model as submitted (popcut.voxel.v1 / popcut.faces.v1)
  std::string material{};  // configs/materials stem; empty: the profile's own forces
};

// giving_up: Daemon::cancel only, a repeated cancel of a cut whose stop waits for a device that
// holds the line: the wait is given up and the abort is not sent.
enum class CancelResult { cancelled, requested, giving_up, already_final, not_found };
// executed_unknown: resuming after the executed strokes was asked, but the device never said what
// it executed (a transport without status answers, or a cut cut short by a crash).
enum class ResumeResult { resumed, not_interrupted, executed_unknown };
// paused: a ready job is held at once; requested: a cutting one stops at the stroke in flight.
enum class PauseResult { paused, requested, conflict, not_found };
enum class ContinueResult { continued, not_paused, not_found };

// A cut's run ends at `end` (an SQL expression): its time since run_started_at is added to the
// job's cutting_s (store.cpp; store_pause.cpp ends a run at a pause with it).
std::string end_run(const std::string& end);

class JobStore {
 public:
  // Opens (creating) the database and `readers` extra connections for reads; throws
  // popcut::Error(io) naming the file.
  explicit JobStore(const std::string& path, int readers = 4);
  ~JobStore();
  JobStore(const JobStore&) = delete;
  JobStore& operator=(const JobStore&) = delete;

  // After a crash: a job that was cutting becomes interrupted (its strokes_sent stands), one
  // that was planning goes back to queued (planning is repeatable). Returns how many of each.
  struct Recovered {
    int interrupted = 0, requeued = 0;
    std::vector<std::int64_t> interrupted_ids;  // the jobs that were cutting
  };
  // `crashed_run_wear`: the wear of a run cut short by the crash (the strokes it certainly got to
  // the device), added to its job and device in the same transaction as its state change.
  Recovered recover(const std::function<Wear(const Job&)>& crashed_run_wear = {});

  // nullopt when `queue_length` unfinished jobs exist already.
  std::optional<std::int64_t> insert(const NewJob& job, int queue_length);
  std::optional<Job> get(std::int64_t id);
  std::optional<std::string> model_json(std::int64_t id);
  // Newest first; owner empty = everyone's.
  std::vector<Job> list(const std::string& owner, int limit);
  // Jobs waiting ahead of this one that a device it may go to could cut (queued, planning, ready).
  int place_in_line(const Job& job);
  // Every job waiting (queued, planning, ready), oldest first: what each may go to and the
  // cutting time it has left (0 while unplanned; a resumed one, after the strokes already cut).
  std::vector<WaitingJob> waiting();
  // The jobs being cut.
  std::vector<Job> cutting();

  // queued -> planning, oldest first.
  std::optional<Job> claim_for_planning();
  // planning -> ready (unless cancelled meanwhile).
  void set_planned(std::int64_t id, std::int64_t strokes_total, double est_time_s);
  // ready -> cutting on `device`, oldest first among jobs naming it or its profile.
  std::optional<Job> claim_for_device(const std::string& device, const std::string& profile_name);
  void set_progress(std::int64_t id, std::int64_t strokes_sent);
  // The last stroke the device is known to have executed at the end of a cut (nullopt: unknown).
  void set_executed(std::int64_t id, std::optional<std::int64_t> strokes_executed);
  // cutting/planning -> a final state (or interrupted); error code and message may be empty.
  void finish(std::int64_t id, JobState state, const std::string& error_code, const std::string& error_message,
              bool sim_match = false);
  // queued/planning/ready/interrupted -> cancelled at once; cutting -> cancel requested (the
  // device worker stops the cut and records it).
  CancelResult cancel(std::int64_t id);
  bool cancel_requested(std::int64_t id);
  // interrupted -> ready, continuing after the strokes the device certainly received, or after
  // those it is known to have executed (then strokes_sent drops to them too: a power-cycled
  // device holds nothing, and a crash before the next confirmation must not resume past them).
  // The choice is committed with the state, so a restart before the cut keeps it.
  ResumeResult resume(std::int64_t id, ResumePoint from = ResumePoint::received);

  // Pause and continue of one job (store_pause.cpp; docs/api.md "Pausing a cut"). ready ->
  // paused at once, cutting -> pause requested; anything else is a conflict.
  PauseResult request_pause(std::int64_t id);
  bool pause_requested(std::int64_t id);
  // cutting -> paused once the device drained and lifted the knife: the next run starts after
  // strokes_sent (every stroke through it is cut, no more), and this run's time ends now.
  void mark_paused(std::int64_t id, const std::string& message);
  // paused -> ready, on the device holding its sheet, continuing after resume_from.
  ContinueResult continue_job(std::int64_t id);
  // A paused job holds its half-cut sheet on `device`: no other job is cut there meanwhile.
  bool holds_paused_job(const std::string& device);

  void set_paused(const std::string& device, bool paused);
  bool paused(const std::string& device);
  // Jobs created, finished or cut since `since_s` (unix seconds), and any being cut: what
  // job_stats (stats.h) counts.
  std::vector<StatsRow> stats_rows(double since_s);
  std::map<std::string, std::int64_t> count_by_state();
  std::int64_t count_submitted();

  // Wear (store_wear.cpp). A run's wear is added to its job and its device in one transaction,
  // before the run's outcome is recorded: a crash between the two leaves the job `cutting`, and
  // recovery resumes it after strokes_sent; that wear counts no stroke past it, the next run none before.
  struct WearAdded {
    DeviceWear device;        // after the addition
    bool newly_worn = false;  // the blade passed blade_life_m with this run: raise blade_worn (once)
  };
  WearAdded add_run_wear(std::int64_t job_id, const std::string& device, const Wear& run,
                         std::optional<double> blade_life_m);
  DeviceWear device_wear(const std::string& device);
  // The blade was changed: its counters start again from now (the lifetime ones go on).
  DeviceWear reset_blade(const std::string& device);

 private:
  void create_wear_tables();
  // The addition itself, inside a transaction the caller holds (with mutex_).
  void add_wear_locked(std::int64_t job_id, const std::string& device, const Wear& run);
  void exec(const char* sql);
  bool has_column(const char* table, const char* column);
  void add_run_time_columns();
  void add_pause_column();
  // Reads run on their own connections: in WAL mode a reader sees the last commit and neither
  // waits for the writer nor holds it up. A free one if any, else the next in turn.
  struct Reader {
    sqlite3* db = nullptr;
    std::mutex mutex;
  };
  std::pair<sqlite3*, std::unique_lock<std::mutex>> reader();

  sqlite3* db_ = nullptr;  // every write, serialised by mutex_: SQLite's own write lock then never waits
  std::string path_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Reader>> readers_;
  std::atomic<std::size_t> next_reader_{0};
};

}  // namespace popcut::daemon
