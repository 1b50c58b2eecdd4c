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

void JobStore::create_sheet_tables() { exec(kSchema); }

std::optional<std::int64_t> JobStore::sheet_allows_locked(const std::string& device) {
  const DeviceSheet sheet = read_sheet(db_, device);
  if (sheet.state == SheetState::loaded) return 0;
  // A used sheet still holds its job's cut so far: that job, resumed, may go on cutting it.
  if (sheet.state == SheetState::used && sheet.last_job != 0) return sheet.last_job;
  return std::nullopt;
}

void JobStore::use_sheet_locked(const std::string& device, std::int64_t job_id) {
  write_sheet(db_, device, SheetState::used, job_id);
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
