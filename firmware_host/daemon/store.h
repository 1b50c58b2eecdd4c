// The job queue in SQLite (WAL): every state change is one committed transaction before anyone acts on it.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "job.h"

struct sqlite3;

namespace popcut::daemon {

struct NewJob {
  std::string owner, name, target_device, target_profile;
  std::string material;    // empty: the profile's own forces
  std::string model_json;  // the model as submitted (popcut.voxel.v1 / popcut.faces.v1)
};

// giving_up: Daemon::cancel only, a repeated cancel of a cut whose stop waits for a device that
// holds the line: the wait is given up and the abort is not sent.
enum class CancelResult { cancelled, requested, giving_up, already_final, not_found };
// executed_unknown: resuming after the executed strokes was asked, but the device never said what
// it executed (a transport without status answers, or a cut cut short by a crash).
enum class ResumeResult { resumed, not_interrupted, executed_unknown };

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
  };
  Recovered recover();

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

  void set_paused(const std::string& device, bool paused);
  bool paused(const std::string& device);
  std::map<std::string, std::int64_t> count_by_state();
  std::int64_t count_submitted();

 private:
  void exec(const char* sql);
  bool has_column(const char* table, const char* column);
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
