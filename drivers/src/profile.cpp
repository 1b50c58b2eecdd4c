// Device profile loader: each TOML section read through typed, range-checked getters; unknown keys rejected.
#include "popcut/drivers/profile.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>
#include <toml++/toml.h>
#include <vector>

#include "popcut/drivers/device.h"
#include "popcut/drivers/hpgl_reader.h"
#include "popcut/drivers/toml_section.h"
#include "popcut/error.h"
#include "popcut/io/files.h"

namespace popcut::drivers {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// What a set-up string may hold besides ESC sequences: commands that set state and never lower
// the knife or draw. A whitelist, since HP-GL's drawing commands are many (PD, arcs, circles,
// edges, fills, labels, symbol mode, encoded polylines, ticks) and others change what a later PD
// draws (line types, scaling, rotation). PA and PR move: with coordinates only once PU or IN in
// the same string has lifted the knife, since popcut's last command before finish (and a cancel's
// command in flight before abort) may have left it down, and init cannot know.
constexpr std::array<const char*, 11> kSetupCommands = {"IN", "DF", "PU", "PA", "PR", "SP", "VS", "FS", "!FS", "!ST", "!NR"};
constexpr const char* kSetupAllowed =
    "allowed are IN, DF, PU, SP, VS, FS, !FS, !ST, !NR, and PA/PR with coordinates only after PU or IN";

// Why `cmds` could lower the knife or draw, or "" when they cannot; `plain` is the text their
// offsets count in (device-control sequences left out).
std::string knife_problem(const std::vector<HpglCommand>& cmds, const std::string& plain) {
  bool lifted = false;
  for (const HpglCommand& cmd : cmds) {
    if (cmd.name.rfind("ESC", 0) == 0) continue;
    const std::string what = plain.substr(cmd.offset, cmd.length);
    if (cmd.name == "PD") return "'" + what + "' lowers the knife (" + kSetupAllowed + ")";
    if (std::find(kSetupCommands.begin(), kSetupCommands.end(), cmd.name) == kSetupCommands.end()) {
      return "'" + what + "' is not a set-up command and may draw or change what is cut (" + kSetupAllowed + ")";
    }
    if (cmd.name == "PU" || cmd.name == "IN") lifted = true;
    if ((cmd.name == "PA" || cmd.name == "PR") && !cmd.params.empty() && !lifted) {
      return "'" + what + "' moves with the knife perhaps down: put PU before it (" + kSetupAllowed + ")";
    }
  }
  return "";
}

// What is wrong with an init or finish string, or "" when nothing is: it is sent verbatim
// around popcut's own commands, so it must be whole HP-GL commands with numeric parameters, each
// ended by ';' or a newline, plus ESC. set-up sequences; no other control bytes (XON/XOFF or NUL
// would disturb flow control) and no queries (their replies would be read as flow control).
std::string hpgl_text_problem(const std::string& text) {
  constexpr char kEsc = '\x1b';
  std::string plain;  // without device-control sequences: what parse_hpgl's offsets count
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == kEsc) {
      std::string e(1, text[i]);
      while (!esc_complete(e) && i + 1 < text.size()) e += text[++i];
      if (!esc_complete(e)) return "an incomplete ESC sequence at the end";
      if (e.size() < 3 || e[1] != '.' || std::string_view("@HIMNRT").find(e[2]) == std::string_view::npos) {
        return "ESC sequence '" + e.substr(1) + "' is not a set-up (ESC.@, .H, .I, .M, .N, .R, .T)";
      }
      continue;
    }
    if ((c < 0x20 && c != '\n' && c != '\r' && c != '\t') || c >= 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "0x%02x", c);
      return std::string("control or non-ASCII byte ") + buf + " at byte " + std::to_string(i + 1);
    }
    plain += text[i];
  }
  for (const HpglCommand& cmd : parse_hpgl(text)) {
    if (cmd.name.rfind("ESC", 0) == 0) continue;
    const std::string what = plain.substr(cmd.offset, cmd.length);
    if (cmd.malformed) return "'" + what + "' is not a command with numeric parameters";
    const char last = cmd.offset + cmd.length > 0 ? plain[cmd.offset + cmd.length - 1] : '\0';
    if (last != ';' && last != '\n') return "'" + what + "' is not ended by ';' or a newline";
    // HP-GL's output instructions (OI, OS, OA, ...) all start with O: the device answers them.
    if (cmd.name.size() == 2 && cmd.name[0] == 'O') {
      return "'" + what + "' is an output instruction: the device's reply would be taken for a status answer or stray input";
    }
  }
  return knife_problem(parse_hpgl(text), plain);
}

