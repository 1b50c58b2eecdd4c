// The designer's live sessions: a FaceDesign per draft in memory, one lock each, read back from its draft on demand.
#pragma once

#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "popcut/design/face_design.h"
#include "store.h"

namespace popcut::daemon {

// One draft being edited. Whoever holds `mutex` may edit `design` and then save it; a FaceDesign
// and its face model's shared caches are not safe to read while another thread edits them.
struct DesignSession {
  DesignSession(std::int64_t draft_id, std::string draft_owner, std::string draft_name, FaceDesign face_design)
      : id(draft_id), owner(std::move(draft_owner)), name(std::move(draft_name)), design(std::move(face_design)) {}
  const std::int64_t id;
  const std::string owner;
  std::mutex mutex;
  std::string name;
  FaceDesign design;
  std::string document;  // popcut.design.v1 of `design` as last saved
};

// The sessions of the last `max_live` drafts used; an older one is dropped from memory (its draft
// stays in SQLite, its undo history goes) and read back from its draft when next asked for.
class DesignSessions {
 public:
  DesignSessions(JobStore& store, std::size_t max_live) : store_(store), max_live_(max_live) {}

  // A new draft saved at once, and its session.
  std::shared_ptr<DesignSession> create(const std::string& owner, const std::string& name, FaceDesign design);
  // The draft's session, or nullptr when no draft has this id or (`owner` not empty) another
  // owner's: such a draft is not read. Reading a draft back may throw popcut::Error (a document a
  // newer popcut wrote).
  std::shared_ptr<DesignSession> open(std::int64_t id, const std::string& owner);
  // Writes the session's document and saves it (call with its mutex held).
  void save(DesignSession& session);
  // Forgets the session and deletes its draft.
  bool remove(std::int64_t id);

 private:
  std::shared_ptr<DesignSession> keep(std::shared_ptr<DesignSession> session);

  JobStore& store_;
  std::size_t max_live_;
  std::mutex mutex_;                // the maps only; never held while a design is read or edited
  std::list<std::int64_t> recent_;  // most recent first
  std::map<std::int64_t, std::pair<std::shared_ptr<DesignSession>, std::list<std::int64_t>::iterator>> live_;
};

}  // namespace popcut::daemon
