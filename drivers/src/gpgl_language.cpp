// GP-GL as a profile language: reads [gpgl], checks the set-up and abort commands, makes its encoder and reader.
#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "language_units.h"
#include "popcut/drivers/gpgl_reader.h"
#include "popcut/error.h"
#include "popcut/gpgl/gpgl.h"

namespace popcut::drivers {
namespace {

// The GP-GL steps Graphtec's cutters offer (a panel setting, no command selects it) and the
// units per mm each gives; Silhouettes work in 0.05 mm.
constexpr std::array<double, 4> kSteps = {0.1, 0.05, 0.025, 0.01};

double step_of(TomlSection& g) {
  const double step = g.number("step_mm", 0.05, 0.01, 0.1);
  if (std::find(kSteps.begin(), kSteps.end(), step) == kSteps.end()) {
    g.fail("step_mm", "must be one of 0.1, 0.05, 0.025, 0.01 (the device's GP-GL step setting)");
  }
  return step;
}

double gpgl_units_per_mm(TomlSection& g) { return 1 / step_of(g); }

// Why `text` is not a bare GP-GL command line (no ETX, ESC or other control bytes), or "".
std::string control_byte_problem(const std::string& text, bool allow_control) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    // The byte after an ESC is the sequence's; the command check judges it.
    const bool after_esc = i > 0 && text[i - 1] == '\x1b';
    const bool allowed = allow_control && (c == 0x1b || c == 0x03 || after_esc || c == '\r' || c == '\n');
    if ((c < 0x20 || c >= 0x7f) && !allowed) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "0x%02x", c);
      return std::string("control or non-ASCII byte ") + buf + " at byte " + std::to_string(i + 1);
    }
  }
  return "";
}

// Set-up commands a profile may add: state that never moves the head or cuts. The tool (J, FX,
// !) goes per stroke from [tool.*]; FN, FU, FW, FY and FC have keys of their own.
constexpr std::array<std::string_view, 10> kSetupCommands = {"FE", "FF", "FM", "TB", "TG", "TJ", "TF", "L", "\\", "Z"};
constexpr std::pair<std::string_view, const char*> kOwnKeys[] = {{"FN", "[gpgl] orientation"},
                                                                 {"FU", "[gpgl] page_size"},
                                                                 {"FW", "[gpgl] media"},
                                                                 {"FY", "[gpgl] track_enhancing"},
                                                                 {"FC", "[gpgl] cutter_offset_mm"},
                                                                 {"J", "[tool.*] pen, sent per stroke"},
                                                                 {"FX", "[tool.*] force_g, sent per stroke"},
                                                                 {"!", "[tool.*] speed_cm_s, sent per stroke"},
                                                                 {"TT", "[gpgl] home"},
                                                                 {"H", "[gpgl] home"}};
constexpr const char* kSetupAllowed = "allowed are FE, FF, FM, TB50-55, TB99, TG, TJ, TF, L, \\ and Z";

std::string setup_problem(const std::string& text) {
  if (const std::string p = control_byte_problem(text, false); !p.empty()) return p + " (popcut adds the ETX)";
  const std::vector<DeviceCommand> cmds = parse_gpgl(text);
  if (cmds.size() != 1) return "'" + text + "' must be one command";
  const DeviceCommand& c = cmds.front();
  if (c.malformed) return "'" + text + "' is not a command with numeric parameters";
  for (const auto& [name, key] : kOwnKeys) {
    if (c.name == name) return "'" + text + "' has a key of its own: " + key;
  }
  const bool listed = std::find(kSetupCommands.begin(), kSetupCommands.end(), c.name) != kSetupCommands.end();
  if (!listed || (c.name == "TB" && c.op != DeviceOp::no_effect)) {
    return "'" + text + "' is not a set-up command that leaves the head and knife alone (" + kSetupAllowed + ")";
  }
  return "";
}

