// HP-GL as a profile language: reads [hpgl], checks the set-up and abort strings, makes its encoder and reader.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "language_units.h"
#include "popcut/drivers/hpgl_reader.h"
#include "popcut/hpgl/hpgl.h"

namespace popcut::drivers {
namespace {

// What a set-up string may hold besides ESC sequences: commands that set state and never lower
// the knife or draw. A whitelist, since HP-GL's drawing commands are many (PD, arcs, circles,
// edges, fills, labels, symbol mode, encoded polylines, ticks) and others change what a later PD
// draws (line types, scaling, rotation). PA and PR move: with coordinates only once PU or IN in
// the same string has lifted the knife, since popcut's last command before finish (and a cancel's
// command in flight before abort) may have left it down, and init cannot know.
constexpr std::array<const char*, 11> kSetupCommands = {"IN", "DF", "PU",  "PA",  "PR", "SP",
                                                        "VS", "FS", "!FS", "!ST", "!NR"};
constexpr const char* kSetupAllowed =
    "allowed are IN, DF, PU, SP, VS, FS, !FS, !ST, !NR, and PA/PR with coordinates only after PU or IN";

// Why `cmds` could lower the knife or draw, or "" when they cannot; `plain` is the text their
// offsets count in (device-control sequences left out).
std::string knife_problem(const std::vector<HpglCommand>& cmds, const std::string& plain) {
  bool lifted = false;
  for (const HpglCommand& cmd : cmds) {
    if (cmd.device_control) continue;
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
    if (cmd.device_control) continue;
    const std::string what = plain.substr(cmd.offset, cmd.length);
    if (cmd.malformed) return "'" + what + "' is not a command with numeric parameters";
    const char last = cmd.offset + cmd.length > 0 ? plain[cmd.offset + cmd.length - 1] : '\0';
    if (last != ';' && last != '\n') return "'" + what + "' is not ended by ';' or a newline";
    // HP-GL's output instructions (OI, OS, OA, ...) all start with O: the device answers them.
    if (cmd.name.size() == 2 && cmd.name[0] == 'O') {
      return "'" + what +
             "' is an output instruction: the device's reply would be taken for a status answer or stray input";
    }
  }
  return knife_problem(parse_hpgl(text), plain);
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
    if (cmd.malformed && !cmd.device_control) {
      t.fail("abort", "'" + plain.substr(cmd.offset, cmd.length) + "' is not a command with numeric parameters");
    }
  }
}

// [hpgl]: the syntax of the device's HP-GL; the frame part of the dialect came from [device].
void read_hpgl_section(TomlSection& h, DeviceProfile& p) {
  HpglDialect& d = p.dialect;
  d.init = h.text("init", "IN;");
  d.finish = h.text("finish", "PU;SP0;");
  for (const auto& [key, value] : {std::pair{"init", d.init}, std::pair{"finish", d.finish}}) {
    if (const std::string problem = hpgl_text_problem(value); !problem.empty()) h.fail(key, problem);
  }
  d.move_style = h.choice("move_style", MoveStyle::separate, kMoveStyleNames);
  d.coords = h.choice("coordinates", CoordMode::absolute, kCoordModeNames);
  d.terminator = h.text("terminator", ";", 2);
  // Anything else (a digit, a comma, a letter) would run into the next command's parameters.
  if (d.terminator.empty() || d.terminator.find_first_not_of(";\n\r") != std::string::npos ||
      d.terminator.find_first_of(";\n") == std::string::npos) {
    h.fail("terminator", "must be ';', a newline, or both (up to 2 bytes of ';', '\\n', '\\r' with a ';' or '\\n')");
  }
  d.newline = h.boolean("newline", false);
  d.velocity = h.boolean("velocity", true);
  d.force = h.choice("force", ForceStyle::fs, kForceStyleNames);
  d.force_g_per_unit = h.number("force_g_per_unit", 1, 0.1, 100);
  d.max_pairs_per_command = h.integer("max_pairs_per_command", 64, 1, 4096);
}

// HP-GL's device-control status: ESC.B free bytes, ESC.O status word (bit 3: buffer empty),
// ESC.E I/O error; each answered with a decimal number and CR (some devices add LF).
class HpglHost final : public HostProtocol {
 public:
  std::string_view query_bytes(DrainQuery q) const override {
    switch (q) {
      case DrainQuery::esc_b: return "\x1b.B";
      case DrainQuery::esc_o: return "\x1b.O";
      case DrainQuery::esc_e: return "\x1b.E";
      default: return "";
    }
  }
  std::string_view query_name(DrainQuery q) const override {
    switch (q) {
      case DrainQuery::esc_b: return "ESC.B";
      case DrainQuery::esc_o: return "ESC.O";
      case DrainQuery::esc_e: return "ESC.E";
      default: return "";
    }
  }
  ReplyByte reply_byte(char c) const override {
    return c == '\r' ? ReplyByte::end : c == '\n' ? ReplyByte::skip : ReplyByte::part;
  }
  std::optional<long> read_answer(std::string_view text) const override {
    const bool number = !text.empty() && text.size() <= 12 &&
                        std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!number) return std::nullopt;
    return std::strtol(std::string(text).c_str(), nullptr, 10);
  }
  StatusMeaning meaning(DrainQuery q, long value) const override {
    if (q == DrainQuery::esc_o) return (value & 8) != 0 ? StatusMeaning::idle : StatusMeaning::busy;
    // 10-14 are device-control complaints (a query or set-up it did not take): no HP-GL byte lost.
    if (q == DrainQuery::esc_e) {
      return value == 15   ? StatusMeaning::line_garbled
             : value == 16 ? StatusMeaning::input_lost
                           : StatusMeaning::nothing;
    }
    return StatusMeaning::nothing;
  }
  std::size_t buffered_bytes(std::string_view bytes) const override {
    std::size_t n = 0;
    std::string esc;
    for (const char c : bytes) {
      if (!esc.empty() || c == '\x1b') {
        esc += c;
        if (esc_complete(esc)) esc.clear();
      } else {
        ++n;
      }
    }
    return n;
  }
  // GP-GL devices (Silhouette, Graphtec) end their answers with ETX; HP-GL's never hold one.
  std::string mismatch_hint(std::string_view heard) const override {
    if (heard.find('\x03') == std::string_view::npos) return "";
    return "its answer ends in ETX (0x03), as a GP-GL device's (Silhouette, Graphtec) does: an HP-GL profile seems "
           "to be talking to a device that speaks GP-GL; check [device] language and that the profile is the "
           "device's";
  }
  DrainQuery default_query() const override { return DrainQuery::none; }
  bool init_resets_device() const override { return false; }  // IN runs in order, after what is buffered
};

const HpglHost kHpglHost;
const HostProtocol& hpgl_host() { return kHpglHost; }

std::unique_ptr<JobEncoder> hpgl_encoder(const DeviceProfile& p) { return std::make_unique<HpglEncoder>(p.dialect); }
std::unique_ptr<DeviceReader> hpgl_reader() { return std::make_unique<HpglReader>(); }
double hpgl_speed_cm_s(const DeviceProfile&, double vs) { return vs; }
std::string hpgl_knife_up(const DeviceProfile& p) {
  return "PU" + p.dialect.terminator + (p.dialect.newline ? "\n" : "");
}
std::string hpgl_park(const DeviceProfile& p) { return p.dialect.finish; }

}  // namespace

const LanguageUnit kHpglLanguage = {CutterLanguage::hpgl, "hpgl",        read_hpgl_section, check_abort,
                                    hpgl_encoder,         hpgl_reader,   nullptr,           nullptr,
                                    hpgl_speed_cm_s,      hpgl_knife_up, hpgl_park,         hpgl_host};

}  // namespace popcut::drivers
