// A device's sheet (docs/api.md "Sheets"): loaded and fresh, used by a job and awaiting a fresh one, or reported empty.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "popcut/names.h"

namespace popcut::daemon {

// As stored in device_sheets. used: a job was claimed onto the sheet (so a kill -9 at any point
// after leaves it used); empty: the device itself said its tray is empty before a job began.
// Both wait for a person to say a fresh sheet is loaded.
// full: a job of several sheets filled this one; its next needs a fresh sheet, as any other job does.
enum class SheetState { loaded, used, empty, full };
inline constexpr auto kSheetStateNames = enum_names<SheetState>({{SheetState::loaded, "loaded"},
                                                                 {SheetState::used, "used"},
                                                                 {SheetState::empty, "empty"},
                                                                 {SheetState::full, "full"}});
const char* to_string(SheetState state);
std::optional<SheetState> parse_sheet_state(const std::string& text);

struct DeviceSheet {
  std::string device;
  SheetState state = SheetState::loaded;  // a device never seen has its first sheet loaded
  std::int64_t last_job = 0;              // the job that last used the sheet (0: none)
  double since_s = 0;                     // unix seconds of the last change (0: never)
  bool awaiting() const { return state != SheetState::loaded; }
};

// What the API shows as `sheet`: in_use while a job cuts, else awaiting_sheet or loaded.
const char* sheet_label(const DeviceSheet& sheet, bool cutting);

// A confirmation's outcome: the fresh sheet, or the job whose sheet is still on the device
// (cutting, paused, interrupted, or resumed and waiting) and its state.
struct SheetConfirmation {
  std::optional<DeviceSheet> sheet;
  std::int64_t held_by = 0;
  std::string held_state;
};

}  // namespace popcut::daemon
