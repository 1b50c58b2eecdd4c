// popcutd's sheet step: after a job a confirm_sheet device waits for a fresh sheet; confirming one lets its worker go
// on.
#include "sheets.h"

#include "daemon.h"
#include "log.h"

namespace popcut::daemon {

const char* to_string(SheetState state) { return kSheetStateNames.name(state).data(); }

std::optional<SheetState> parse_sheet_state(const std::string& text) { return kSheetStateNames.find(text); }

const char* sheet_label(const DeviceSheet& sheet, bool cutting) {
  if (cutting) return "in_use";
  return sheet.awaiting() ? "awaiting_sheet" : "loaded";
}

DeviceSheet Daemon::sheet(const std::string& device) { return store_.device_sheet(device); }

SheetConfirmation Daemon::confirm_sheet(const std::string& device) {
  SheetConfirmation sheet = store_.confirm_sheet(device);
  if (!sheet.sheet) return sheet;
  log_line(device, ": a fresh sheet is loaded");
  notify();  // its worker may claim the next job now
  return sheet;
}

void Daemon::sheet_after_job(const DeviceConfig& dev, std::int64_t job_id) {
  if (!dev.confirm_sheet) return;
  const DeviceSheet s = store_.device_sheet(dev.name);
  // An empty tray was raised when the device reported it (sheet_reported_empty).
  if (!s.awaiting() || s.state == SheetState::empty) return;
  log_line(dev.name, ": awaiting a fresh sheet after job ", job_id, ": POST /api/v1/devices/", dev.name,
           "/sheet (popcut sheet ", dev.name, ") once one is loaded");
  emit_event(EventKind::awaiting_sheet, job_id, dev.name);
}

bool Daemon::sheet_reported_empty(Worker& w, const Job& job, const CutOutcome& out) {
  const DeviceConfig& dev = *w.device;
  if (!out.no_sheet) return false;
  {
    std::lock_guard lock(mutex_);
    if (w.user_cancel) return false;
  }
  if (!store_.back_for_no_sheet(job.id, dev.name)) return false;
  if (dev.confirm_sheet) {
    log_line(dev.name, ": no sheet loaded (", out.error, "): job ", job.id,
             " goes back in line; load one, then POST /api/v1/devices/", dev.name, "/sheet (popcut sheet ", dev.name,
             ")");
  } else {
    // Nobody confirms sheets here: the device is asked again a little later, as often as it takes.
    w.busy_until = std::chrono::steady_clock::now() + kNoSheetRetry;
    w.sheet_check = true;
    log_line(dev.name, ": no sheet loaded (", out.error, "): job ", job.id, " goes back in line; asking again in ",
             std::chrono::duration_cast<std::chrono::seconds>(kNoSheetRetry).count(), " s");
  }
  emit_event(EventKind::awaiting_sheet, job.id, dev.name);
  return true;
}

void Daemon::ask_again_for_sheet(Worker& w) {
  if (w.device->confirm_sheet || !w.sheet_check) return;
  w.sheet_check = false;
  if (store_.ask_again_for_sheet(w.device->name)) log_line(w.device->name, ": asking again whether a sheet is loaded");
}

}  // namespace popcut::daemon
