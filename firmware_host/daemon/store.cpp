// SQLite job store: schema, WAL with synchronous=NORMAL, each transition as one guarded UPDATE, reads on their own
// connections.
#include "store.h"

#include <sqlite3.h>

#include <algorithm>
#include <chrono>

#include "popcut/error.h"
#include "sqlite_stmt.h"
#include "store_queue.h"

namespace popcut::daemon {
namespace {

constexpr const char* kJobColumns =
    "id, owner, name, target_device, target_profile, device, state, error_code, error_message, strokes_total, "
    "strokes_sent, resume_from, est_time_s, created_at, started_at, finished_at, sim_match, strokes_executed, "
    "resume_point, material, cut_mm, knife_down_strokes, priority, " POPCUT_JOB_RANK
    ", copies, pause_requested, "
    "sheet_copies, sheet_strokes";

Job read_job(const Stmt& s) {
  Job j;
  j.id = s.integer(0);
  j.owner = s.text(1);
  j.name = s.text(2);
  j.target_device = s.text(3);
  j.target_profile = s.text(4);
  j.device = s.text(5);
  j.state = parse_job_state(s.text(6)).value_or(JobState::failed);
  j.error_code = s.text(7);
  j.error_message = s.text(8);
  j.strokes_total = s.integer(9);
  j.strokes_sent = s.integer(10);
  j.resume_from = s.integer(11);
  j.est_time_s = s.real(12);
  j.created_at = s.real(13);
  j.started_at = s.real(14);
  j.finished_at = s.real(15);
  j.sim_match = s.integer(16) != 0;
  j.strokes_executed = s.nullable_integer(17);
  j.resume_point = parse_resume_point(s.text(18));  // NULL (never resumed) reads as "": nullopt
  j.material = s.text(19);
  j.cut_mm = s.real(20);
  j.knife_down_strokes = s.integer(21);
  j.priority = static_cast<int>(s.integer(22));
  j.queue_rank = s.real(23);
  j.copies = static_cast<int>(s.integer(24));
  j.pause_requested = s.integer(25) != 0;
  j.sheet_copies = static_cast<int>(s.integer(26));
  j.sheet_strokes = s.integer(27);
  return j;
}

// A cut's run ends (finished, interrupted, or found cut short at restart) at `end`: its time
// since run_started_at is added to the job's cutting_s. Only a job leaving `cutting` has a run.
}  // namespace

std::string end_run(const std::string& end) {
  return "cutting_s = cutting_s + CASE WHEN state='cutting' AND run_started_at > 0 THEN MAX(0, " + end +
         " - run_started_at) ELSE 0 END, last_cut_at = CASE WHEN state='cutting' THEN MAX(last_cut_at, " + end +
         ") ELSE last_cut_at END";
}

namespace {

std::string select_jobs(const std::string& where) {
  return std::string("SELECT ") + kJobColumns + " FROM jobs " + where;
}

}  // namespace

namespace {

sqlite3* open_db(const std::string& path) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr) !=
      SQLITE_OK) {
    const std::string msg = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw Error(ErrorCode::io, path, "", "cannot open the job database: " + msg);
  }
  sqlite3_busy_timeout(db, 5000);
  return db;
}

}  // namespace

