// The device-language seam of the simulator: bytes in, commands out, each with what it makes a cutter do.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace popcut::drivers {

// What a command makes the simulated cutter do, whatever language it came in. A reader maps its
// language's commands onto these; the simulator's device model executes them.
enum class DeviceOp {
  unknown,          // reported, not fatal
  reset,            // knife up, absolute coordinates, no tool (HP-GL IN)
  defaults,         // absolute coordinates (DF)
  select_tool,      // params[0]: the tool (pen) number; the knife goes up (SP)
  speed,            // params[0]: knife-down speed in cm/s (VS)
  force,            // params[0]: force in the device's units (FS, !FS)
  no_effect,        // accepted, changes nothing the simulator models (!ST)
  knife_up,         // the knife goes up, then moves through params' pairs (PU)
  knife_down,       // the knife goes down, then moves through params' pairs (PD)
  absolute,         // absolute coordinates from here, then moves (PA)
  relative,         // relative coordinates from here, then moves (PR)
  report_identity,  // buffered queries, answered once executed (OI, OS, OA)
  report_status,
  report_position,
  home,                 // knife up, then to the origin (GP-GL H, TT)
  knife_up_relative,    // the knife goes up, then moves by params' pairs (GP-GL O)
  knife_down_relative,  // the knife goes down, then moves by params' pairs (GP-GL E)
  report_version,       // buffered queries of GP-GL: FG; TB71 and FA (calibration); [ and U (area)
  report_calibration,
  report_lower_left,
  report_upper_right,
  // Device control: bypasses the buffer and is answered at once.
  query_free_buffer,  // ESC.B
  query_idle,         // ESC.O
  query_io_error,     // ESC.E
  query_identity,     // ESC.A
  abort,              // ESC.K: drop what is buffered
  initialize,         // GP-GL ESC EOT: drop what is buffered, knife up, no tool
  query_state,        // GP-GL ESC ENQ: ready, moving, media unloaded or paused
  handshake_setup,    // ESC.@, .H, .I, .M, .N, .R, .T: only counted, pacing comes from the profile
  unknown_control,
};

struct DeviceCommand {
  std::string name;  // as the language spells it: "PA", "!FS", or "ESC.B" for device control
  DeviceOp op = DeviceOp::unknown;
  bool device_control = false;  // out of band: never enters the buffer
  std::vector<double> params;   // numeric parameters in order (ESC.@ and friends: theirs too)
  std::size_t offset = 0;       // byte offset of the command in the stream
  std::size_t length = 0;       // bytes it took, terminator included
  // Bytes it held in a device's buffer: its length and the separators (newlines, spaces) read
  // since the command before, which a device stores and discards like any byte.
  std::size_t buffer_bytes = 0;
  bool malformed = false;  // a parameter that is not a number
};

// What a simulated device knows when it answers a query; each language formats its own answer.
struct DeviceFacts {
  std::size_t free_buffer_bytes = 0;
  bool idle = true;  // nothing buffered, not moving
  bool media_loaded = true;
  bool paused = false;
  int io_error = 0;     // HP's ESC.E code
  bool errors = false;  // a command was malformed
  std::array<std::int64_t, 2> position{0, 0};
  bool knife_down = false;
  std::array<std::int64_t, 2> area_min{0, 0}, area_max{0, 0};
};

// An incremental reader of one device language: feed bytes as they arrive; commands come out once
// complete, so a command split across writes is read whole. Offsets count the buffered bytes only
// (device-control sequences left out).
class DeviceReader {
 public:
  virtual ~DeviceReader() = default;
  virtual void feed(std::string_view bytes, std::vector<DeviceCommand>& out) = 0;
  // The same, but stops just after a device-control command completes, so a device can answer it
  // with exactly the bytes ahead of it in its buffer; returns the bytes it took.
  virtual std::size_t feed_to_control(std::string_view bytes, std::vector<DeviceCommand>& out) = 0;
  // End of input: the last command may lack its terminator.
  virtual void finish(std::vector<DeviceCommand>& out) = 0;
  // Drops the bytes of a command not yet complete (a device discarding its buffer).
  virtual void discard_pending() = 0;
  // Whether the next byte continues a device-control command (those bypass the buffer).
  virtual bool in_device_control() const = 0;
  // Whether `byte` begins a device-control command (the device reads it even with a full buffer).
  virtual bool starts_device_control(char byte) const = 0;
  // Buffer bytes held for a command not yet complete (a device-control command being received is
  // not among them: those never enter the buffer).
  virtual std::size_t pending() const = 0;
  // The bytes a device of this language answers the query `c` with (a report_* or query_* op),
  // or "" for a command that is not one.
  virtual std::string answer(const DeviceCommand& c, const DeviceFacts& facts) const = 0;
};

}  // namespace popcut::drivers
