// Calibration overlays: found next to popcut's user config, read with the profile's ranges, merged before the profile.
#include "popcut/drivers/calibration.h"

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <system_error>

#include "popcut/drivers/toml_section.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/lang/device_check.h"
#include "popcut/text.h"

namespace popcut::drivers {
namespace {

std::optional<double> optional_in(TomlSection& s, const char* key, double lo, double hi) {
  return s.optional_number(key, lo, hi);
}

// [calibration]: where the numbers came from. Typed and bounded like the rest, never guessed.
void read_provenance(TomlSection& s, CalibrationOverlay& o) {
  o.profile = s.text("profile", "", 4096);
  o.measured_at = s.text("measured_at", "");
  o.frame_width_mm = optional_in(s, "frame_width_mm", 1, 10000);
  o.frame_height_mm = optional_in(s, "frame_height_mm", 1, 10000);
  o.measured_width_mm = optional_in(s, "measured_width_mm", 0, 20000);
  o.measured_height_mm = optional_in(s, "measured_height_mm", 0, 20000);
  o.measured_diagonal_mm = optional_in(s, "measured_diagonal_mm", 0, 30000);
  o.timed_by = s.text("timed_by", "");
  o.real_s = optional_in(s, "real_s", 0, 1e7);
  o.modelled_s = optional_in(s, "modelled_s", 0, 1e7);
}

void put(toml::table& t, const char* key, const std::optional<double>& v) {
  if (v) t.insert_or_assign(key, *v);
}

// The section, made when missing; null when the document has something else by that name (the
// profile's reader then says so).
toml::table* section_of(toml::table& root, const char* name) {
  if (!root.contains(name)) root.insert_or_assign(name, toml::table{});
  return root.get(name)->as_table();
}

}  // namespace

std::string calibration_overlay_path(const std::string& profile_path) {
  const std::string stem = std::filesystem::path(profile_path).stem().string() + ".toml";
  if (const char* dir = std::getenv("POPCUT_CALIBRATION_DIR"); dir && *dir)
    return (std::filesystem::path(dir) / stem).string();
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
    return (std::filesystem::path(xdg) / "popcut" / "calibration" / stem).string();
  if (const char* home = std::getenv("HOME"); home && *home)
    return (std::filesystem::path(home) / ".config" / "popcut" / "calibration" / stem).string();
  return "";
}

CalibrationOverlay parse_calibration_overlay(const std::string& text, const std::string& source) {
  const toml::table root = parse_toml(text, source);
  const auto section = [&](const char* name) {
    const toml::node* n = root.get(name);
    if (n && !n->is_table())
      throw Error(ErrorCode::invalid_input, source, std::string("[") + name + "]", "expected a table");
    return TomlSection(n ? n->as_table() : nullptr, name, source);
  };
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key != "calibration" && key != "device" && key != "kinematics") {
      throw Error(ErrorCode::invalid_input, source, "[" + key + "]",
                  "unknown section in a calibration overlay (expected calibration, device, kinematics)");
    }
  }
  CalibrationOverlay o;
  TomlSection dev = section("device");
  o.scale_x = dev.optional_number("scale_x", kMinCalibrationRatio, kMaxCalibrationRatio);
  o.scale_y = dev.optional_number("scale_y", kMinCalibrationRatio, kMaxCalibrationRatio);
  o.skew_deg = dev.optional_number("skew_deg", -kMaxSkewDeg, kMaxSkewDeg);
  dev.reject_unknown();
  TomlSection kin = section("kinematics");
  o.time_factor = kin.optional_number("time_factor", kMinTimeFactor, kMaxTimeFactor);
  kin.reject_unknown();
  TomlSection cal = section("calibration");
  read_provenance(cal, o);
  cal.reject_unknown();
  return o;
}

std::string format_calibration_overlay(const CalibrationOverlay& o) {
  std::ostringstream out;
  // Numbers as people read them (10 significant digits: far below any measurement), strings as
  // TOML writes them.
  const auto number = [&](const char* key, const std::optional<double>& v) {
    if (v) out << key << " = " << format_significant(*v, 10) << "\n";
  };
  const auto text = [&](const char* key, const std::string& v) {
    if (!v.empty()) out << key << " = " << toml::value<std::string>(v) << "\n";
  };
  out << "# popcut calibration overlay" << (o.profile.empty() ? "" : " for " + o.profile)
      << ", written by `popcut calibrate`.\n"
         "# Every job on that profile (popcut plan, cut, test-cut, submit; popcutd) uses these values in\n"
         "# place of the profile's own [device] scale_x, scale_y, skew_deg and [kinematics] time_factor.\n"
         "# Calibrate again to refine them; delete this file to go back to the profile's values.\n\n"
         "[calibration]\n";
  text("profile", o.profile);
  text("measured_at", o.measured_at);
  number("frame_width_mm", o.frame_width_mm);
  number("frame_height_mm", o.frame_height_mm);
  number("measured_width_mm", o.measured_width_mm);
  number("measured_height_mm", o.measured_height_mm);
  number("measured_diagonal_mm", o.measured_diagonal_mm);
  text("timed_by", o.timed_by);
  number("real_s", o.real_s);
  number("modelled_s", o.modelled_s);
  out << "\n[device]\n";
  number("scale_x", o.scale_x);
  number("scale_y", o.scale_y);
  number("skew_deg", o.skew_deg);
  if (o.time_factor) {
    out << "\n[kinematics]\n";
    number("time_factor", o.time_factor);
  }
  return out.str();
}

void save_calibration_overlay(const std::string& path, const CalibrationOverlay& overlay) {
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  if (ec)
    throw Error(ErrorCode::io, dir.string(), "calibration overlay", "cannot create the directory: " + ec.message());
  write_text_file(path, format_calibration_overlay(overlay));
}

void merge_calibration_overlay(toml::table& profile, const CalibrationOverlay& o) {
  if (o.scale_x || o.scale_y || o.skew_deg) {
    if (toml::table* dev = section_of(profile, "device")) {
      put(*dev, "scale_x", o.scale_x);
      put(*dev, "scale_y", o.scale_y);
      put(*dev, "skew_deg", o.skew_deg);
    }
  }
  if (o.time_factor) {
    if (toml::table* kin = section_of(profile, "kinematics")) put(*kin, "time_factor", o.time_factor);
  }
}

nlohmann::json calibration_json(const DeviceCalibration& c) {
  nlohmann::json j = {{"calibrated", !c.overlay.empty()},
                      {"overlay", c.overlay.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.overlay)},
                      {"measured_at", c.measured_at.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.measured_at)},
                      {"scale_x", c.scale_x},
                      {"scale_y", c.scale_y},
                      {"skew_deg", c.skew_deg},
                      {"time_factor", c.time_factor}};
  return j;
}

}  // namespace popcut::drivers