JobStore::JobStore(const std::string& path, int readers) : path_(path) {
  db_ = open_db(path);
  try {
    exec("PRAGMA journal_mode=WAL");
    // NORMAL, not FULL: in WAL mode a commit is then written to the log but not fsynced; the log
    // is synced at each checkpoint. A crash of popcutd (kill -9, abort) loses nothing: the
    // written log survives the process and is replayed on open. Only a power loss or kernel crash
    // can lose the last commits before a checkpoint, and even then the database stays
    // consistent (never corrupt). FULL paid one fsync per state change, serialised behind one
    // lock: p99 627 ms at 32 clients (bench/popcutd_bench). docs/api.md "Durability".
    exec("PRAGMA synchronous=NORMAL");
    exec(
        "CREATE TABLE IF NOT EXISTS jobs ("
        " id INTEGER PRIMARY KEY AUTOINCREMENT, owner TEXT NOT NULL, name TEXT NOT NULL,"
        " target_device TEXT NOT NULL, target_profile TEXT NOT NULL, device TEXT NOT NULL DEFAULT '',"
        " state TEXT NOT NULL, error_code TEXT NOT NULL DEFAULT '', error_message TEXT NOT NULL DEFAULT '',"
        " strokes_total INTEGER NOT NULL DEFAULT 0, strokes_sent INTEGER NOT NULL DEFAULT 0,"
        " resume_from INTEGER NOT NULL DEFAULT 0, est_time_s REAL NOT NULL DEFAULT 0,"
        " created_at REAL NOT NULL, started_at REAL NOT NULL DEFAULT 0, finished_at REAL NOT NULL DEFAULT 0,"
        " cancel_requested INTEGER NOT NULL DEFAULT 0, sim_match INTEGER NOT NULL DEFAULT 0, strokes_executed INTEGER,"
        " resume_point TEXT)");
    // A database from before strokes_executed: the column is added, unknown (NULL) for old jobs.
    if (!has_column("jobs", "strokes_executed")) exec("ALTER TABLE jobs ADD COLUMN strokes_executed INTEGER");
    // From before resume_point: old jobs resumed only after the strokes received, but whether
    // one was resumed at all is not recorded, so NULL (shown as never resumed).
    if (!has_column("jobs", "resume_point")) exec("ALTER TABLE jobs ADD COLUMN resume_point TEXT");
    // From before materials: every old job used its profile's own forces.
    if (!has_column("jobs", "material")) exec("ALTER TABLE jobs ADD COLUMN material TEXT NOT NULL DEFAULT ''");
    // Wear: a job's own knife-down totals over its runs, and each device's counters (store_wear.cpp).
    if (!has_column("jobs", "cut_mm")) exec("ALTER TABLE jobs ADD COLUMN cut_mm REAL NOT NULL DEFAULT 0");
    if (!has_column("jobs", "knife_down_strokes"))
      exec("ALTER TABLE jobs ADD COLUMN knife_down_strokes INTEGER NOT NULL DEFAULT 0");
    create_wear_tables();
    create_sheet_tables();
    create_design_tables();
    add_run_time_columns();
    add_queue_columns();
    add_pause_column();
    exec("CREATE TABLE IF NOT EXISTS models (id INTEGER PRIMARY KEY, model TEXT NOT NULL)");
    exec("CREATE TABLE IF NOT EXISTS devices (name TEXT PRIMARY KEY, paused INTEGER NOT NULL)");
    exec("CREATE INDEX IF NOT EXISTS jobs_state ON jobs(state, id)");
    exec("CREATE INDEX IF NOT EXISTS jobs_owner ON jobs(owner, id)");
    for (int i = 0; i < std::max(1, readers); ++i) {
      readers_.push_back(std::make_unique<Reader>());
      readers_.back()->db = open_db(path);
    }
  } catch (...) {
    for (auto& r : readers_) sqlite3_close(r->db);
    sqlite3_close(db_);
    throw;
  }
}

std::pair<sqlite3*, std::unique_lock<std::mutex>> JobStore::reader() {
  for (auto& r : readers_) {
    std::unique_lock lock(r->mutex, std::try_to_lock);
    if (lock.owns_lock()) return {r->db, std::move(lock)};
  }
  Reader& r = *readers_[next_reader_++ % readers_.size()];
  return {r.db, std::unique_lock(r.mutex)};
}

JobStore::~JobStore() {
  for (auto& r : readers_) sqlite3_close(r->db);
  sqlite3_close(db_);
}

bool JobStore::has_column(const char* table, const char* column) {
  Stmt s(db_, (std::string("SELECT 1 FROM pragma_table_info('") + table + "') WHERE name=?").c_str());
  s.bind(1, std::string(column));
  return s.step();
}

void JobStore::exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    throw Error(ErrorCode::io, path_, sql, msg);
  }
}

