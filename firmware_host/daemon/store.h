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
#include "sheets.h"
#include "stats.h"
#include "wear.h"

struct sqlite3;

namespace popcut::daemon {

struct NewJob {
  std::string owner, name, target_device, target_profile;
  std::string model_json;  // the model as submitted (popcut.voxel.v1 / popcut.faces.v1)
  std::string material{};  // configs/materials stem; empty: the profile's own forces
  int copies = 1;          // cards nested on the one sheet (drivers::Copies)
  // Idempotency-Key (empty: none) and a digest of what was asked: a retry with the same key and
  // the same request is answered with the first job (docs/api.md "Idempotent submission").
  std::string idempotency_key{}, request_sha256{};
};

// What a submission became. replayed: the key was seen with the same request (id: that job);
// key_reused: with another request; queue_full: [limits] queue_length unfinished jobs already.
enum class Submitted { created, replayed, key_reused, queue_full };
struct SubmitResult {
  Submitted outcome = Submitted::created;
  std::int64_t id = 0;
};
// How long popcutd remembers an Idempotency-Key.
inline constexpr double kIdempotencyKeepS = 24 * 3600;

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

// What GET /api/v1/jobs lists: each part empty takes every job.
struct JobFilter {
  std::string owner;              // empty: everyone's
  std::vector<JobState> states;   // empty: any state
  std::string device;             // cut on it, or (not cut yet) naming it
  std::optional<double> since_s;  // created or finished at or after (unix seconds)
  int limit = 100;
};

// An admin's move (PATCH /api/v1/jobs/N): a new priority, or the place just ahead of `before`
// (taking that job's priority), or both when they agree.
struct Reorder {
  std::optional<int> priority;
  std::optional<std::int64_t> before;
};
// priority_mismatch: `priority` and `before` given, and `before` has another priority.
enum class ReorderResult { moved, not_found, not_waiting, before_not_found, before_not_waiting, priority_mismatch };

// A designer's draft (store_designs.cpp): the popcut.design.v1 document as last saved, per owner.
struct DesignDraft {
  std::int64_t id = 0;
  std::string owner, name, document;
  std::size_t items = 0;
  double created_s = 0, updated_s = 0;
};

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

  // nullopt when `queue_length` unfinished jobs exist already (or the key was used for another request).
  std::optional<std::int64_t> insert(const NewJob& job, int queue_length);
  // insert, with the job's Idempotency-Key looked up and recorded in the same transaction.
  SubmitResult submit(const NewJob& job, int queue_length);
  std::optional<Job> get(std::int64_t id);
  std::optional<std::string> model_json(std::int64_t id);
  // Newest first, those `filter` takes.
  std::vector<Job> list(const JobFilter& filter);
  // Jobs waiting ahead of this one that a device it may go to could cut (queued, planning, ready).
  int place_in_line(const Job& job);
  // Every job waiting (queued, planning, ready), in the queue's order: what each may go to and the
  // cutting time it has left (0 while unplanned; a resumed one, after the strokes already cut).
  std::vector<WaitingJob> waiting();
  // The jobs being cut.
  std::vector<Job> cutting();

  // queued -> planning, first in the queue's order (priority, then rank).
  std::optional<Job> claim_for_planning();
  // planning -> ready (unless cancelled meanwhile).
  // With sheet_copies > 0 the job spans sheets (Job::sheets), each full one sheet_strokes long.
  void set_planned(std::int64_t id, std::int64_t strokes_total, double est_time_s, int sheet_copies = 0,
                   std::int64_t sheet_strokes = 0);
  // ready -> cutting on `device`, first in the queue's order among jobs naming it or its profile.
  // With `confirm_sheet`, only onto a loaded sheet (or the job a used one holds, resumed), which the
  // claim marks used in the same transaction: docs/api.md "Sheets".
  std::optional<Job> claim_for_device(const std::string& device, const std::string& profile_name,
                                      bool confirm_sheet = false);
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

  // Moves a waiting job (store_queue.cpp); place_in_line, eta_s and the claims follow the new order.
  ReorderResult reorder(std::int64_t id, const Reorder& to);
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

  // Sheets (store_sheets.cpp).
  DeviceSheet device_sheet(const std::string& device);
  // A fresh sheet is loaded; nullopt (and nothing changed) while a job is cutting on the device.
  SheetConfirmation confirm_sheet(const std::string& device);
  // The device said before the job's first byte that no sheet is loaded: a job that had not
  // started goes back to `ready` in its place and the device's sheet is `empty` (true); a resumed
  // one, or one with a cancel or pause asked, is left to its outcome (false).
  bool back_for_no_sheet(std::int64_t job_id, const std::string& device);
  // A device that confirms no sheets, once its tray was reported empty: asked again at its next
  // job (true when it was empty).
  bool ask_again_for_sheet(const std::string& device);
  // A job's sheet is cut and more follow: back to `ready` in its place, strokes through `next_from`
  // done, on no device (its next sheet may go to any of its devices); the device's sheet is `full`
  // and, with `confirm_sheet`, waits for a fresh one (docs/api.md "Sheets").
  void sheet_full(std::int64_t job_id, const std::string& device, std::int64_t next_from, bool confirm_sheet);

  // Designer drafts (store_designs.cpp). Each edit saves the whole document: a draft survives a
  // restart as the items it had (undo history lives in the session only).
  std::int64_t create_design(const std::string& owner, const std::string& name, const std::string& document,
                             std::size_t items);
  void save_design(std::int64_t id, const std::string& name, const std::string& document, std::size_t items);
  std::optional<DesignDraft> design(std::int64_t id);
  // Newest first, without their documents; an empty owner lists everyone's.
  std::vector<DesignDraft> list_designs(const std::string& owner, int limit);
  bool delete_design(std::int64_t id);

 private:
  void create_design_tables();
  void create_sheet_tables();
  // Inside a transaction the caller holds: 0 any job may be claimed onto the device's sheet, a
  // job id only that one, nullopt none; and the claim of `job_id` using it.
  // An empty tray allows none, whatever `confirm_sheet`.
  std::optional<std::int64_t> sheet_allows_locked(const std::string& device, bool confirm_sheet);
  void use_sheet_locked(const std::string& device, std::int64_t job_id);
  // `job`, claimed onto its own used sheet, would start its next sheet there (it was cut short
  // just after a sheet's last stroke): that sheet is full instead, and the job on no device (true).
  bool sheet_filled_locked(const Job& job, const std::string& device);
  void create_wear_tables();
  // The addition itself, inside a transaction the caller holds (with mutex_).
  void add_wear_locked(std::int64_t job_id, const std::string& device, const Wear& run);
  void exec(const char* sql);
  bool has_column(const char* table, const char* column);
  void add_run_time_columns();
  void add_queue_columns();
  // The key's earlier job in this transaction (store_queue.cpp), or nullopt; forgets old keys.
  std::optional<SubmitResult> replay_locked(const NewJob& job);
  void remember_key_locked(const NewJob& job, std::int64_t id);
  ReorderResult reorder_locked(std::int64_t id, const Reorder& to);
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
