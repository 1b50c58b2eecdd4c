// The job store's part of pause and continue: the pause_requested column and the paused state's transitions.
#include <sqlite3.h>

#include "sqlite_stmt.h"
#include "store.h"

namespace popcut::daemon {

void JobStore::add_pause_column() {
  if (!has_column("jobs", "pause_requested"))
    exec("ALTER TABLE jobs ADD COLUMN pause_requested INTEGER NOT NULL DEFAULT 0");
}

PauseResult JobStore::request_pause(std::int64_t id) {
  std::lock_guard lock(mutex_);
  // Not yet on the device: held back at once (it keeps its place and resume point).
  Stmt(db_,
       "UPDATE jobs SET state='paused', error_code='', error_message='paused before the cut' WHERE id=? AND "
       "state='ready'")
      .bind(1, id)
      .step();
  if (sqlite3_changes(db_) > 0) return PauseResult::paused;
  Stmt(db_, "UPDATE jobs SET pause_requested=1 WHERE id=? AND state='cutting' AND cancel_requested=0")
      .bind(1, id)
      .step();
  if (sqlite3_changes(db_) > 0) return PauseResult::requested;
  Stmt s(db_, "SELECT 1 FROM jobs WHERE id=?");
  s.bind(1, id);
  return s.step() ? PauseResult::conflict : PauseResult::not_found;
}

bool JobStore::pause_requested(std::int64_t id) {
  auto [db, lock] = reader();
  Stmt s(db, "SELECT pause_requested FROM jobs WHERE id=?");
  s.bind(1, id);
  return s.step() && s.integer(0) != 0;
}

void JobStore::mark_paused(std::int64_t id, const std::string& message) {
  std::lock_guard lock(mutex_);
  Stmt(db_, ("UPDATE jobs SET state='paused', resume_from=strokes_sent, pause_requested=0, error_code='',"
             " error_message=?1, " +
             end_run("?2") + " WHERE id=?3 AND state='cutting'")
                .c_str())
      .bind(1, message)
      .bind(2, unix_now_s())
      .bind(3, id)
      .step();
}

ContinueResult JobStore::continue_job(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Stmt(db_, "UPDATE jobs SET state='ready', error_code='', error_message='' WHERE id=? AND state='paused'")
      .bind(1, id)
      .step();
  if (sqlite3_changes(db_) > 0) return ContinueResult::continued;
  Stmt s(db_, "SELECT 1 FROM jobs WHERE id=?");
  s.bind(1, id);
  return s.step() ? ContinueResult::not_paused : ContinueResult::not_found;
}

bool JobStore::holds_paused_job(const std::string& device) {
  auto [db, lock] = reader();
  Stmt s(db, "SELECT 1 FROM jobs WHERE state='paused' AND device=? LIMIT 1");
  s.bind(1, device);
  return s.step();
}

}  // namespace popcut::daemon
