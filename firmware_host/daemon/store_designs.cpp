// The job store's designs table: the designer's drafts, one popcut.design.v1 document each, saved on every edit.
#include <sqlite3.h>

#include "sqlite_stmt.h"
#include "store.h"

namespace popcut::daemon {

void JobStore::create_design_tables() {
  exec(
      "CREATE TABLE IF NOT EXISTS designs (id INTEGER PRIMARY KEY AUTOINCREMENT, owner TEXT NOT NULL,"
      " name TEXT NOT NULL, document TEXT NOT NULL, items INTEGER NOT NULL, created_at REAL NOT NULL,"
      " updated_at REAL NOT NULL)");
  exec("CREATE INDEX IF NOT EXISTS designs_owner ON designs(owner, updated_at)");
}

std::int64_t JobStore::create_design(const std::string& owner, const std::string& name, const std::string& document,
                                     std::size_t items) {
  std::lock_guard lock(mutex_);
  const double now = unix_now_s();
  Stmt(db_, "INSERT INTO designs (owner, name, document, items, created_at, updated_at) VALUES (?1,?2,?3,?4,?5,?5)")
      .bind(1, owner)
      .bind(2, name)
      .bind(3, document)
      .bind(4, static_cast<std::int64_t>(items))
      .bind(5, now)
      .step();
  return sqlite3_last_insert_rowid(db_);
}

void JobStore::save_design(std::int64_t id, const std::string& name, const std::string& document, std::size_t items) {
  std::lock_guard lock(mutex_);
  Stmt(db_, "UPDATE designs SET name=?2, document=?3, items=?4, updated_at=?5 WHERE id=?1")
      .bind(1, id)
      .bind(2, name)
      .bind(3, document)
      .bind(4, static_cast<std::int64_t>(items))
      .bind(5, unix_now_s())
      .step();
}

std::optional<DesignDraft> JobStore::design(std::int64_t id) {
  auto [db, lock] = reader();
  Stmt s(db, "SELECT owner, name, document, items, created_at, updated_at FROM designs WHERE id=?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return DesignDraft{id, s.text(0), s.text(1), s.text(2), static_cast<std::size_t>(s.integer(3)), s.real(4), s.real(5)};
}

std::vector<DesignDraft> JobStore::list_designs(const std::string& owner, int limit) {
  auto [db, lock] = reader();
  Stmt s(db,
         "SELECT id, owner, name, items, created_at, updated_at FROM designs WHERE ?1 = '' OR owner = ?1"
         " ORDER BY updated_at DESC, id DESC LIMIT ?2");
  s.bind(1, owner).bind(2, static_cast<std::int64_t>(limit));
  std::vector<DesignDraft> out;
  while (s.step()) {
    out.push_back(DesignDraft{s.integer(0), s.text(1), s.text(2), "", static_cast<std::size_t>(s.integer(3)), s.real(4),
                              s.real(5)});
  }
  return out;
}

bool JobStore::delete_design(std::int64_t id) {
  std::lock_guard lock(mutex_);
  Stmt(db_, "DELETE FROM designs WHERE id=?").bind(1, id).step();
  return sqlite3_changes(db_) > 0;
}

}  // namespace popcut::daemon
