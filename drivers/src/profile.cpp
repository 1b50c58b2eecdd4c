// Device profile loader: each TOML section read by its owner through typed, range-checked getters; unknown keys
// rejected.
#include "popcut/drivers/profile.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <set>
#include <string_view>
#include <toml++/toml.h>
#include <vector>

#include "language_units.h"
#include "popcut/drivers/calibration.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/motion_model.h"
#include "popcut/drivers/toml_section.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/lang/device_check.h"
#include "popcut/text.h"
#include "tool_keys.h"

namespace popcut::drivers {
namespace {

// HP-GL frames are right-handed seen from above, so the job must turn the pattern, never mirror
// it: a swap, or one flip, is a reflection; a swap with one flip, or both flips, a turn. Only a
// device whose own frame is mirrored (said by mirrored_frame) needs the job mirrored back.
void check_turn_not_mirror(TomlSection& dev, const PlotterFrame& d) {
  const bool mirrors = d.swap_axes != (d.flip_x != d.flip_y);
  const bool mirrored_frame = dev.boolean("mirrored_frame", false);
  if (mirrors && !mirrored_frame) {
    const auto on = [](bool b) { return b ? "true" : "false"; };
    dev.fail(d.swap_axes ? "swap_axes"
             : d.flip_x  ? "flip_x"
                         : "flip_y",
             std::string("swap_axes = ") + on(d.swap_axes) + ", flip_x = " + on(d.flip_x) +
                 ", flip_y = " + on(d.flip_y) +
                 " mirrors the card: a swap with one of flip_x/flip_y, or both flips, turns it instead (set "
                 "mirrored_frame only for a device whose +y runs clockwise from +x seen from above)");
  }
  if (mirrored_frame && !mirrors) {
    dev.fail("mirrored_frame",
             "a mirrored device frame needs a mirroring swap_axes/flip_x/flip_y (a swap alone, one "
             "flip alone, or all three), or the card comes out mirrored");
  }
}

// [device]: the name and the language.
void read_device_identity(TomlSection& dev, bool present, DeviceProfile& p) {
  if (!present) dev.fail("name", "missing: every profile names its device");
  p.name = dev.text("name", "");
  if (p.name.empty()) dev.fail("name", "must not be empty");
  p.language = dev.choice("language", CutterLanguage::hpgl, kCutterLanguageNames);
  p.family = dev.choice("family", DeviceFamily::generic, kDeviceFamilyNames);
}

// [device]: the frame every language shares. `language_units` are the units per mm the
// language's own section fixes (GP-GL's step), or 0 when it does not.
void read_device_frame(TomlSection& dev, double language_units, const LanguageUnit& language, DeviceProfile& p) {
  PlotterFrame& d = p.dialect;
  if (language_units > 0 && dev.node("units_per_mm")) {
    dev.fail("units_per_mm", "a " + std::string(kCutterLanguageNames.name(p.language)) + " device's unit is set in [" +
                                 std::string(language.section) + "] (step_mm); calibrate with scale_x/scale_y");
  }
  d.units_per_mm_x = language_units > 0 ? language_units : dev.number("units_per_mm", 40, 1, 1000);
  d.units_per_mm_y = d.units_per_mm_x;
  // Calibration: real devices differ per axis by up to a few per cent, and their axes may be a
  // fraction of a degree off square (an overlay written by popcut calibrate sets all three).
  DeviceCalibration& cal = p.calibration;
  cal.scale_x = dev.number("scale_x", 1, kMinCalibrationRatio, kMaxCalibrationRatio);
  cal.scale_y = dev.number("scale_y", 1, kMinCalibrationRatio, kMaxCalibrationRatio);
  cal.skew_deg = dev.number("skew_deg", 0, -kMaxSkewDeg, kMaxSkewDeg);
  d.units_per_mm_x *= cal.scale_x;
  d.units_per_mm_y *= cal.scale_y;
  d.skew_deg = cal.skew_deg;
  d.swap_axes = dev.boolean("swap_axes", false);
  d.flip_x = dev.boolean("flip_x", false);
  d.flip_y = dev.boolean("flip_y", false);
  d.sheet_at_origin = dev.boolean("sheet_at_origin", false);
  check_turn_not_mirror(dev, d);
  d.allow_negative = dev.boolean("negative_coords", false);
  const double lo = d.allow_negative ? -10000 : 0;
  const double min_x = dev.number("area_min_x_mm", 0, lo, 10000), min_y = dev.number("area_min_y_mm", 0, lo, 10000);
  // A roll runs along plotter y on HP-GL cutters and along x on a GP-GL one with its axes swapped.
  const double max_x = dev.number("area_max_x_mm", 600, lo, 100000),
               max_y = dev.number("area_max_y_mm", 1000, lo, 100000);
  if (max_x <= min_x) dev.fail("area_max_x_mm", "must exceed area_min_x_mm (" + format_significant(min_x) + ")");
  if (max_y <= min_y) dev.fail("area_max_y_mm", "must exceed area_min_y_mm (" + format_significant(min_y) + ")");
  // The area's corners are whole plotter units inside what the profile declares.
  d.area_min_x_pu = static_cast<std::int64_t>(std::ceil(min_x * d.units_per_mm_x));
  d.area_min_y_pu = static_cast<std::int64_t>(std::ceil(min_y * d.units_per_mm_y));
  d.area_max_x_pu = static_cast<std::int64_t>(std::floor(max_x * d.units_per_mm_x));
  d.area_max_y_pu = static_cast<std::int64_t>(std::floor(max_y * d.units_per_mm_y));
}

void read_kinematics_section(TomlSection& k, DeviceProfile& p) {
  Kinematics& out = p.kinematics;
  out.travel_speed_mm_s = k.number("travel_speed_cm_s", 30, 0.1, 500) * 10;
  out.accel_mm_s2 = k.number("accel_mm_s2", 2000, 1, 100000);
  out.knife_up_s = k.number("knife_up_s", 0.03, 0, 10);
  out.knife_down_s = k.number("knife_down_s", 0.03, 0, 10);
  // The device's real pace over the model's, as calibrate measures it; the sender's motion model
  // (motion_schedule) scales by it, the simulator's own clock does not. A pace that was measured
  // lets time pacing use the smaller pace_margin_calibrated_percent.
  const std::optional<double> time_factor = k.optional_number("time_factor", kMinTimeFactor, kMaxTimeFactor);
  p.calibration.time_factor = time_factor.value_or(1);
  p.transport.pace_measured = time_factor.has_value();
  p.starts_at = k.choice("starts_at", StartsAt::anywhere, kStartsAtNames);
}

// [plan]: the planner's options for this device (the per-kind modes come from [tool.*]).
void read_plan_section(TomlSection& pl, PlanOptions& out) {
  out.fold_gap_mm = pl.number("fold_gap_mm", 0.5, 0, 20);
  out.max_turn_deg = pl.optional_number("max_turn_deg", 1, 180);
  out.optimise_work =
      static_cast<std::uint64_t>(pl.integer("optimise_work", static_cast<int>(kDefaultOptimiseWork), 0, 1000000000));
  out.blade_offset_mm = pl.number("blade_offset_mm", 0, 0, 2);
  out.swivel_step_deg = pl.number("swivel_step_deg", 15, 1, 90);
  out.overcut_mm = pl.number("overcut_mm", 0, 0, 10);
  out.precut_mm = pl.number("precut_mm", 0, 0, 5);
  if (out.precut_mm > 0 && out.blade_offset_mm <= 0) {
    pl.fail("precut_mm", "a precut turns a drag knife's blade: set blade_offset_mm as well");
  }
  if (const toml::array* order = pl.array("order")) {
    out.order.clear();
    std::set<std::string> names;
    for (const toml::node& n : *order) {
      const std::string s = n.value<std::string>().value_or("");
      const std::optional<PlanKind> kind = kPlanKindNames.find(s);
      if (!kind) pl.fail("order", "\"" + s + "\" is not a line kind (" + kPlanKindNames.list(", ") + ")");
      if (!names.insert(s).second) pl.fail("order", "\"" + s + "\" appears twice");
      out.order.push_back(*kind);
    }
    if (names.size() != 4) pl.fail("order", "must list each of " + kPlanKindNames.list(", ") + " once");
  }
}

// [tool.KIND] for each line kind: the tool and how the planner draws that kind.
void read_tool_sections(const toml::table& root, const std::string& source, DeviceProfile& p) {
  const toml::node* tools = root.get("tool");
  if (tools && !tools->is_table())
    throw Error(ErrorCode::invalid_input, source, "[tool]", "expected tables [tool.KIND]");
  if (tools) {
    for (const auto& [key, v] : *tools->as_table()) {
      const std::string name(key.str());
      if (!kPlanKindNames.find(name)) {
        throw Error(ErrorCode::invalid_input, source, "[tool." + name + "]",
                    "unknown line kind (expected " + kPlanKindNames.list(", ") + ")");
      }
    }
  }
  for (const PlanKind kind : kAllPlanKinds) {
    const std::string kind_name(kPlanKindNames.name(kind));
    const std::string name = "tool." + kind_name;
    const toml::node* n = tools ? tools->as_table()->get(kind_name) : nullptr;
    if (n && !n->is_table()) throw Error(ErrorCode::invalid_input, source, "[" + name + "]", "expected a table");
    TomlSection s(n ? n->as_table() : nullptr, name, source);
    ToolSetting& tool = p.tools[index_of(kind)];
    KindPlan& kp = p.plan.kinds[index_of(kind)];
    const bool fold = kind == PlanKind::valley || kind == PlanKind::mountain;
    // Folds default to scoring at reduced force; cuts and the outline cut through.
    kp.mode = s.choice("mode", fold ? ToolMode::score : ToolMode::cut, kToolModeNames);
    tool.pen = s.integer("pen", 1, 1, 8);  // SP0 puts the tool away: a line kind cut with it is not cut
    tool.force_g = s.number("force_g", fold ? 40 : 120, kMinForceG, kMaxForceG);
    tool.speed_cm_s = s.number("speed_cm_s", 10, kMinSpeedCmS, kMaxSpeedCmS);
    read_passes(s, tool, kp);
    kp.perforate_on_mm = s.number("perforate_on_mm", 1, 0.1, 100);
    kp.perforate_off_mm = s.number("perforate_off_mm", 1, 0.1, 100);
    if (n) s.reject_unknown();
  }
}

// Every top-level key names a section some owner reads.
void check_sections(const toml::table& root, const std::string& source) {
  std::vector<std::string> known = {"device"};
  for (const LanguageUnit* unit : language_units()) known.emplace_back(unit->section);
  for (const char* s : {"transport", "kinematics", "plan", "tool"}) known.emplace_back(s);
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    std::string expected;
    for (const std::string& s : known)
      expected += (expected.empty() ? "" : ", ") + (s == "tool" ? std::string("tool.KIND") : s);
    throw Error(ErrorCode::invalid_input, source, "[" + key + "]", "unknown section (expected " + expected + ")");
  }
}

}  // namespace

