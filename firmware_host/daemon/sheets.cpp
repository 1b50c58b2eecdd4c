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
  if (!s.awaiting()) return;
  log_line(dev.name, ": awaiting a fresh sheet after job ", job_id, ": POST /api/v1/devices/", dev.name,
           "/sheet (popcut sheet ", dev.name, ") once one is loaded");
  emit_event(EventKind::awaiting_sheet, job_id, dev.name);
}

}  // namespace popcut::daemon