constexpr std::array<const char*, 4> kKindNames = {"valley", "mountain", "cut", "outline"};
constexpr std::array<const char*, 4> kModeNames = {"cut", "score", "perforate", "skip"};
constexpr std::array<const char*, 5> kFlowNames = {"none", "xon_xoff", "rts_cts", "esc_b", "dtr_dsr"};

// "vvvv:pppp" in hex, as lsusb prints USB ids.
bool usb_id_text(const std::string& s) {
  if (s.size() != 9 || s[4] != ':') return false;
  for (std::size_t i = 0; i < 9; ++i) {
    if (i != 4 && !std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  }
  return true;
}

// HP-GL frames are right-handed seen from above, so the job must turn the pattern, never mirror
// it: a swap, or one flip, is a reflection; a swap with one flip, or both flips, a turn. Only a
// device whose own frame is mirrored (said by mirrored_frame) needs the job mirrored back.
void check_turn_not_mirror(TomlSection& dev, const HpglDialect& d) {
  const bool mirrors = d.swap_axes != (d.flip_x != d.flip_y);
  const bool mirrored_frame = dev.boolean("mirrored_frame", false);
  if (mirrors && !mirrored_frame) {
    const auto on = [](bool b) { return b ? "true" : "false"; };
    dev.fail(d.swap_axes ? "swap_axes" : d.flip_x ? "flip_x" : "flip_y",
             std::string("swap_axes = ") + on(d.swap_axes) + ", flip_x = " + on(d.flip_x) + ", flip_y = " + on(d.flip_y) +
                 " mirrors the card: a swap with one of flip_x/flip_y, or both flips, turns it instead (set "
                 "mirrored_frame only for a device whose +y runs clockwise from +x seen from above)");
  }
  if (mirrored_frame && !mirrors) {
    dev.fail("mirrored_frame", "a mirrored device frame needs a mirroring swap_axes/flip_x/flip_y (a swap alone, one "
                               "flip alone, or all three), or the card comes out mirrored");
  }
}

// The abort string is sent to stop a job, mid-stroke perhaps: its HP-GL must not cut on. Its ESC
// sequences (ESC.K and the like) pass as they are.
void check_abort(const TomlSection& t, const std::string& abort) {
  for (char c : abort) {
    // ESC plus printable HP-GL: anything else is a typo that a device would take as data.
    if (c != '\x1b' && c != '\r' && c != '\n' && (c < 0x20 || c > 0x7e)) {
      t.fail("abort", "only ESC (\\u001b), CR, LF and printable ASCII are allowed");
    }
  }
  std::string plain;  // without device-control sequences: what parse_hpgl's offsets count
  for (std::size_t i = 0; i < abort.size(); ++i) {
    if (abort[i] != '\x1b') {
      plain += abort[i];
      continue;
    }
    std::string e(1, '\x1b');
    while (!esc_complete(e) && i + 1 < abort.size()) e += abort[++i];
  }
  const std::vector<HpglCommand> cmds = parse_hpgl(abort);
  if (const std::string problem = knife_problem(cmds, plain); !problem.empty()) {
    t.fail("abort", "must not lower the knife or draw, it is sent to stop a job: " + problem);
  }
  for (const HpglCommand& cmd : cmds) {
    if (cmd.malformed && cmd.name.rfind("ESC", 0) != 0) {
      t.fail("abort", "'" + plain.substr(cmd.offset, cmd.length) + "' is not a command with numeric parameters");
    }
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

DeviceProfile parse_profile(const std::string& text, const std::string& source) {
  const toml::table root = parse_toml(text, source);
  DeviceProfile p;
  p.source = source;
  const auto section = [&](const std::string& name) {
    const toml::node* n = root.get(name);
    if (n && !n->is_table()) throw Error(ErrorCode::invalid_input, source, "[" + name + "]", "expected a table");
    return TomlSection(n ? n->as_table() : nullptr, name, source);
  };
  for (const auto& [k, v] : root) {
    const std::string key(k.str());
    if (key != "device" && key != "hpgl" && key != "transport" && key != "kinematics" && key != "plan" && key != "tool") {
      throw Error(ErrorCode::invalid_input, source, "[" + key + "]",
                  "unknown section (expected device, hpgl, transport, kinematics, plan, tool.KIND)");
    }
  }

  TomlSection dev = section("device");
  if (!root.get("device")) dev.fail("name", "missing: every profile names its device");
  p.name = dev.text("name", "");
  if (p.name.empty()) dev.fail("name", "must not be empty");
  HpglDialect& d = p.dialect;
  d.units_per_mm_x = dev.number("units_per_mm", 40, 1, 1000);
  d.units_per_mm_y = d.units_per_mm_x;
  // Calibration: real devices differ per axis by up to a few per cent.
  d.units_per_mm_x *= dev.number("scale_x", 1, 0.9, 1.1);
  d.units_per_mm_y *= dev.number("scale_y", 1, 0.9, 1.1);
  d.swap_axes = dev.boolean("swap_axes", false);
  d.flip_x = dev.boolean("flip_x", false);
  d.flip_y = dev.boolean("flip_y", false);
  check_turn_not_mirror(dev, d);
  d.allow_negative = dev.boolean("negative_coords", false);
  const double lo = d.allow_negative ? -10000 : 0;
  const double min_x = dev.number("area_min_x_mm", 0, lo, 10000), min_y = dev.number("area_min_y_mm", 0, lo, 10000);
  const double max_x = dev.number("area_max_x_mm", 600, lo, 10000), max_y = dev.number("area_max_y_mm", 1000, lo, 100000);
  if (max_x <= min_x) dev.fail("area_max_x_mm", "must exceed area_min_x_mm (" + num(min_x) + ")");
  if (max_y <= min_y) dev.fail("area_max_y_mm", "must exceed area_min_y_mm (" + num(min_y) + ")");
  // The area's corners are whole plotter units inside what the profile declares.
  d.area_min_x_pu = static_cast<std::int64_t>(std::ceil(min_x * d.units_per_mm_x));
  d.area_min_y_pu = static_cast<std::int64_t>(std::ceil(min_y * d.units_per_mm_y));
  d.area_max_x_pu = static_cast<std::int64_t>(std::floor(max_x * d.units_per_mm_x));
  d.area_max_y_pu = static_cast<std::int64_t>(std::floor(max_y * d.units_per_mm_y));
  dev.reject_unknown();

  TomlSection h = section("hpgl");
  d.init = h.text("init", "IN;");
  d.finish = h.text("finish", "PU;SP0;");
  for (const auto& [key, value] : {std::pair{"init", d.init}, std::pair{"finish", d.finish}}) {
    if (const std::string problem = hpgl_text_problem(value); !problem.empty()) h.fail(key, problem);
  }
  d.move_style = h.choice("move_style", 0, std::array<const char*, 2>{"separate", "inline"}) == 0 ? MoveStyle::separate
                                                                                                  : MoveStyle::inline_xy;
  d.coords = h.choice("coordinates", 0, std::array<const char*, 2>{"absolute", "relative"}) == 0 ? CoordMode::absolute
                                                                                                 : CoordMode::relative;
  d.terminator = h.text("terminator", ";", 2);
  // Anything else (a digit, a comma, a letter) would run into the next command's parameters.
  if (d.terminator.empty() || d.terminator.find_first_not_of(";\n\r") != std::string::npos ||
      d.terminator.find_first_of(";\n") == std::string::npos) {
    h.fail("terminator", "must be ';', a newline, or both (up to 2 bytes of ';', '\\n', '\\r' with a ';' or '\\n')");
  }
  d.newline = h.boolean("newline", false);
  d.velocity = h.boolean("velocity", true);
  d.force = static_cast<ForceStyle>(h.choice("force", 1, std::array<const char*, 3>{"none", "fs", "roland"}));
  d.force_g_per_unit = h.number("force_g_per_unit", 1, 0.1, 100);
  d.max_pairs_per_command = h.integer("max_pairs_per_command", 64, 1, 4096);
  h.reject_unknown();

  TomlSection t = section("transport");
  p.transport.uri = t.text("default", "");  // no guess: `popcut cut` asks for --device
  if (!p.transport.uri.empty()) {
    // Checked here so a bad default is blamed on the profile, not on a --device flag never given.
    DeviceAddress address;
    const TransportStatus parsed = parse_device(p.transport.uri, address);
    if (!parsed.ok()) t.fail("default", parsed.message);
  }
  p.transport.baud = t.integer("baud", 9600, 300, 4000000);
  p.transport.flow = static_cast<FlowControl>(t.choice("flow_control", 0, kFlowNames));
  p.transport.buffer_bytes = static_cast<std::size_t>(t.integer("buffer_bytes", 1024, 64, 1 << 26));
  // At least a native UART's FIFO: 0 would claim bytes still in the UART as received.
  p.transport.adapter_fifo_bytes = static_cast<std::size_t>(t.integer("adapter_fifo_bytes", 4096, 16, 1 << 20));
  p.transport.timeout_ms = t.integer("timeout_ms", 5000, 10, 600000);
  p.transport.hold_timeout_ms = t.integer("hold_timeout_ms", 120000, 10, 3600000);
  p.transport.pace_margin_percent = t.integer("pace_margin_percent", 25, 0, 1000);
  p.transport.data_bits = t.integer("data_bits", 8, 5, 8);
  p.transport.parity = static_cast<Parity>(t.choice("parity", 0, std::array<const char*, 3>{"none", "odd", "even"}));
  p.transport.stop_bits = t.integer("stop_bits", 1, 1, 2);
  p.transport.drain_query = static_cast<DrainQuery>(
      t.choice("drain_query", p.transport.flow == FlowControl::esc_b ? 1 : 0, std::array<const char*, 3>{"none", "esc_b", "esc_o"}));
  p.transport.error_query = t.choice("error_query", 0, std::array<const char*, 2>{"none", "esc_e"}) == 1;
  p.transport.abort = t.text("abort", "", 64);
  check_abort(t, p.transport.abort);
  // An abort is there to stop the device at once, which HP-style devices do by discarding their
  // buffer (ESC.K): what was received but not cut is then gone. Assuming so unless the profile
  // says otherwise never skips a stroke on resume; the opposite guess would leave strokes uncut.
  p.transport.abort_discards_buffer = t.boolean("abort_discards_buffer", !p.transport.abort.empty());
  if (p.transport.abort_discards_buffer && p.transport.abort.empty()) {
    t.fail("abort_discards_buffer", "true needs an abort sequence that makes the device discard its buffer (e.g. abort = \"\\u001b.K\")");
  }
  if (const toml::array* ids = t.array("usb_ids")) {
    for (const toml::node& n : *ids) {
      const std::string id = n.value<std::string>().value_or("");
      if (!usb_id_text(id)) t.fail("usb_ids", "\"" + id + "\" is not a USB id like \"0b4d:110a\" (hex vendor:product)");
      std::string lower;
      for (char c : id) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      p.transport.usb_ids.push_back(lower);
    }
  }
  p.transport.usb_chunk_bytes = static_cast<std::size_t>(t.integer("usb_chunk_bytes", 4096, 8, 1 << 20));
  t.reject_unknown();

  TomlSection k = section("kinematics");
  p.kinematics.travel_speed_mm_s = k.number("travel_speed_cm_s", 30, 0.1, 500) * 10;
  p.kinematics.accel_mm_s2 = k.number("accel_mm_s2", 2000, 1, 100000);
  p.kinematics.knife_up_s = k.number("knife_up_s", 0.03, 0, 10);
  p.kinematics.knife_down_s = k.number("knife_down_s", 0.03, 0, 10);
  k.reject_unknown();

  TomlSection pl = section("plan");
  p.plan.fold_gap_mm = pl.number("fold_gap_mm", 0.5, 0, 20);
  p.plan.max_turn_deg = pl.optional_number("max_turn_deg", 1, 180);
  p.plan.optimise_work = static_cast<std::uint64_t>(pl.integer("optimise_work", static_cast<int>(kDefaultOptimiseWork), 0, 1000000000));
  p.plan.blade_offset_mm = pl.number("blade_offset_mm", 0, 0, 2);
  p.plan.swivel_step_deg = pl.number("swivel_step_deg", 15, 1, 90);
  p.plan.overcut_mm = pl.number("overcut_mm", 0, 0, 10);
  p.plan.precut_mm = pl.number("precut_mm", 0, 0, 5);
  if (p.plan.precut_mm > 0 && p.plan.blade_offset_mm <= 0) {
    pl.fail("precut_mm", "a precut turns a drag knife's blade: set blade_offset_mm as well");
  }
  if (const toml::array* order = pl.array("order")) {
    p.plan.order.clear();
    std::set<std::string> names;
    for (const toml::node& n : *order) {
      const std::string s = n.value<std::string>().value_or("");
      std::size_t i = 0;
      while (i < 4 && s != kKindNames[i]) ++i;
      if (i == 4) pl.fail("order", "\"" + s + "\" is not a line kind (valley, mountain, cut, outline)");
      if (!names.insert(s).second) pl.fail("order", "\"" + s + "\" appears twice");
      p.plan.order.push_back(static_cast<PlanKind>(i));
    }
    if (names.size() != 4) pl.fail("order", "must list each of valley, mountain, cut, outline once");
  }
  pl.reject_unknown();

  const toml::node* tools = root.get("tool");
  if (tools && !tools->is_table()) throw Error(ErrorCode::invalid_input, source, "[tool]", "expected tables [tool.KIND]");
  if (tools) {
    for (const auto& [key, v] : *tools->as_table()) {
      const std::string name(key.str());
      if (std::find_if(kKindNames.begin(), kKindNames.end(), [&](const char* n) { return name == n; }) == kKindNames.end()) {
        throw Error(ErrorCode::invalid_input, source, "[tool." + name + "]", "unknown line kind (expected valley, mountain, cut, outline)");
      }
    }
  }
  for (std::size_t i = 0; i < 4; ++i) {
    const std::string name = std::string("tool.") + kKindNames[i];
    const toml::node* n = tools ? tools->as_table()->get(kKindNames[i]) : nullptr;
    if (n && !n->is_table()) throw Error(ErrorCode::invalid_input, source, "[" + name + "]", "expected a table");
    TomlSection s(n ? n->as_table() : nullptr, name, source);
    ToolSetting& tool = p.tools[i];
    KindPlan& kp = p.plan.kinds[i];
    const bool fold = i < 2;
    // Folds default to scoring at reduced force; cuts and the outline cut through.
    kp.mode = static_cast<ToolMode>(s.choice("mode", fold ? 1 : 0, kModeNames));
    tool.pen = s.integer("pen", 1, 1, 8);  // SP0 puts the tool away: a line kind cut with it is not cut
    tool.force_g = s.number("force_g", fold ? 40 : 120, 1, 2000);
    tool.speed_cm_s = s.number("speed_cm_s", 10, 0.1, 200);
    kp.passes = s.integer("passes", 1, 1, 10);
    kp.perforate_on_mm = s.number("perforate_on_mm", 1, 0.1, 100);
    kp.perforate_off_mm = s.number("perforate_off_mm", 1, 0.1, 100);
    if (!n) continue;
    s.reject_unknown();
  }
  return p;
}

DeviceProfile load_profile(const std::string& path) { return parse_profile(read_text_file(path, 1 << 20), path); }

}  // namespace popcut::drivers
