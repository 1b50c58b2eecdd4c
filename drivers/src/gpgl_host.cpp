// GP-GL's host side: ESC ENQ status (ready, moving, tray empty, paused), answers ended by ETX.
#include <algorithm>
#include <cstdlib>
#include <string>
#include <string_view>

#include "language_units.h"

namespace popcut::drivers {
namespace {

constexpr char kEsc = '\x1b';
constexpr char kEtx = '\x03';

// The status a GP-GL device answers to ESC ENQ (Silhouette and Graphtec alike): a digit, then ETX.
class GpglHost final : public HostProtocol {
 public:
  std::string_view query_bytes(DrainQuery q) const override { return q == DrainQuery::esc_enq ? "\x1b\x05" : ""; }
  std::string_view query_name(DrainQuery q) const override { return q == DrainQuery::esc_enq ? "ESC ENQ" : ""; }
  // Everything up to ETX is the answer: a CR or LF in it is no GP-GL and shows in the message.
  ReplyByte reply_byte(char c) const override { return c == kEtx ? ReplyByte::end : ReplyByte::part; }
  std::optional<long> read_answer(std::string_view text) const override {
    // Some Graphtecs pad their numbers with spaces.
    const auto first = text.find_first_not_of(' ');
    const auto last = text.find_last_not_of(' ');
    if (first == std::string_view::npos) return std::nullopt;
    const std::string_view digits = text.substr(first, last - first + 1);
    if (digits.size() > 12 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
      return std::nullopt;
    return std::strtol(std::string(digits).c_str(), nullptr, 10);
  }
  StatusMeaning meaning(DrainQuery q, long value) const override {
    if (q != DrainQuery::esc_enq) return StatusMeaning::nothing;
    switch (value) {
      case 0: return StatusMeaning::idle;  // ready: everything before the query is done
      case 1: return StatusMeaning::busy;  // moving
      case 2: return StatusMeaning::tray_empty;
      case 3: return StatusMeaning::paused;
      default: return StatusMeaning::nothing;
    }
  }
  // Device control is ESC and one byte (ESC ENQ, ESC EOT): it never enters the buffer.
  std::size_t buffered_bytes(std::string_view bytes) const override {
    std::size_t n = 0;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
      if (bytes[i] == kEsc) {
        ++i;
        continue;
      }
      ++n;
    }
    return n;
  }
  // HP-GL plotters ignore ESC ENQ (silence) and end their answers with CR.
  std::string mismatch_hint(std::string_view heard) const override {
    const std::string looks = heard.find('\r') != std::string_view::npos
                                  ? "its answer ends in CR, as an HP-GL plotter's does"
                              : heard.empty() ? "an HP-GL plotter ignores ESC ENQ"
                                              : "that is no GP-GL status";
    return "a GP-GL profile seems to be talking to a device that does not speak GP-GL (" + looks +
           "): check [device] language and that the profile is the device's, then the cable and the port";
  }
  DrainQuery default_query() const override { return DrainQuery::esc_enq; }
  bool init_resets_device() const override { return true; }  // ESC EOT
};

const GpglHost kGpglHost;

}  // namespace

const HostProtocol& gpgl_host_protocol() { return kGpglHost; }

}  // namespace popcut::drivers
