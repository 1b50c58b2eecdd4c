// HP-GL tokenizer: splits a byte stream into commands with numeric parameters, tolerating any dialect's separators.
#include "popcut/drivers/hpgl_reader.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string_view>
#include <utility>

namespace popcut::drivers {
namespace {

constexpr char kEsc = '\x1b';

bool is_letter(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool starts_command(char c) { return is_letter(c) || c == '!' || c == kEsc; }
bool is_separator(char c) {
  return c == ';' || c == '\n' || c == '\r' || c == ' ' || c == '\t' || c == ',' || c == '\x11' || c == '\x13';
}

// Numbers separated by commas or blanks; anything else marks the command malformed.
void parse_params(std::string_view text, HpglCommand& cmd) {
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ',' || text[i] == ' ' || text[i] == '\t' || text[i] == '\r')) ++i;
    if (i >= text.size()) break;
    std::size_t j = i;
    while (j < text.size() && text[j] != ',' && text[j] != ' ' && text[j] != '\t' && text[j] != '\r') ++j;
    const std::string token(text.substr(i, j - i));
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(v))
      cmd.malformed = true;
    else
      cmd.params.push_back(v);
    i = j;
  }
}

// What each HP-GL command the simulator models makes it do; anything else is DeviceOp::unknown.
constexpr std::pair<std::string_view, DeviceOp> kHpglOps[] = {
    {"IN", DeviceOp::reset},
    {"DF", DeviceOp::defaults},
    {"SP", DeviceOp::select_tool},
    {"VS", DeviceOp::speed},
    {"FS", DeviceOp::force},
    {"!FS", DeviceOp::force},
    {"!ST", DeviceOp::no_effect},
    {"PU", DeviceOp::knife_up},
    {"PD", DeviceOp::knife_down},
    {"PA", DeviceOp::absolute},
    {"PR", DeviceOp::relative},
    {"OI", DeviceOp::report_identity},
    {"OS", DeviceOp::report_status},
    {"OA", DeviceOp::report_position},
    {"ESC.B", DeviceOp::query_free_buffer},
    {"ESC.O", DeviceOp::query_idle},
    {"ESC.E", DeviceOp::query_io_error},
    {"ESC.A", DeviceOp::query_identity},
    {"ESC.K", DeviceOp::abort},
    {"ESC.@", DeviceOp::handshake_setup},
    {"ESC.H", DeviceOp::handshake_setup},
    {"ESC.I", DeviceOp::handshake_setup},
    {"ESC.M", DeviceOp::handshake_setup},
    {"ESC.N", DeviceOp::handshake_setup},
    {"ESC.R", DeviceOp::handshake_setup},
    {"ESC.T", DeviceOp::handshake_setup},
};

// The command with its op filled in: device control (ESC...) that the table lacks is unknown_control.
HpglCommand classified(HpglCommand cmd) {
  cmd.op = cmd.device_control ? DeviceOp::unknown_control : DeviceOp::unknown;
  for (const auto& [name, op] : kHpglOps) {
    if (cmd.name == name) cmd.op = op;
  }
  return cmd;
}

}  // namespace

// Whether a device-control sequence is complete: three bytes, or up to the colon for set-ups.
bool esc_complete(const std::string& e) {
  if (e.size() < 2) return false;
  if (e[1] != '.') return true;  // not device control: ESC and one byte
  if (e.size() < 3) return false;
  if (std::string_view("@HIMNT").find(e[2]) == std::string_view::npos) return true;
  return e.back() == ':';
}

HpglCommand esc_command(const std::string& e, std::size_t offset) {
  HpglCommand cmd;
  cmd.device_control = true;
  cmd.offset = offset;
  cmd.length = e.size();
  if (e[1] != '.') {
    cmd.name = "ESC";
    cmd.malformed = true;
    return classified(std::move(cmd));
  }
  cmd.name = std::string("ESC.") + e[2];
  if (e.size() > 3) {
    std::string p = e.substr(3, e.back() == ':' ? e.size() - 4 : e.size() - 3);
    for (char& c : p) c = c == ';' ? ',' : c;
    parse_params(p, cmd);
  }
  return classified(std::move(cmd));
}

void HpglReader::feed(std::string_view bytes, std::vector<HpglCommand>& out) {
  while (!bytes.empty()) bytes.remove_prefix(feed_to_control(bytes, out));
}

std::size_t HpglReader::feed_to_control(std::string_view bytes, std::vector<HpglCommand>& out) {
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const char c = bytes[i];
    if (!esc_.empty() || c == kEsc) {
      // Commands complete before the sequence come out before it: an ESC.B answer must count
      // every byte that arrived ahead of the query, and none after it.
      if (esc_.empty()) parse(out, false);
      esc_ += c;
      if (esc_complete(esc_)) {
        out.push_back(esc_command(esc_, consumed_ + pending_.size() - synthetic_));
        esc_.clear();
        return i + 1;
      }
      continue;
    }
    pending_ += c;
  }
  parse(out, false);
  return bytes.size();
}

