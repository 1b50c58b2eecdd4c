// Incremental GP-GL reader, the device side: ETX-terminated commands and ESC device-control sequences.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "popcut/drivers/device_reader.h"

namespace popcut::drivers {

// The GP-GL device reader. A command is a one-character name (M, D, H, J, !, \, ...) or a letter
// and a capital (FX, TB, TT, ...), then numbers separated by commas, ended by ETX (CR and LF end
// one too, as Graphtec's terminator setting allows) or, without one, by the next command's name
// ("\0,0,Z4000,6000,L0," as some hosts send it). ESC and the byte after it (ESC NUL and two
// more: the key presses) are device control, taken out of the stream wherever they arrive, and
// never enter the buffer. Each command comes out with its DeviceOp; unknown for what the
// simulator does not model, unknown_control for device control it does not know. Offsets count
// the buffered bytes only.
class GpglReader final : public DeviceReader {
 public:
  void feed(std::string_view bytes, std::vector<DeviceCommand>& out) override;
  std::size_t feed_to_control(std::string_view bytes, std::vector<DeviceCommand>& out) override;
  void finish(std::vector<DeviceCommand>& out) override;
  void discard_pending() override;
  bool in_device_control() const override { return !esc_.empty(); }
  bool starts_device_control(char byte) const override { return byte == '\x1b'; }
  std::size_t pending() const override { return pending_.size() + separators_; }
  // GP-GL answers end with ETX: ESC ENQ "0" ready, "1" moving, "2" no media, "3" paused; FG the
  // version; TB71, FA, [ and U pairs of numbers right-aligned in five columns.
  std::string answer(const DeviceCommand& c, const DeviceFacts& facts) const override;

 private:
  void end_command(std::vector<DeviceCommand>& out, bool terminated);
  std::string pending_;         // the command being received, from its first byte
  std::size_t offset_ = 0;      // buffered bytes read before pending_ (and its separators)
  std::size_t separators_ = 0;  // terminators and blanks since the last command
  std::string esc_;             // a device-control sequence being received
};

// Every command in `text`, the last one whether or not it has its ETX.
std::vector<DeviceCommand> parse_gpgl(std::string_view text);

}  // namespace popcut::drivers
