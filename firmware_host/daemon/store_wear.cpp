// The job store's wear counters: device_wear rows and each job's own totals, added per run.
#include <sqlite3.h>

#include "sqlite_stmt.h"
#include "store.h"

namespace popcut::daemon {
namespace {

// blade_*: since the last reset (`since`); lifetime_*: never reset. worn_at: when blade_worn was raised.
constexpr const char* kSchema =
    "CREATE TABLE IF NOT EXISTS device_wear (name TEXT PRIMARY KEY, cut_mm REAL NOT NULL DEFAULT 0,"
    " knife_down_strokes INTEGER NOT NULL DEFAULT 0, since REAL, score_mm REAL NOT NULL DEFAULT 0,"
    " perforate_mm REAL NOT NULL DEFAULT 0, worn_at REAL, lifetime_cut_mm REAL NOT NULL DEFAULT 0,"
    " lifetime_score_mm REAL NOT NULL DEFAULT 0, lifetime_perforate_mm REAL NOT NULL DEFAULT 0,"
    " lifetime_knife_down_strokes INTEGER NOT NULL DEFAULT 0)";

constexpr const char* kSelect =
    "SELECT cut_mm, score_mm, perforate_mm, knife_down_strokes, lifetime_cut_mm, lifetime_score_mm,"
    " lifetime_perforate_mm, lifetime_knife_down_strokes, COALESCE(since,0), COALESCE(worn_at,0)"
    " FROM device_wear WHERE name=?";

DeviceWear read_wear(sqlite3* db, const std::string& device) {
  DeviceWear w;
  w.name = device;
  Stmt s(db, kSelect);
  s.bind(1, device);
  if (!s.step()) return w;
  w.blade = {s.real(0), s.real(1), s.real(2), s.integer(3)};
  w.lifetime = {s.real(4), s.real(5), s.real(6), s.integer(7)};
  w.since_s = s.real(8);
  w.worn_at_s = s.real(9);
  return w;
}

}  // namespace

void JobStore::create_wear_tables() {
  exec(kSchema);
  // Set when a run's wear is added, cleared when a run starts: a crash after the addition and
  // before the job's outcome was recorded must not count that run again at the restart.
  if (!has_column("jobs", "run_wear_counted"))
    exec("ALTER TABLE jobs ADD COLUMN run_wear_counted INTEGER NOT NULL DEFAULT 0");
}

void JobStore::add_wear_locked(std::int64_t job_id, const std::string& device, const Wear& run) {
  if (run.knife_down_strokes == 0) return;
  Stmt(db_, "UPDATE jobs SET cut_mm=cut_mm+?, knife_down_strokes=knife_down_strokes+? WHERE id=?")
      .bind(1, run.cut_mm)
      .bind(2, run.knife_down_strokes)
      .bind(3, job_id)
      .step();
  Stmt(db_, "INSERT INTO device_wear (name, since) VALUES (?1, ?2) ON CONFLICT(name) DO NOTHING")
      .bind(1, device)
      .bind(2, unix_now_s())
      .step();
  Stmt(db_,
       "UPDATE device_wear SET cut_mm=cut_mm+?2, score_mm=score_mm+?3, perforate_mm=perforate_mm+?4,"
       " knife_down_strokes=knife_down_strokes+?5, lifetime_cut_mm=lifetime_cut_mm+?2,"
       " lifetime_score_mm=lifetime_score_mm+?3, lifetime_perforate_mm=lifetime_perforate_mm+?4,"
       " lifetime_knife_down_strokes=lifetime_knife_down_strokes+?5 WHERE name=?1")
      .bind(1, device)
      .bind(2, run.cut_mm)
      .bind(3, run.score_mm)
      .bind(4, run.perforate_mm)
      .bind(5, run.knife_down_strokes)
      .step();
}

JobStore::WearAdded JobStore::add_run_wear(std::int64_t job_id, const std::string& device, const Wear& run,
                                           std::optional<double> blade_life_m) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    add_wear_locked(job_id, device, run);
    Stmt(db_, "UPDATE jobs SET run_wear_counted=1 WHERE id=?").bind(1, job_id).step();
    WearAdded out;
    out.device = read_wear(db_, device);
    // Marked in the same transaction: the event is raised once, whatever restarts follow.
    if (out.device.worn_at_s == 0 && blade_worn(out.device, blade_life_m)) {
      out.device.worn_at_s = unix_now_s();
      Stmt(db_, "UPDATE device_wear SET worn_at=? WHERE name=?").bind(1, out.device.worn_at_s).bind(2, device).step();
      out.newly_worn = true;
    }
    exec("COMMIT");
    return out;
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

DeviceWear JobStore::device_wear(const std::string& device) {
  auto [db, lock] = reader();
  return read_wear(db, device);
}

DeviceWear JobStore::reset_blade(const std::string& device) {
  std::lock_guard lock(mutex_);
  Stmt(db_,
       "INSERT INTO device_wear (name, since) VALUES (?1, ?2) ON CONFLICT(name) DO UPDATE SET cut_mm=0, score_mm=0,"
       " perforate_mm=0, knife_down_strokes=0, since=?2, worn_at=NULL")
      .bind(1, device)
      .bind(2, unix_now_s())
      .step();
  return read_wear(db_, device);
}

}  // namespace popcut::daemon
