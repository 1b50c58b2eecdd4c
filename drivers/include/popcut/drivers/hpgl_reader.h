// Incremental HP-GL reader: two-letter commands, Roland "!XX" commands and ESC. device-control sequences.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "popcut/drivers/device_reader.h"

namespace popcut::drivers {

// HP-GL's commands are the simulator's device commands; the name stays for its callers.
using HpglCommand = DeviceCommand;

// The HP-GL device reader: a terminator, a newline or the next command's first letter ends a
// command, and each comes out with its DeviceOp (unknown for what the simulator does not model).
// Two things follow real devices rather than the letter of HP-GL:
// - ESC. sequences are taken out of the stream wherever they arrive, even inside another
//   command's parameters (hosts poll ESC.B between arbitrary chunks);
// - a long PA/PR/PU/PD comes out in pieces as its coordinate pairs arrive (same name, the pairs
//   so far), as a plotter consumes them from its buffer; executing the pieces equals the whole.
// Offsets count the HP-GL bytes only (device-control sequences left out).
class HpglReader final : public DeviceReader {
 public:
  void feed(std::string_view bytes, std::vector<HpglCommand>& out) override;
  // The same, but stops just after a device-control sequence completes, so a device can answer
  // it with exactly the bytes ahead of it in its buffer; returns the bytes it took.
  std::size_t feed_to_control(std::string_view bytes, std::vector<HpglCommand>& out) override;
  // End of input: the last command may lack its terminator.
  void finish(std::vector<HpglCommand>& out) override;
  // Drops the bytes of a command not yet complete (a device discarding its buffer, ESC.K).
  void discard_pending() override;
  // Whether the next byte continues a device-control sequence (those bypass the buffer).
  bool in_device_control() const override { return !esc_.empty(); }
  bool starts_device_control(char byte) const override { return byte == '\x1b'; }
  // Buffer bytes held for a command not yet complete (a device-control sequence being received
  // is not among them: those never enter the buffer).
  std::size_t pending() const override { return pending_.size() - synthetic_ + separators_; }
  // HP-GL answers end with CR: ESC.B free bytes, ESC.O 8 when idle, ESC.E the error code.
  std::string answer(const HpglCommand& c, const DeviceFacts& facts) const override;

 private:
  void parse(std::vector<HpglCommand>& out, bool final);
  std::string pending_;
  std::size_t consumed_ = 0;    // stream offset of pending_[0]
  std::size_t synthetic_ = 0;   // leading bytes of pending_ we put back (a split command's name)
  std::size_t separators_ = 0;  // separators read since the last command (its buffer_bytes count them)
  std::string esc_;             // a device-control sequence being received
};

std::vector<HpglCommand> parse_hpgl(std::string_view text);

// Whether `e`, bytes from an ESC on, is a whole device-control sequence (three bytes, or up to
// the colon for set-ups such as ESC.@...:).
bool esc_complete(const std::string& e);

}  // namespace popcut::drivers
