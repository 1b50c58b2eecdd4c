// What popcutd tells a webhook ([[notify]]): the event names, and one event on its way out.
#pragma once

#include <nlohmann/json.hpp>

#include "popcut/names.h"

namespace popcut::daemon {

// docs/api.md "Webhooks". awaiting_sheet and job_paused are raised by the sheet and pause code.
enum class EventKind { job_done, job_failed, job_interrupted, awaiting_sheet, device_error, blade_worn, job_paused };
inline constexpr auto kEventKindNames = enum_names<EventKind>({{EventKind::job_done, "job_done"},
                                                               {EventKind::job_failed, "job_failed"},
                                                               {EventKind::job_interrupted, "job_interrupted"},
                                                               {EventKind::awaiting_sheet, "awaiting_sheet"},
                                                               {EventKind::device_error, "device_error"},
                                                               {EventKind::blade_worn, "blade_worn"},
                                                               {EventKind::job_paused, "job_paused"}});
const char* to_string(EventKind kind);

// The body's parts: `job` and `device` are JSON objects, or null when the event has none.
struct Event {
  EventKind kind = EventKind::job_done;
  double at_s = 0;  // unix seconds it happened
  nlohmann::json job;
  nlohmann::json device;
};

// The seam the daemon raises events through; an implementation never blocks the caller.
class EventSink {
 public:
  virtual ~EventSink() = default;
  virtual void emit(Event event) = 0;
};

}  // namespace popcut::daemon