const char* to_string(FlowControl flow) { return kFlowControlNames.name(flow).data(); }
const char* to_string(DrainQuery query) { return kDrainQueryNames.name(query).data(); }

std::array<double, 4> DeviceProfile::cut_speed_mm_s() const {
  std::array<double, 4> s{};
  for (std::size_t i = 0; i < 4; ++i) s[i] = tools[i].speed_cm_s * 10;
  return s;
}

namespace {

// The profile's document, read section by section by their owners.
DeviceProfile read_profile(const toml::table& root, const std::string& source) {
  check_sections(root, source);
  const auto section = [&](std::string_view name_view) {
    const std::string name(name_view);
    const toml::node* n = root.get(name);
    if (n && !n->is_table()) throw Error(ErrorCode::invalid_input, source, "[" + name + "]", "expected a table");
    return TomlSection(n ? n->as_table() : nullptr, name, source);
  };
  DeviceProfile p;
  p.source = source;
  TomlSection dev = section("device");
  read_device_identity(dev, root.get("device") != nullptr, p);
  // The language's own section, read by its unit; it may fix the frame's units.
  const LanguageUnit& language = language_unit(p.language);
  TomlSection lang = section(language.section);
  const double units = language.units_per_mm ? language.units_per_mm(lang) : 0;
  for (const LanguageUnit* other : language_units()) {
    if (other != &language && root.get(std::string(other->section))) {
      throw Error(ErrorCode::invalid_input, source, "[" + std::string(other->section) + "]",
                  "is for " + std::string(kCutterLanguageNames.name(other->language)) +
                      " devices, and [device] language is \"" + std::string(kCutterLanguageNames.name(p.language)) +
                      "\"");
    }
  }
  read_device_frame(dev, units, language, p);
  dev.reject_unknown();
  language.read_section(lang, p);
  lang.reject_unknown();
  TomlSection transport = section("transport");
  read_transport_section(transport, language, p.transport);
  transport.reject_unknown();
  TomlSection kinematics = section("kinematics");
  read_kinematics_section(kinematics, p);
  kinematics.reject_unknown();
  TomlSection plan = section("plan");
  read_plan_section(plan, p.plan);
  plan.reject_unknown();
  read_tool_sections(root, source, p);
  if (language.check_profile) language.check_profile(p);
  check_starts_at(p);
  return p;
}

}  // namespace

DeviceProfile parse_profile(const std::string& text, const std::string& source) {
  return read_profile(parse_toml(text, source), source);
}

DeviceProfile load_profile_with_overlay(const std::string& path, const std::string& overlay_path) {
  toml::table root = parse_toml(read_text_file(path, 1 << 20), path);
  CalibrationOverlay overlay;
  if (!overlay_path.empty()) {
    overlay = parse_calibration_overlay(read_text_file(overlay_path, 1 << 16), overlay_path);
    merge_calibration_overlay(root, overlay);
  }
  DeviceProfile p = read_profile(root, path);
  p.calibration.overlay = overlay_path;
  p.calibration.measured_at = overlay.measured_at;
  return p;
}

DeviceProfile load_profile(const std::string& path) {
  const std::string overlay = calibration_overlay_path(path);
  std::error_code ec;
  const bool present = !overlay.empty() && std::filesystem::exists(overlay, ec);
  return load_profile_with_overlay(path, present ? overlay : "");
}

}  // namespace popcut::drivers
