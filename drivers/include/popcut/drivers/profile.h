// Device profiles (configs/devices/*.toml): dialect, tools, planning, kinematics, transport defaults.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "popcut/hpgl/hpgl.h"
#include "popcut/plan/plan.h"

namespace popcut::drivers {

// How the host keeps the device's input buffer from overflowing.
enum class FlowControl { none, xon_xoff, rts_cts, esc_b };  // esc_b: ask ESC.B for free space
const char* to_string(FlowControl flow);

struct TransportDefaults {
  std::string uri;  // e.g. "sim", "file:/dev/usb/lp0", "serial:/dev/ttyUSB0"
  int baud = 9600;
  FlowControl flow = FlowControl::none;
  std::size_t buffer_bytes = 1024;  // the device's input buffer
  int timeout_ms = 5000;        // one write or one reply
  int hold_timeout_ms = 120000; // the device holding the host off while it cuts
};

struct DeviceProfile {
  std::string source;  // file it came from
  std::string name;
  HpglDialect dialect;
  std::array<ToolSetting, 4> tools{};  // indexed by index_of(PlanKind)
  PlanOptions plan;                    // fold gap, turn limit, kind order, per-kind modes
  Kinematics kinematics;
  TransportDefaults transport;
  // Knife-down speed per kind in mm/s, as estimate_time_s wants it.
  std::array<double, 4> cut_speed_mm_s() const;
};

// Reads a profile; unknown sections or keys, wrong types and out-of-range values throw
// popcut::Error(invalid_input) naming the file, "[section] key" and the allowed range.
DeviceProfile parse_profile(const std::string& text, const std::string& source);
DeviceProfile load_profile(const std::string& path);

}  // namespace popcut::drivers