// The abort string stops a job, mid-stroke perhaps: nothing in it may lower the knife, and no
// query may be in it (its answer would be read as the device's state).
void check_abort(const TomlSection& t, const std::string& abort) {
  if (const std::string p = control_byte_problem(abort, true); !p.empty()) {
    t.fail("abort", p + " (allowed: ESC sequences, ETX, CR, LF and printable ASCII)");
  }
  for (const DeviceCommand& c : parse_gpgl(abort)) {
    if (c.device_control) {
      if (c.op != DeviceOp::initialize) {
        t.fail("abort",
               "'" + c.name + "' is not ESC EOT (initialise), the one device-control sequence that stops a job");
      }
      continue;
    }
    const std::string what = c.name + (c.params.empty() ? "" : " ...");
    if (c.malformed) t.fail("abort", "'" + what + "' is not a command with numeric parameters");
    if (c.op == DeviceOp::knife_down || c.op == DeviceOp::knife_down_relative) {
      t.fail("abort", "must not lower the knife, it is sent to stop a job: '" + what + "' cuts");
    }
    if (c.name != "H" && c.name != "TT" && c.name != "M" && c.name != "J") {
      t.fail("abort", "'" + what + "' is not a stop command (allowed: ESC EOT, H, TT, M x,y with the knife up, J n)");
    }
  }
}

void read_levels(TomlSection& g, GpglDialect& d) {
  d.force_min = g.integer("force_min", 1, 1, 1000);
  d.force_max = g.integer("force_max", 33, 1, 1000);
  if (d.force_max < d.force_min)
    g.fail("force_max", "must be at least force_min (" + std::to_string(d.force_min) + ")");
  d.force_g_per_level = g.number("force_g_per_level", 7, 0.1, 1000);
  d.speed_min = g.integer("speed_min", 1, 1, 1000);
  d.speed_max = g.integer("speed_max", 10, 1, 1000);
  if (d.speed_max < d.speed_min)
    g.fail("speed_max", "must be at least speed_min (" + std::to_string(d.speed_min) + ")");
  d.speed_cm_s_per_level = g.number("speed_cm_s_per_level", 1, 0.01, 100);
  d.speed_base = g.integer("speed_base", 0, 0, 1000);
}

// [gpgl]: the device's GP-GL; the frame part of the dialect is [device]'s.
void read_gpgl_section(TomlSection& g, DeviceProfile& p) {
  GpglDialect& d = p.gpgl;
  d.step_mm = step_of(g);
  d.home = g.choice("home", GpglHome::none, kGpglHomeNames);
  d.finish = g.choice("finish", GpglFinish::origin, kGpglFinishNames);
  d.tool_holders = g.integer("tool_holders", 1, 1, 2);
  d.tool_in_params = g.boolean("tool_in_params", false);
  read_levels(g, d);
  d.cutter_offset_mm = g.optional_number("cutter_offset_mm", 0, 5);
  if (g.node("media")) d.media = g.integer("media", 300, 100, 300);
  if (g.node("track_enhancing")) d.track_enhancing = g.boolean("track_enhancing", false);
  if (g.node("orientation")) d.orientation = g.choice("orientation", GpglOrientation::portrait, kGpglOrientationNames);
  d.page_size = g.boolean("page_size", false);
  d.max_pairs_per_command = g.integer("max_pairs_per_command", 32, 1, 1024);
  d.setup.clear();
  if (const toml::array* setup = g.array("setup")) {
    for (const toml::node& n : *setup) {
      if (!n.is_string()) g.fail("setup", "expected strings, one GP-GL command each");
      const std::string s = n.value<std::string>().value_or("");
      if (const std::string problem = setup_problem(s); !problem.empty()) g.fail("setup", problem);
      d.setup.push_back(s);
    }
  }
}

