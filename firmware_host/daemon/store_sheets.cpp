// The job store's device_sheets rows: a claim uses the sheet in its own transaction, a confirmation loads a fresh one.
#include <sqlite3.h>

#include "sqlite_stmt.h"
#include "store.h"

namespace popcut::daemon {
namespace {

// last_job: the job claimed onto the sheet; since: unix seconds of the change.
constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS device_sheets (name TEXT PRIMARY KEY, state TEXT NOT NULL,"
    " last_job INTEGER NOT NULL DEFAULT 0, since REAL NOT NULL DEFAULT 0)";

DeviceSheet read_sheet(sqlite3* db, const std::string& device) {
  DeviceSheet sheet;
  sheet.device = device;
  Stmt s(db, "SELECT state, last_job, since FROM device_sheets WHERE name=?");
  s.bind(1, device);
  if (!s.step()) return sheet;
  // An unknown word (a newer popcutd's) reads as waiting: never cut onto a sheet nobody confirmed.
  sheet.state = parse_sheet_state(s.text(0)).value_or(SheetState::used);
  sheet.last_job = s.integer(1);
  sheet.since_s = s.real(2);
  return sheet;
}

void write_sheet(sqlite3* db, const std::string& device, SheetState state, std::int64_t job) {
  Stmt(db,
       "INSERT INTO device_sheets (name, state, last_job, since) VALUES (?1,?2,?3,?4) ON CONFLICT(name) DO UPDATE"
       " SET state=excluded.state, last_job=CASE WHEN ?3 <> 0 THEN ?3 ELSE last_job END, since=excluded.since")
      .bind(1, device)
      .bind(2, std::string(to_string(state)))
      .bind(3, job)
      .bind(4, unix_now_s())
      .step();
}

}  // namespace

void JobStore::create_sheet_tables() {
  exec(kSchema);
  // From before jobs of several sheets: every old job is on one.
  if (!has_column("jobs", "sheet_copies")) exec("ALTER TABLE jobs ADD COLUMN sheet_copies INTEGER NOT NULL DEFAULT 0");
  if (!has_column("jobs", "sheet_strokes"))
    exec("ALTER TABLE jobs ADD COLUMN sheet_strokes INTEGER NOT NULL DEFAULT 0");
}

std::optional<std::int64_t> JobStore::sheet_allows_locked(const std::string& device, bool confirm_sheet) {
  const DeviceSheet sheet = read_sheet(db_, device);
  if (sheet.state == SheetState::loaded) return 0;
  // The device itself said its tray is empty: no job starts on it, whether sheets are confirmed or not.
  if (sheet.state == SheetState::empty) return std::nullopt;
  if (!confirm_sheet) return 0;
  // A used sheet still holds its job's cut so far: that job, resumed, may go on cutting it.
  if (sheet.state == SheetState::used && sheet.last_job != 0) return sheet.last_job;
  return std::nullopt;
}

void JobStore::use_sheet_locked(const std::string& device, std::int64_t job_id) {
  write_sheet(db_, device, SheetState::used, job_id);
}

bool JobStore::sheet_filled_locked(const Job& job, const std::string& device) {
  if (job.sheets() <= 1 || job.sheet_strokes <= 0 || job.resume_from <= 0 || job.resume_from >= job.strokes_total ||
      job.resume_from % job.sheet_strokes != 0)
    return false;
  Stmt(db_, "UPDATE jobs SET device='' WHERE id=?").bind(1, job.id).step();
  write_sheet(db_, device, SheetState::full, job.id);
  return true;
}

bool JobStore::back_for_no_sheet(std::int64_t job_id, const std::string& device) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    // A job that had not started: it goes back in line as it was (its place kept, no device, no
    // run). One resumed on its half-cut sheet stays where it is: that sheet is gone from the device.
    Stmt(db_,
         "UPDATE jobs SET state='ready', device='', started_at=0, run_started_at=0, last_cut_at=0,"
         " strokes_executed=NULL WHERE id=? AND state='cutting' AND resume_from=0 AND strokes_sent=0"
         " AND cancel_requested=0 AND pause_requested=0")
        .bind(1, job_id)
        .step();
    const bool back = sqlite3_changes(db_) > 0;
    if (back) write_sheet(db_, device, SheetState::empty, job_id);  // its owner may say a sheet is in
    exec("COMMIT");
    return back;
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

void JobStore::sheet_full(std::int64_t job_id, const std::string& device, std::int64_t next_from, bool confirm_sheet) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    Stmt(db_, ("UPDATE jobs SET " + end_run("?3") +
               ", state='ready', device='', resume_from=?2, strokes_sent=?2, strokes_executed=NULL WHERE id=?1 AND"
               " state='cutting'")
                  .c_str())
        .bind(1, job_id)
        .bind(2, next_from)
        .bind(3, unix_now_s())
        .step();
    if (confirm_sheet) write_sheet(db_, device, SheetState::full, job_id);
    exec("COMMIT");
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

bool JobStore::ask_again_for_sheet(const std::string& device) {
  std::lock_guard lock(mutex_);
  Stmt(db_, "UPDATE device_sheets SET state='loaded', since=? WHERE name=? AND state='empty'")
      .bind(1, unix_now_s())
      .bind(2, device)
      .step();
  return sqlite3_changes(db_) > 0;
}

DeviceSheet JobStore::device_sheet(const std::string& device) {
  auto [db, lock] = reader();
  return read_sheet(db, device);
}

SheetConfirmation JobStore::confirm_sheet(const std::string& device) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    // Checked in the transaction a claim also takes: a job claimed a moment ago is cutting here.
    // A paused, interrupted or resumed job's half-cut sheet is on the device too: a fresh one
    // would take the rest of that card.
    Stmt holding(db_,
                 "SELECT id, state FROM jobs WHERE device=? AND state IN ('cutting','paused','interrupted','ready')"
                 " ORDER BY state='cutting' DESC, id LIMIT 1");
    holding.bind(1, device);
    if (holding.step()) {
      SheetConfirmation held{std::nullopt, holding.integer(0), holding.text(1)};
      exec("ROLLBACK");
      return held;
    }
    write_sheet(db_, device, SheetState::loaded, 0);
    SheetConfirmation done{read_sheet(db_, device), 0, ""};
    exec("COMMIT");
    return done;
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

}  // namespace popcut::daemon
