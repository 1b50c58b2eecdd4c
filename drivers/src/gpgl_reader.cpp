// GP-GL tokenizer, the device side: commands up to ETX, ESC sequences out of band, each mapped to what it makes a
// cutter do.
#include "popcut/drivers/gpgl_reader.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

namespace popcut::drivers {
namespace {

constexpr char kEsc = '\x1b';
constexpr char kEtx = '\x03';

bool is_terminator(char c) { return c == kEtx || c == '\n' || c == '\r'; }
bool is_blank(char c) { return c == ' ' || c == '\t'; }
bool is_capital(char c) { return c >= 'A' && c <= 'Z'; }
// The first byte of a GP-GL command: a capital or one of the symbols GP-GL names commands by.
bool starts_command(char c) {
  return is_capital(c) || std::string_view("!\"#$%&()*/:;=>?@[\\]^_").find(c) != std::string_view::npos;
}

// Numbers separated by commas (blanks ignored); a trailing comma ends the list, as GP-GL's
// "\x,y," forms have it. Anything else marks the command malformed.
void parse_params(std::string_view text, DeviceCommand& cmd) {
  std::string compact;
  for (char c : text) {
    if (!is_blank(c)) compact += c;
  }
  if (compact.empty()) return;
  if (compact.back() == ',') compact.pop_back();
  std::size_t i = 0;
  while (i <= compact.size()) {
    const std::size_t j = std::min(compact.find(',', i), compact.size());
    const std::string token = compact.substr(i, j - i);
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (token.empty() || end != token.c_str() + token.size() || !std::isfinite(v))
      cmd.malformed = true;
    else
      cmd.params.push_back(v);
    i = j + 1;
  }
}

// What each GP-GL command the simulator models makes it do. The set-up commands change nothing
// it models: FC cutter offset, FY track enhancing, FN orientation, FU page size, FW media, FE
// lift control, FF corners, FM, TG mat, TJ acceleration, TF depth, L line type, \ and Z the
// cutting area.
constexpr std::pair<std::string_view, DeviceOp> kGpglOps[] = {
    {"M", DeviceOp::knife_up},
    {"D", DeviceOp::knife_down},
    {"O", DeviceOp::knife_up_relative},
    {"E", DeviceOp::knife_down_relative},
    {"H", DeviceOp::home},
    {"TT", DeviceOp::home},
    {"J", DeviceOp::select_tool},
    {"FX", DeviceOp::force},
    {"!", DeviceOp::speed},
    {"FG", DeviceOp::report_version},
    {"FA", DeviceOp::report_calibration},
    {"[", DeviceOp::report_lower_left},
    {"U", DeviceOp::report_upper_right},
    {"FC", DeviceOp::no_effect},
    {"FY", DeviceOp::no_effect},
    {"FN", DeviceOp::no_effect},
    {"FU", DeviceOp::no_effect},
    {"FW", DeviceOp::no_effect},
    {"FE", DeviceOp::no_effect},
    {"FF", DeviceOp::no_effect},
    {"FM", DeviceOp::no_effect},
    {"TG", DeviceOp::no_effect},
    {"TJ", DeviceOp::no_effect},
    {"TF", DeviceOp::no_effect},
    {"L", DeviceOp::no_effect},
    {"\\", DeviceOp::no_effect},
    {"Z", DeviceOp::no_effect},
};

// TB's first parameter picks the function: 71 asks the sensor calibration, 50-55 and 99 set
// orientation and registration marks; others (70 cuts a test cross, 23/123 search marks) act
// in ways the simulator does not model.
DeviceOp tb_op(const DeviceCommand& cmd) {
  if (cmd.params.empty()) return DeviceOp::unknown;
  const double f = cmd.params[0];
  if (f == 71) return DeviceOp::report_calibration;
  if ((f >= 50 && f <= 55) || f == 99) return DeviceOp::no_effect;
  return DeviceOp::unknown;
}

DeviceCommand command_of(const std::string& text) {
  DeviceCommand cmd;
  const std::size_t name_len = text.size() > 1 && is_capital(text[0]) && is_capital(text[1]) ? 2 : 1;
  cmd.name = text.substr(0, name_len);
  parse_params(std::string_view(text).substr(name_len), cmd);
  cmd.op = DeviceOp::unknown;
  for (const auto& [name, op] : kGpglOps) {
    if (cmd.name == name) cmd.op = op;
  }
  if (cmd.name == "TB") cmd.op = tb_op(cmd);
  return cmd;
}

DeviceCommand control_of(const std::string& e, std::size_t offset) {
  DeviceCommand cmd;
  cmd.device_control = true;
  cmd.offset = offset;
  cmd.length = e.size();
  const auto byte = static_cast<unsigned char>(e.size() > 1 ? e[1] : 0);
  if (e.size() > 1 && e[1] == '\x04') {
    cmd.name = "ESC EOT";
    cmd.op = DeviceOp::initialize;
  } else if (e.size() > 1 && e[1] == '\x05') {
    cmd.name = "ESC ENQ";
    cmd.op = DeviceOp::query_state;
  } else {
    char buf[16];
    std::snprintf(buf, sizeof buf, "ESC 0x%02x", byte);
    cmd.name = buf;
    cmd.op = DeviceOp::unknown_control;
    cmd.malformed = e.size() < 2;
  }
  return cmd;
}

// ESC and one byte; ESC NUL takes one more (Silhouette Studio's key presses).
bool control_complete(const std::string& e) { return e.size() >= 2 && (e[1] != '\0' || e.size() >= 3); }

std::string five_columns(std::int64_t v) {
  std::string s = std::to_string(v);
  return std::string(s.size() < 5 ? 5 - s.size() : 0, ' ') + s;
}

}  // namespace

void GpglReader::feed(std::string_view bytes, std::vector<DeviceCommand>& out) {
  while (!bytes.empty()) bytes.remove_prefix(feed_to_control(bytes, out));
}

std::size_t GpglReader::feed_to_control(std::string_view bytes, std::vector<DeviceCommand>& out) {
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const char c = bytes[i];
    if (!esc_.empty() || c == kEsc) {
      esc_ += c;
      if (control_complete(esc_)) {
        out.push_back(control_of(esc_, offset_ + separators_ + pending_.size()));
        esc_.clear();
        return i + 1;
      }
      continue;
    }
    if (is_terminator(c)) {
      if (pending_.empty())
        ++separators_;
      else
        end_command(out, true);
    } else if (pending_.empty() && is_blank(c)) {
      ++separators_;
    } else {
      // Without a terminator, the next command's name ends this one, as in "\\0,0,Z4000,6000,L0,"
      // (a letter after a one-capital name is its second letter instead: FX, TB).
      const bool name_goes_on = pending_.size() == 1 && is_capital(pending_[0]) && is_capital(c);
      if (!pending_.empty() && !name_goes_on && starts_command(c)) end_command(out, false);
      pending_ += c;
    }
  }
  return bytes.size();
}