JobStore::Recovered JobStore::recover(const std::function<Wear(const Job&)>& crashed_run_wear) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  Recovered r;
  try {
    std::vector<Job> cut_short;
    for (Stmt s(db_, select_jobs("WHERE state='cutting' ORDER BY id").c_str()); s.step();)
      cut_short.push_back(read_job(s));
    std::vector<std::int64_t> counted;  // their run's wear was added just before the crash
    for (Stmt s(db_, "SELECT id FROM jobs WHERE state='cutting' AND run_wear_counted=1"); s.step();)
      counted.push_back(s.integer(0));
    for (const Job& j : cut_short) {
      r.interrupted_ids.push_back(j.id);
      const bool done = std::find(counted.begin(), counted.end(), j.id) != counted.end();
      if (crashed_run_wear && !done) add_wear_locked(j.id, j.device, crashed_run_wear(j));
    }
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
  Stmt(db_, ("UPDATE jobs SET state='interrupted', resume_from=strokes_sent, cancel_requested=0, pause_requested=0,"
             " error_code='interrupted', error_message='popcutd stopped without a clean shutdown during the cut', " +
             end_run("last_cut_at") + " WHERE state='cutting'")
                .c_str())
      .step();
  r.interrupted = sqlite3_changes(db_);
  Stmt(db_, "UPDATE jobs SET state='queued' WHERE state='planning'").step();
  r.requeued = sqlite3_changes(db_);
  exec("COMMIT");
  return r;
}

std::optional<Job> JobStore::get(std::int64_t id) {
  auto [db, lock] = reader();
  Stmt s(db, select_jobs("WHERE id=?").c_str());
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return read_job(s);
}

