// Live designer sessions kept by recent use, saved to and read back from the job store's drafts.
#include "design_sessions.h"

#include <iterator>

#include "popcut/io/design_json.h"

namespace popcut::daemon {

std::shared_ptr<DesignSession> DesignSessions::create(const std::string& owner, const std::string& name,
                                                      FaceDesign design) {
  const std::size_t items = design.items().size();
  std::string document = to_design_json(design, name);
  const std::int64_t id = store_.create_design(owner, name, document, items);
  auto session = std::make_shared<DesignSession>(id, owner, name, std::move(design));
  session->document = std::move(document);
  return keep(std::move(session));
}

std::shared_ptr<DesignSession> DesignSessions::open(std::int64_t id, const std::string& owner) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = live_.find(id); it != live_.end()) {
      if (!owner.empty() && it->second.first->owner != owner) return nullptr;
      recent_.splice(recent_.begin(), recent_, it->second.second);
      return it->second.first;
    }
  }
  const std::optional<DesignDraft> draft = store_.design(id);
  if (!draft || (!owner.empty() && draft->owner != owner)) return nullptr;
  auto session = std::make_shared<DesignSession>(id, draft->owner, draft->name,
                                                 parse_design(draft->document, "design " + std::to_string(id)));
  session->document = draft->document;
  return keep(std::move(session));
}

std::shared_ptr<DesignSession> DesignSessions::keep(std::shared_ptr<DesignSession> session) {
  std::lock_guard lock(mutex_);
  // Two requests may read the same draft at once: the first kept wins, so edits meet one session.
  if (auto it = live_.find(session->id); it != live_.end()) return it->second.first;
  recent_.push_front(session->id);
  live_.emplace(session->id, std::make_pair(session, recent_.begin()));
  // Drop the least recent sessions nobody holds: one a request is editing must stay the only
  // session of its draft, or a second one read from the draft meanwhile would miss that edit.
  for (auto it = std::prev(recent_.end()); live_.size() > max_live_ && it != recent_.begin();) {
    const auto here = it--;
    auto found = live_.find(*here);
    if (found->second.first.use_count() > 1) continue;
    live_.erase(found);
    recent_.erase(here);
  }
  return session;
}

void DesignSessions::save(DesignSession& session) {
  session.document = to_design_json(session.design, session.name);
  store_.save_design(session.id, session.name, session.document, session.design.items().size());
}

bool DesignSessions::remove(std::int64_t id) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = live_.find(id); it != live_.end()) {
      recent_.erase(it->second.second);
      live_.erase(it);
    }
  }
  return store_.delete_design(id);
}

}  // namespace popcut::daemon
