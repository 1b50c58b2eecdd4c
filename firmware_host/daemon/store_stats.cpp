// The job store's part of the statistics: the run-time columns and the rows GET /api/v1/stats counts.
#include <sqlite3.h>

#include <memory>

#include "popcut/error.h"
#include "store.h"

namespace popcut::daemon {

// The cutting time of each run: when the current run began, the last moment it is known to have
// cut (a confirmed stroke, or the run's end), and the time of the runs ended so far (store.cpp's
// end_run adds each run as it ends).
void JobStore::add_run_time_columns() {
  if (has_column("jobs", "cutting_s")) return;
  exec("ALTER TABLE jobs ADD COLUMN run_started_at REAL NOT NULL DEFAULT 0");
  exec("ALTER TABLE jobs ADD COLUMN last_cut_at REAL NOT NULL DEFAULT 0");
  exec("ALTER TABLE jobs ADD COLUMN cutting_s REAL NOT NULL DEFAULT 0");
  // Jobs from before: one never resumed was cut in one run, from started_at to finished_at; a
  // resumed one's runs are not recorded, so it counts none (its span holds the interruption).
  exec(
      "UPDATE jobs SET cutting_s = finished_at - started_at, last_cut_at = finished_at, run_started_at = started_at"
      " WHERE resume_point IS NULL AND started_at > 0 AND finished_at >= started_at");
}

std::vector<StatsRow> JobStore::stats_rows(double since_s) {
  auto [db, lock] = reader();
  sqlite3_stmt* raw = nullptr;
  const char* sql =
      "SELECT state, device, created_at, finished_at, last_cut_at, cutting_s, run_started_at FROM jobs"
      " WHERE created_at >= ?1 OR finished_at >= ?1 OR last_cut_at >= ?1 OR state='cutting'";
  if (sqlite3_prepare_v2(db, sql, -1, &raw, nullptr) != SQLITE_OK)
    throw Error(ErrorCode::io, "job database", "prepare", sqlite3_errmsg(db));
  const std::unique_ptr<sqlite3_stmt, int (*)(sqlite3_stmt*)> st(raw, sqlite3_finalize);
  sqlite3_bind_double(raw, 1, since_s);
  std::vector<StatsRow> out;
  int rc = SQLITE_ROW;
  while ((rc = sqlite3_step(raw)) == SQLITE_ROW) {
    StatsRow r;
    const unsigned char* state = sqlite3_column_text(raw, 0);
    const unsigned char* device = sqlite3_column_text(raw, 1);
    r.state = parse_job_state(state ? reinterpret_cast<const char*>(state) : "").value_or(JobState::failed);
    r.device = device ? reinterpret_cast<const char*>(device) : "";
    r.created_at = sqlite3_column_double(raw, 2);
    r.finished_at = sqlite3_column_double(raw, 3);
    r.last_cut_at = sqlite3_column_double(raw, 4);
    r.cutting_s = sqlite3_column_double(raw, 5);
    r.run_started_at = sqlite3_column_double(raw, 6);
    out.push_back(std::move(r));
  }
  if (rc != SQLITE_DONE) throw Error(ErrorCode::io, "job database", "step", sqlite3_errmsg(db));
  return out;
}

}  // namespace popcut::daemon
