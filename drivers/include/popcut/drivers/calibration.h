// Calibration overlays: a profile's measured axis correction and motion-time factor, found, read strictly and written.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <toml++/toml.h>

#include "popcut/drivers/profile.h"

namespace popcut::drivers {

// The range of [kinematics] time_factor: a device this much faster or slower than its profile's
// kinematics is measured wrong, or needs its kinematics fixed.
inline constexpr double kMinTimeFactor = 0.5, kMaxTimeFactor = 5;

// What an overlay sets, and where its numbers came from ([calibration], for people and reports).
struct CalibrationOverlay {
  std::optional<double> scale_x, scale_y, skew_deg;  // [device]
  std::optional<double> time_factor;                 // [kinematics]
  std::string profile;                               // the profile it was measured with
  std::string measured_at;                           // UTC, ISO 8601
  std::optional<double> frame_width_mm, frame_height_mm;
  std::optional<double> measured_width_mm, measured_height_mm, measured_diagonal_mm;
  std::string timed_by;  // how time_factor was measured: "status", "sim_clock", "enter", "stopwatch"
  std::optional<double> real_s, modelled_s;
};

// Where the overlay of the profile at `profile_path` lives: <dir>/<profile file stem>.toml in
// $POPCUT_CALIBRATION_DIR when set, else $XDG_CONFIG_HOME/popcut/calibration, else
// $HOME/.config/popcut/calibration; "" when none can be named (no HOME either).
std::string calibration_overlay_path(const std::string& profile_path);

// Reads an overlay; unknown sections or keys, wrong types and values outside the profile's ranges
// throw popcut::Error(invalid_input) naming `source` and "[section] key".
CalibrationOverlay parse_calibration_overlay(const std::string& text, const std::string& source);

// The overlay as TOML, with a header saying what it is and that every job on the profile uses it.
std::string format_calibration_overlay(const CalibrationOverlay& overlay);

// Writes it atomically, creating its directory; throws popcut::Error(io) naming the file.
void save_calibration_overlay(const std::string& path, const CalibrationOverlay& overlay);

// Puts the overlay's values into a profile's document ([device] scale_x, scale_y, skew_deg,
// [kinematics] time_factor), in place of the profile's own, before the profile is read.
void merge_calibration_overlay(toml::table& profile, const CalibrationOverlay& overlay);

// A report's `calibration` object: whether the profile is calibrated, by which overlay and when,
// and the values in effect.
nlohmann::json calibration_json(const DeviceCalibration& calibration);

}  // namespace popcut::drivers
