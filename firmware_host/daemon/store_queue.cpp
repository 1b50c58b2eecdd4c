// Entering and reordering the queue: idempotent submission, a job's priority, its place ahead of another.
#include <sqlite3.h>

#include <algorithm>
#include <vector>

#include "sqlite_stmt.h"
#include "store.h"
#include "store_queue.h"

namespace popcut::daemon {
namespace {

constexpr const char* kWaiting = "state IN ('queued','planning','ready')";

struct Place {
  std::string state;
  int priority = 0;
  double rank = 0;
};

std::optional<Place> place_of(sqlite3* db, std::int64_t id) {
  Stmt s(db, "SELECT state, priority, " POPCUT_JOB_RANK " FROM jobs WHERE id=?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return Place{s.text(0), static_cast<int>(s.integer(1)), s.real(2)};
}

bool waiting_state(const std::string& state) { return state == "queued" || state == "planning" || state == "ready"; }

// The rank of the job just ahead of `before` among the waiting ones of its priority, `moving` aside.
std::optional<double> rank_ahead(sqlite3* db, std::int64_t before, const Place& b, std::int64_t moving) {
  Stmt s(db, (std::string("SELECT " POPCUT_JOB_RANK " FROM jobs WHERE ") + kWaiting +
              " AND id <> ?4 AND priority = ?2 AND " POPCUT_QUEUE_AHEAD("?1", "?2", "?3") " ORDER BY " POPCUT_JOB_RANK
                                                                                          " DESC, id DESC LIMIT 1")
                 .c_str());
  s.bind(1, before).bind(2, std::int64_t{b.priority}).bind(3, b.rank).bind(4, moving);
  if (!s.step()) return std::nullopt;
  return s.real(0);
}

// Halving gaps runs out after some fifty moves to the same spot: the waiting jobs of that
// priority are then spread evenly over their own span again, in the order they have.
void respread(sqlite3* db, int priority) {
  std::vector<std::int64_t> ids;
  double lo = 0, hi = 0;
  Stmt s(db, (std::string("SELECT id, " POPCUT_JOB_RANK " FROM jobs WHERE ") + kWaiting +
              " AND priority = ? ORDER BY " POPCUT_QUEUE_ORDER)
                 .c_str());
  s.bind(1, std::int64_t{priority});
  while (s.step()) {
    if (ids.empty()) lo = s.real(1);
    hi = s.real(1);
    ids.push_back(s.integer(0));
  }
  const double n = static_cast<double>(ids.size());
  hi = std::max(hi, lo + n);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    Stmt(db, "UPDATE jobs SET queue_rank=? WHERE id=?")
        .bind(1, lo + (hi - lo) * static_cast<double>(i) / n)
        .bind(2, ids[i])
        .step();
  }
}

}  // namespace

void JobStore::add_queue_columns() {
  // Keys are the submitter's own: two tokens may use the same one.
  exec(
      "CREATE TABLE IF NOT EXISTS idempotency (owner TEXT NOT NULL, key TEXT NOT NULL, request_sha256 TEXT NOT NULL,"
      " job_id INTEGER NOT NULL, created_at REAL NOT NULL, PRIMARY KEY (owner, key))");
  if (!has_column("jobs", "copies")) exec("ALTER TABLE jobs ADD COLUMN copies INTEGER NOT NULL DEFAULT 1");
  if (has_column("jobs", "priority")) return;
  exec("ALTER TABLE jobs ADD COLUMN priority INTEGER NOT NULL DEFAULT 0");
  exec("ALTER TABLE jobs ADD COLUMN queue_rank REAL");  // NULL: the id
}

std::optional<std::int64_t> JobStore::insert(const NewJob& nj, int queue_length) {
  const SubmitResult r = submit(nj, queue_length);
  if (r.outcome == Submitted::queue_full || r.outcome == Submitted::key_reused) return std::nullopt;
  return r.id;
}

SubmitResult JobStore::submit(const NewJob& nj, int queue_length) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    if (const std::optional<SubmitResult> earlier = replay_locked(nj)) {
      exec("COMMIT");
      return *earlier;
    }
    Stmt count(db_,
               "SELECT COUNT(*) FROM jobs WHERE state IN ('queued','planning','ready','cutting','interrupted',"
               "'paused')");
    count.step();
    if (count.integer(0) >= queue_length) {
      exec("ROLLBACK");
      return {Submitted::queue_full, 0};
    }
    Stmt ins(db_,
             "INSERT INTO jobs (owner, name, target_device, target_profile, state, created_at, material, copies) "
             "VALUES (?,?,?,?,'queued',?,?,?)");
    ins.bind(1, nj.owner)
        .bind(2, nj.name)
        .bind(3, nj.target_device)
        .bind(4, nj.target_profile)
        .bind(5, unix_now_s())
        .bind(6, nj.material)
        .bind(7, std::int64_t{nj.copies})
        .step();
    const std::int64_t id = sqlite3_last_insert_rowid(db_);
    Stmt(db_, "INSERT INTO models (id, model) VALUES (?,?)").bind(1, id).bind(2, nj.model_json).step();
    remember_key_locked(nj, id);
    exec("COMMIT");
    return {Submitted::created, id};
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

std::optional<SubmitResult> JobStore::replay_locked(const NewJob& nj) {
  if (nj.idempotency_key.empty()) return std::nullopt;
  Stmt(db_, "DELETE FROM idempotency WHERE created_at < ?").bind(1, unix_now_s() - kIdempotencyKeepS).step();
  Stmt s(db_, "SELECT request_sha256, job_id FROM idempotency WHERE owner=? AND key=?");
  s.bind(1, nj.owner).bind(2, nj.idempotency_key);
  if (!s.step()) return std::nullopt;
  return SubmitResult{s.text(0) == nj.request_sha256 ? Submitted::replayed : Submitted::key_reused, s.integer(1)};
}

void JobStore::remember_key_locked(const NewJob& nj, std::int64_t id) {
  if (nj.idempotency_key.empty()) return;
  Stmt(db_, "INSERT INTO idempotency (owner, key, request_sha256, job_id, created_at) VALUES (?,?,?,?,?)")
      .bind(1, nj.owner)
      .bind(2, nj.idempotency_key)
      .bind(3, nj.request_sha256)
      .bind(4, id)
      .bind(5, unix_now_s())
      .step();
}

ReorderResult JobStore::reorder(std::int64_t id, const Reorder& to) {
  std::lock_guard lock(mutex_);
  exec("BEGIN IMMEDIATE");
  try {
    const ReorderResult r = reorder_locked(id, to);
    exec(r == ReorderResult::moved ? "COMMIT" : "ROLLBACK");
    return r;
  } catch (...) {
    exec("ROLLBACK");
    throw;
  }
}

ReorderResult JobStore::reorder_locked(std::int64_t id, const Reorder& to) {
  const std::optional<Place> job = place_of(db_, id);
  if (!job) return ReorderResult::not_found;
  if (!waiting_state(job->state)) return ReorderResult::not_waiting;
  if (!to.before) {
    Stmt(db_, "UPDATE jobs SET priority=? WHERE id=?")
        .bind(1, std::int64_t{to.priority.value_or(job->priority)})
        .bind(2, id)
        .step();
    return ReorderResult::moved;
  }
  std::optional<Place> b = place_of(db_, *to.before);
  if (!b) return ReorderResult::before_not_found;
  if (!waiting_state(b->state)) return ReorderResult::before_not_waiting;
  if (to.priority && *to.priority != b->priority) return ReorderResult::priority_mismatch;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const std::optional<double> ahead = rank_ahead(db_, *to.before, *b, id);
    const double rank = ahead ? (*ahead + b->rank) / 2 : b->rank - 1;
    if ((!ahead || rank > *ahead) && rank < b->rank) {
      Stmt(db_, "UPDATE jobs SET priority=?, queue_rank=? WHERE id=?")
          .bind(1, std::int64_t{b->priority})
          .bind(2, rank)
          .bind(3, id)
          .step();
      return ReorderResult::moved;
    }
    respread(db_, b->priority);
    b = place_of(db_, *to.before);
  }
  throw Error(ErrorCode::io, "job database", "reorder", "no rank left between two jobs after spreading them");
}

}  // namespace popcut::daemon
