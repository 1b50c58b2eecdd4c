// Device profiles (configs/devices/*.toml): language and dialect, tools, planning, kinematics, transport defaults.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "popcut/gpgl/gpgl.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/lang/encoder.h"
#include "popcut/names.h"
#include "popcut/plan/plan.h"

namespace popcut::drivers {

// How the host keeps the device's input buffer from overflowing. xon_xoff and esc_b are paced by
// popcut itself; rts_cts and dtr_dsr by the serial port's hardware lines.
enum class FlowControl { none, xon_xoff, rts_cts, esc_b, dtr_dsr };  // esc_b: ask ESC.B for free space
inline constexpr auto kFlowControlNames = enum_names<FlowControl>({{FlowControl::none, "none"},
                                                                   {FlowControl::xon_xoff, "xon_xoff"},
                                                                   {FlowControl::rts_cts, "rts_cts"},
                                                                   {FlowControl::esc_b, "esc_b"},
                                                                   {FlowControl::dtr_dsr, "dtr_dsr"}});
const char* to_string(FlowControl flow);

// How to ask a device whether it has executed everything (HP-GL device-control queries). esc_e
// is not a drain query (a profile's drain_query cannot name it): the sender's I/O-error check.
enum class DrainQuery { none, esc_b, esc_o, esc_e };  // esc_b: whole buffer free; esc_o: status bit 3
inline constexpr auto kDrainQueryNames = enum_names<DrainQuery>({{DrainQuery::none, "none"},
                                                                 {DrainQuery::esc_b, "esc_b"},
                                                                 {DrainQuery::esc_o, "esc_o"},
                                                                 {DrainQuery::esc_e, "esc_e"}});
const char* to_string(DrainQuery query);

enum class Parity { none, odd, even };
inline constexpr auto kParityNames =
    enum_names<Parity>({{Parity::none, "none"}, {Parity::odd, "odd"}, {Parity::even, "even"}});

struct TransportDefaults {
  std::string uri;  // [transport] default: e.g. "sim", "file:/dev/usb/lp0", "serial:/dev/ttyUSB0"
  int baud = 9600;
  int data_bits = 8;
  Parity parity = Parity::none;
  int stop_bits = 1;
  FlowControl flow = FlowControl::none;
  DrainQuery drain_query = DrainQuery::none;  // default: esc_b when flow is esc_b
  // error_query = "esc_e": after the job, ask the device's I/O error (ESC.E); 15 (framing, parity,
  // overrun) or 16 (input buffer overflow) means bytes were lost and the cut is wrong.
  bool error_query = false;
  // Device-specific bytes sent on cancel before the knife goes up (e.g. ESC.K: discard the buffer).
  std::string abort;
  // The device drops what its buffer holds when it gets `abort` (ESC.K does): after a cancel the
  // strokes it received but had not cut are lost, so a resume starts after those it executed.
  // Default: true when there is an abort sequence.
  bool abort_discards_buffer = false;
  // USB ids ("vvvv:pppp", lower-case hex) of the devices this profile is for.
  std::vector<std::string> usb_ids;
  std::size_t usb_chunk_bytes = 4096;  // one bulk OUT transfer
  std::size_t buffer_bytes = 1024;     // the device's input buffer
  // Bytes a USB-serial adapter's transmit FIFO may hold unseen by the OS (a CP2102: 640, an
  // FT232R: 128): assumed not yet at the device where no answer confirms them. 4096 by default,
  // above every adapter checked, since a stroke counted received too early is skipped on resume.
  std::size_t adapter_fifo_bytes = 4096;
  int timeout_ms = 5000;         // one write or one reply
  int hold_timeout_ms = 120000;  // the device holding the host off while it cuts
  // Time pacing (flow_control "none" on a line that cannot hold popcut off): the device is
  // assumed to take up to this much longer than the plan's motion estimate.
  int pace_margin_percent = 25;
};

// Which maker's force, speed and blade numbers a device takes: materials (configs/materials)
// give their settings per family.
enum class DeviceFamily { generic, silhouette, graphtec, roland, uscutter, secabo };
inline constexpr auto kDeviceFamilyNames = enum_names<DeviceFamily>({{DeviceFamily::generic, "generic"},
                                                                     {DeviceFamily::silhouette, "silhouette"},
                                                                     {DeviceFamily::graphtec, "graphtec"},
                                                                     {DeviceFamily::roland, "roland"},
                                                                     {DeviceFamily::uscutter, "uscutter"},
                                                                     {DeviceFamily::secabo, "secabo"}});

// A device's calibration in effect: the profile's [device] scale_x, scale_y, skew_deg and
// [kinematics] time_factor, or its overlay's where load_profile merged one (calibration.h).
struct DeviceCalibration {
  double scale_x = 1, scale_y = 1, skew_deg = 0;  // as applied to the frame (dialect)
  double time_factor = 1;                         // the device's real job time over the motion model's
  std::string overlay;                            // the overlay merged; empty: the profile's own values
  std::string measured_at;                        // the overlay's [calibration] measured_at
};

struct DeviceProfile {
  std::string source;  // file it came from
  std::string name;
  DeviceFamily family = DeviceFamily::generic;     // [device] family
  CutterLanguage language = CutterLanguage::hpgl;  // [device] language: the encoder and reader it picks
  // The frame ([device]: units, axes, usable area) every language uses, and [hpgl]'s syntax.
  HpglDialect dialect;
  // [gpgl]'s syntax for a GP-GL device; its frame part is unused (make_encoder copies dialect's in).
  GpglDialect gpgl;
  std::array<ToolSetting, 4> tools{};  // indexed by index_of(PlanKind)
  PlanOptions plan;                    // fold gap, turn limit, kind order, per-kind modes
  Kinematics kinematics;
  TransportDefaults transport;
  DeviceCalibration calibration;
  // Knife-down speed per kind in mm/s, as estimate_time_s wants it.
  std::array<double, 4> cut_speed_mm_s() const;
};

// Reads a profile; unknown sections or keys, wrong types and out-of-range values throw
// popcut::Error(invalid_input) naming the file, "[section] key" and the allowed range.
DeviceProfile parse_profile(const std::string& text, const std::string& source);
// Reads the profile file with its calibration overlay merged when one exists where
// calibration_overlay_path says (calibration.h); a malformed overlay is an error naming it.
DeviceProfile load_profile(const std::string& path);
// The same with the overlay at `overlay_path` (it must exist), or with none when it is empty.
DeviceProfile load_profile_with_overlay(const std::string& path, const std::string& overlay_path);

}  // namespace popcut::drivers