// What [gpgl] and the other sections must agree on, once all are read.
// A per-pass value's refusal, saying which pass (1-based, as a user counts them).
void pass_checked(std::size_t i, const std::function<void()>& level) {
  try {
    level();
  } catch (const Error& e) {
    throw Error(e.code(), e.source(), e.location(), "pass " + std::to_string(i + 1) + ": " + e.message());
  }
}

void check_gpgl_profile(const DeviceProfile& p) {
  const GpglDialect& d = p.gpgl;
  if (d.cutter_offset_mm && *d.cutter_offset_mm > 0 && p.plan.blade_offset_mm > 0) {
    throw Error(ErrorCode::invalid_input, p.source, "[gpgl] cutter_offset_mm",
                "the device would compensate the blade offset on top of [plan] blade_offset_mm: set one of them to 0");
  }
  for (const PlanKind kind : kAllPlanKinds) {
    if (p.plan.kinds[index_of(kind)].mode == ToolMode::skip) continue;
    const ToolSetting& t = p.tools[index_of(kind)];
    const std::string section = "[tool." + std::string(kPlanKindNames.name(kind)) + "] ";
    if (t.pen > d.tool_holders) {
      throw Error(ErrorCode::invalid_input, p.source, section + "pen",
                  std::to_string(t.pen) + " is out of range 1 to " + std::to_string(d.tool_holders) +
                      " (the device's tool holders, [gpgl] tool_holders)");
    }
    const auto in_range = [&](const char* key, const auto& level) {
      try {
        level();
      } catch (const Error& e) {
        throw Error(ErrorCode::invalid_input, p.source, section + key, e.message());
      }
    };
    in_range("force_g", [&] { d.force_level(t.force_g); });
    in_range("speed_cm_s", [&] { d.speed_level(t.speed_cm_s); });
    // A light first pass is sent as its own FX/! too: each pass's value must suit the device.
    for (std::size_t i = 0; i < t.pass_force_g.size(); ++i) {
      in_range("pass_force_g", [&] { pass_checked(i, [&] { d.force_level(t.pass_force_g[i]); }); });
    }
    for (std::size_t i = 0; i < t.pass_speed_cm_s.size(); ++i) {
      in_range("pass_speed_cm_s", [&] { pass_checked(i, [&] { d.speed_level(t.pass_speed_cm_s[i]); }); });
    }
  }
}

double gpgl_speed_cm_s(const DeviceProfile& p, double sent) {
  return (sent - p.gpgl.speed_base) * p.gpgl.speed_cm_s_per_level;
}

// GP-GL lifts the knife only by moving: M to the usable area's origin corner, as the job's finish.
std::string gpgl_knife_up(const DeviceProfile& p) {
  return "M" + std::to_string(p.dialect.area_min_x_pu) + "," + std::to_string(p.dialect.area_min_y_pu) + kGpglEtx;
}

// As encode_gpgl_job's finish: the origin corner (the knife-up's move), home, or nowhere.
std::string gpgl_park(const DeviceProfile& p) {
  if (p.gpgl.finish == GpglFinish::origin) return gpgl_knife_up(p);
  return p.gpgl.finish == GpglFinish::home ? std::string("H") + kGpglEtx : std::string();
}

std::unique_ptr<JobEncoder> gpgl_encoder(const DeviceProfile& p) {
  GpglDialect d = p.gpgl;
  static_cast<PlotterFrame&>(d) = p.dialect;  // the frame is [device]'s, calibration included
  return std::make_unique<GpglEncoder>(std::move(d));
}
std::unique_ptr<DeviceReader> gpgl_reader() { return std::make_unique<GpglReader>(); }

}  // namespace

const LanguageUnit kGpglLanguage = {CutterLanguage::gpgl, "gpgl",        read_gpgl_section, check_abort,
                                    gpgl_encoder,         gpgl_reader,   gpgl_units_per_mm, check_gpgl_profile,
                                    gpgl_speed_cm_s,      gpgl_knife_up, gpgl_park,         gpgl_host_protocol};

}  // namespace popcut::drivers
