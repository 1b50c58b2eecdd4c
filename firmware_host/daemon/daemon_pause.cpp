// Pausing and continuing a job: the request committed first, then the device worker told.
#include "daemon.h"

namespace popcut::daemon {

PauseResult Daemon::pause(std::int64_t id) {
  const PauseResult r = store_.request_pause(id);
  if (r == PauseResult::paused) {
    // Held before it reached a device: an event as for a paused cut.
    emit_event(EventKind::job_paused, id, store_.get(id) ? store_.get(id)->device : std::string());
  } else if (r == PauseResult::requested) {
    std::lock_guard lock(mutex_);
    for (auto& w : workers_) {
      if (w->job == id) w->pause_cut = true;
    }
  }
  return r;
}

ContinueResult Daemon::continue_job(std::int64_t id) {
  const ContinueResult r = store_.continue_job(id);
  if (r == ContinueResult::continued) notify();  // the device worker may claim it again
  return r;
}

}  // namespace popcut::daemon