void HpglReader::discard_pending() {
  consumed_ += pending_.size() - synthetic_;
  pending_.clear();
  synthetic_ = 0;
  separators_ = 0;
}

void HpglReader::finish(std::vector<HpglCommand>& out) {
  if (!esc_.empty()) {
    out.push_back(esc_command(esc_.size() >= 2 ? esc_ : esc_ + "?", consumed_));
    esc_.clear();
  }
  parse(out, true);
}

void HpglReader::parse(std::vector<HpglCommand>& out, bool final) {
  std::size_t i = 0;
  const std::string_view s = pending_;
  while (i < s.size()) {
    if (is_separator(s[i])) {
      ++i;
      ++separators_;
      continue;
    }
    HpglCommand cmd;
    cmd.offset = consumed_ + i;
    std::size_t end = 0;  // one past the command's last byte
    std::size_t params_from = 0, params_to = 0;
    if (s[i] == '!' || is_letter(s[i])) {
      const std::size_t name_len = s[i] == '!' ? 3 : 2;
      if (s.size() - i < name_len) {
        if (!final) break;
        cmd.name = std::string(s.substr(i));
        cmd.malformed = true;
        end = s.size();
      } else {
        cmd.name = std::string(s.substr(i, name_len));
        for (char& c : cmd.name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        std::size_t j = i + name_len;
        while (j < s.size() && s[j] != ';' && s[j] != '\n' && !starts_command(s[j])) ++j;
        if (j == s.size() && !final) {
          // The parameters may go on in the next write. A coordinate command hands over the
          // pairs complete so far (those followed by a separator) and keeps the rest.
          const bool coords = cmd.name == "PA" || cmd.name == "PR" || cmd.name == "PU" || cmd.name == "PD";
          if (!coords) break;
          std::size_t numbers = 0, cut = 0;
          for (std::size_t k = i + name_len; k < j; ++k) {
            if ((s[k] == ',' || s[k] == ' ') && k > i + name_len && s[k - 1] != ',' && s[k - 1] != ' ') {
              ++numbers;
              if (numbers % 2 == 0) cut = k;
            }
          }
          if (cut == 0) break;
          parse_params(s.substr(i + name_len, cut - i - name_len), cmd);
          cmd.length = cut + 1 - i - (i == 0 ? synthetic_ : 0);  // bytes that really arrived
          cmd.buffer_bytes = cmd.length + std::exchange(separators_, 0);
          out.push_back(classified(cmd));
          // Put the name back before the rest, as if the command had been sent in two.
          const std::string name = std::string(s.substr(i, name_len));
          const std::size_t real = cut + 1 - synthetic_;
          consumed_ += real;
          pending_ = name + pending_.substr(cut + 1);
          synthetic_ = name_len;
          return;
        }
        params_from = i + name_len;
        params_to = j;
        end = j < s.size() && (s[j] == ';' || s[j] == '\n') ? j + 1 : j;
      }
    } else {
      cmd.name = "?";
      cmd.malformed = true;
      end = i + 1;
    }
    if (params_to > params_from) parse_params(s.substr(params_from, params_to - params_from), cmd);
    cmd.length = end - i - (i == 0 ? synthetic_ : 0);
    cmd.buffer_bytes = cmd.length + std::exchange(separators_, 0);
    out.push_back(classified(std::move(cmd)));
    i = end;
  }
  const std::size_t real = i > synthetic_ ? i - synthetic_ : 0;
  if (i > 0) synthetic_ = 0;
  consumed_ += real;
  pending_.erase(0, i);
}

std::string HpglReader::answer(const HpglCommand& c, const DeviceFacts& f) const {
  switch (c.op) {
    case DeviceOp::query_free_buffer: return std::to_string(f.free_buffer_bytes) + "\r";
    case DeviceOp::query_idle: return std::string(f.idle ? "8" : "0") + "\r";
    case DeviceOp::query_io_error: return std::to_string(f.io_error) + "\r";
    case DeviceOp::query_identity: return "popcut-sim,0\r";
    case DeviceOp::report_identity: return "popcut-sim\r";
    case DeviceOp::report_status: return std::string(f.errors ? "48" : "16") + "\r";
    case DeviceOp::report_position:
      return std::to_string(f.position[0]) + "," + std::to_string(f.position[1]) + "," + (f.knife_down ? "1" : "0") +
             "\r";
    default: return "";
  }
}

std::vector<HpglCommand> parse_hpgl(std::string_view text) {
  HpglReader r;
  std::vector<HpglCommand> out;
  r.feed(text, out);
  r.finish(out);
  return out;
}

}  // namespace popcut::drivers