std::optional<std::string> JobStore::model_json(std::int64_t id) {
  auto [db, lock] = reader();
  Stmt s(db, "SELECT model FROM models WHERE id=?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return s.text(0);
}

std::vector<Job> JobStore::list(const JobFilter& f) {
  std::string where =
      "WHERE (?1 = '' OR owner = ?1) AND (?2 = '' OR device = ?2 OR (device = '' AND target_device = ?2))"
      " AND (?3 IS NULL OR MAX(created_at, finished_at) >= ?3)";
  if (!f.states.empty()) {
    where += " AND state IN (";
    for (std::size_t i = 0; i < f.states.size(); ++i)
      where += (i ? ",'" : "'") + std::string(to_string(f.states[i])) + "'";
    where += ")";
  }
  auto [db, lock] = reader();
  Stmt s(db, select_jobs(where + " ORDER BY id DESC LIMIT ?4").c_str());
  s.bind(1, f.owner).bind(2, f.device).bind(4, static_cast<std::int64_t>(f.limit));
  if (f.since_s) s.bind(3, *f.since_s);
  std::vector<Job> out;
  while (s.step()) out.push_back(read_job(s));
  return out;
}

// The device a waiting job must go to: the one holding its half-cut sheet (a resumed job: it was
// cut there), else the one it names ('' when it names only a profile).
#define POPCUT_JOB_DEVICE "(CASE WHEN device <> '' THEN device ELSE target_device END)"
// Jobs that may take the same device: two bound to or naming devices, the same device; else (one
// or both name only a profile) the same profile: a job naming a device also records its profile.
static const char* kAheadWhere =
    " WHERE " POPCUT_QUEUE_AHEAD("?1", "?4", "?5") " AND state IN ('queued','planning','ready') AND"
    " ((?2 <> '' AND " POPCUT_JOB_DEVICE " <> '' AND " POPCUT_JOB_DEVICE " = ?2) OR ((?2 = '' OR " POPCUT_JOB_DEVICE
    " = '') AND target_profile = ?3))";
// Cutting time left of a job: the share of its strokes not yet cut (after resume_from, if resumed).
static const char* kLeftS =
    "est_time_s * (CASE WHEN strokes_total > 0 THEN 1.0 - MAX(strokes_sent, resume_from) * 1.0 / strokes_total ELSE "
    "1.0 END)";

int JobStore::place_in_line(const Job& j) {
  auto [db, lock] = reader();
  Stmt s(db, (std::string("SELECT COUNT(*) FROM jobs") + kAheadWhere).c_str());
  s.bind(1, j.id)
      .bind(2, j.targets().device)
      .bind(3, j.target_profile)
      .bind(4, std::int64_t{j.priority})
      .bind(5, j.queue_rank);
  s.step();
  return static_cast<int>(s.integer(0));
}

std::vector<WaitingJob> JobStore::waiting() {
  auto [db, lock] = reader();
  Stmt s(db, (std::string("SELECT id, " POPCUT_JOB_DEVICE ", target_profile, ") + kLeftS +
              " FROM jobs WHERE state IN ('queued','planning','ready') ORDER BY " POPCUT_QUEUE_ORDER)
                 .c_str());
  std::vector<WaitingJob> out;
  while (s.step()) out.push_back({s.integer(0), {s.text(1), s.text(2)}, s.real(3)});
  return out;
}

std::vector<Job> JobStore::cutting() {
  auto [db, lock] = reader();
  Stmt s(db, select_jobs("WHERE state='cutting'").c_str());
  std::vector<Job> out;
  while (s.step()) out.push_back(read_job(s));
  return out;
}

std::optional<Job> JobStore::claim_for_planning() {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    Stmt s(db_, select_jobs("WHERE state='queued' ORDER BY " POPCUT_QUEUE_ORDER " LIMIT 1").c_str());
    if (!s.step()) {
      exec("COMMIT");
      return std::nullopt;
    }
    Job j = read_job(s);
    Stmt(db_, "UPDATE jobs SET state='planning' WHERE id=?").bind(1, j.id).step();
    exec("COMMIT");
    j.state = JobState::planning;
    return j;
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

void JobStore::set_planned(std::int64_t id, std::int64_t strokes_total, double est_time_s, int sheet_copies,
                           std::int64_t sheet_strokes) {
  std::lock_guard lock(mutex_);
  Stmt(db_,
       "UPDATE jobs SET state='ready', strokes_total=?, est_time_s=?, sheet_copies=?, sheet_strokes=? WHERE id=? AND"
       " state='planning'")
      .bind(1, strokes_total)
      .bind(2, est_time_s)
      .bind(3, std::int64_t{sheet_copies})
      .bind(4, sheet_strokes)
      .bind(5, id)
      .step();
}

std::optional<Job> JobStore::claim_for_device(const std::string& device, const std::string& profile_name,
                                              bool confirm_sheet) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    const std::optional<std::int64_t> only = sheet_allows_locked(device, confirm_sheet);
    if (!only) {
      exec("COMMIT");
      return std::nullopt;
    }
    // A resumed or continued job goes back to the device holding its half-cut sheet, and only
    // there, before any other: that sheet is what lies on the device.
    Stmt s(db_, select_jobs(
                    "WHERE state='ready' AND (" POPCUT_JOB_DEVICE "=?1 OR (" POPCUT_JOB_DEVICE
                    "='' AND target_profile=?2)) AND (?3 = 0 OR id = ?3) ORDER BY device = ?1 DESC, " POPCUT_QUEUE_ORDER
                    " LIMIT 1")
                    .c_str());
    s.bind(1, device).bind(2, profile_name).bind(3, *only);
    if (!s.step()) {
      exec("COMMIT");
      return std::nullopt;
    }
    Job j = read_job(s);
    if (*only == j.id && sheet_filled_locked(j, device)) {
      exec("COMMIT");
      return std::nullopt;
    }
    j.started_at = j.started_at > 0 ? j.started_at : unix_now_s();
    Stmt(db_,
         "UPDATE jobs SET state='cutting', device=?, started_at=?, strokes_executed=NULL,"
         " run_started_at=?4, last_cut_at=?4, run_wear_counted=0 WHERE id=?3")
        .bind(1, device)
        .bind(2, j.started_at)
        .bind(3, j.id)
        .bind(4, unix_now_s())
        .step();
    if (confirm_sheet) use_sheet_locked(device, j.id);
    exec("COMMIT");
    j.state = JobState::cutting;
    j.device = device;
    return j;
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

void JobStore::set_progress(std::int64_t id, std::int64_t strokes_sent) {
  std::lock_guard lock(mutex_);
  Stmt(db_, "UPDATE jobs SET strokes_sent=?, last_cut_at=? WHERE id=? AND state='cutting'")
      .bind(1, strokes_sent)
      .bind(2, unix_now_s())
      .bind(3, id)
      .step();
}

void JobStore::set_executed(std::int64_t id, std::optional<std::int64_t> strokes_executed) {
  std::lock_guard lock(mutex_);
  Stmt(db_, "UPDATE jobs SET strokes_executed=? WHERE id=? AND state='cutting'")
      .bind(1, strokes_executed)
      .bind(2, id)
      .step();
}

void JobStore::finish(std::int64_t id, JobState state, const std::string& code, const std::string& message,
                      bool sim_match) {
  std::lock_guard lock(mutex_);
  Stmt(db_, ("UPDATE jobs SET state=?, error_code=?, error_message=?, finished_at=?, sim_match=?, cancel_requested=0, "
             "pause_requested=0,"
             " resume_from=CASE WHEN ?1='interrupted' THEN strokes_sent ELSE resume_from END, " +
             end_run("?7") + " WHERE id=?6 AND state IN ('planning','cutting')")
                .c_str())
      .bind(1, std::string(to_string(state)))
      .bind(2, code)
      .bind(3, message)
      .bind(4, is_terminal(state) ? unix_now_s() : 0.0)
      .bind(5, static_cast<std::int64_t>(sim_match))
      .bind(6, id)
      .bind(7, unix_now_s())
      .step();
}

CancelResult JobStore::cancel(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Stmt(db_,
       "UPDATE jobs SET state='cancelled', finished_at=?, error_code='cancelled',"
       " error_message=CASE state WHEN 'interrupted' THEN 'cancelled while interrupted; the rest was not cut'"
       " WHEN 'paused' THEN 'cancelled while paused; the rest was not cut' ELSE 'cancelled before the cut' END,"
       " pause_requested=0 WHERE id=? AND state IN ('queued','planning','ready','interrupted','paused')")
      .bind(1, unix_now_s())
      .bind(2, id)
      .step();
  if (sqlite3_changes(db_) > 0) return CancelResult::cancelled;
  Stmt(db_, "UPDATE jobs SET cancel_requested=1 WHERE id=? AND state='cutting'").bind(1, id).step();
  if (sqlite3_changes(db_) > 0) return CancelResult::requested;
  Stmt s(db_, "SELECT 1 FROM jobs WHERE id=?");
  s.bind(1, id);
  return s.step() ? CancelResult::already_final : CancelResult::not_found;
}

bool JobStore::cancel_requested(std::int64_t id) {
  auto [db, lock] = reader();
  Stmt s(db, "SELECT cancel_requested FROM jobs WHERE id=?");
  s.bind(1, id);
  return s.step() && s.integer(0) != 0;
}

ResumeResult JobStore::resume(std::int64_t id, ResumePoint from) {
  std::lock_guard lock(mutex_);
  if (from == ResumePoint::executed) {
    Stmt(db_,
         "UPDATE jobs SET state='ready', resume_from=strokes_executed, strokes_sent=strokes_executed, "
         "resume_point='executed',"
         " error_code='', error_message='' WHERE id=? AND state='interrupted' AND strokes_executed IS NOT NULL")
        .bind(1, id)
        .step();
  } else {
    Stmt(db_,
         "UPDATE jobs SET state='ready', resume_from=strokes_sent, resume_point='received', error_code='', "
         "error_message=''"
         " WHERE id=? AND state='interrupted'")
        .bind(1, id)
        .step();
  }
  if (sqlite3_changes(db_) > 0) return ResumeResult::resumed;
  Stmt s(db_, "SELECT 1 FROM jobs WHERE id=? AND state='interrupted'");
  s.bind(1, id);
  return s.step() ? ResumeResult::executed_unknown : ResumeResult::not_interrupted;
}

void JobStore::set_paused(const std::string& device, bool paused) {
  std::lock_guard lock(mutex_);
  Stmt(db_, "INSERT INTO devices (name, paused) VALUES (?,?) ON CONFLICT(name) DO UPDATE SET paused=excluded.paused")
      .bind(1, device)
      .bind(2, static_cast<std::int64_t>(paused))
      .step();
}

bool JobStore::paused(const std::string& device) {
  auto [db, lock] = reader();
  Stmt s(db, "SELECT paused FROM devices WHERE name=?");
  s.bind(1, device);
  return s.step() && s.integer(0) != 0;
}

std::map<std::string, std::int64_t> JobStore::count_by_state() {
  auto [db, lock] = reader();
  std::map<std::string, std::int64_t> out;
  for (const auto& [state, name] : kJobStateNames.entries) out[std::string(name)] = 0;
  Stmt s(db, "SELECT state, COUNT(*) FROM jobs GROUP BY state");
  while (s.step()) out[s.text(0)] = s.integer(1);
  return out;
}

std::int64_t JobStore::count_submitted() {
  auto [db, lock] = reader();
  Stmt s(db, "SELECT COALESCE(MAX(id),0) FROM jobs");
  s.step();
  return s.integer(0);
}

}  // namespace popcut::daemon