void GpglReader::end_command(std::vector<DeviceCommand>& out, bool terminated) {
  DeviceCommand cmd = command_of(pending_);
  cmd.offset = offset_ + separators_;
  cmd.length = pending_.size() + (terminated ? 1 : 0);
  cmd.buffer_bytes = cmd.length + separators_;
  offset_ += cmd.buffer_bytes;
  separators_ = 0;
  pending_.clear();
  out.push_back(std::move(cmd));
}

void GpglReader::finish(std::vector<DeviceCommand>& out) {
  if (!esc_.empty()) {
    out.push_back(control_of(esc_, offset_ + separators_ + pending_.size()));
    esc_.clear();
  }
  if (!pending_.empty()) end_command(out, false);
}

void GpglReader::discard_pending() {
  offset_ += pending_.size() + separators_;
  pending_.clear();
  separators_ = 0;
}

std::string GpglReader::answer(const DeviceCommand& c, const DeviceFacts& f) const {
  switch (c.op) {
    case DeviceOp::query_state: {
      const char* state = !f.media_loaded ? "2" : f.paused ? "3" : f.idle ? "0" : "1";
      return std::string(state) + kEtx;
    }
    case DeviceOp::report_version: return std::string("POPCUT-SIM V1.00") + kEtx;
    case DeviceOp::report_calibration: return five_columns(0) + "," + five_columns(0) + kEtx;
    case DeviceOp::report_lower_left: return five_columns(f.area_min[0]) + "," + five_columns(f.area_min[1]) + kEtx;
    case DeviceOp::report_upper_right: return five_columns(f.area_max[0]) + "," + five_columns(f.area_max[1]) + kEtx;
    default: return "";
  }
}

std::vector<DeviceCommand> parse_gpgl(std::string_view text) {
  GpglReader r;
  std::vector<DeviceCommand> out;
  r.feed(text, out);
  r.finish(out);
  return out;
}

}  // namespace popcut::drivers
