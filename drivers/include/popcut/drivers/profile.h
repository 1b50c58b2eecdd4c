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

// How the host keeps the device's input buffer from overflowing. xon_xoff, esc_b and status are
// paced by popcut itself; rts_cts and dtr_dsr by the serial port's hardware lines. esc_b: ask
// ESC.B for free space; status: keep at most about buffer_bytes ahead of where the motion model
// puts the device, on any line, with the drain query's idle/busy answers correcting the model
// (GP-GL's ESC ENQ: those devices give no buffer figure).
enum class FlowControl { none, xon_xoff, rts_cts, esc_b, dtr_dsr, status };
inline constexpr auto kFlowControlNames = enum_names<FlowControl>({{FlowControl::none, "none"},
                                                                   {FlowControl::xon_xoff, "xon_xoff"},
                                                                   {FlowControl::rts_cts, "rts_cts"},
                                                                   {FlowControl::esc_b, "esc_b"},
                                                                   {FlowControl::dtr_dsr, "dtr_dsr"},
                                                                   {FlowControl::status, "status"}});
const char* to_string(FlowControl flow);

// The status questions popcut asks a device, named as profiles name them; the language's host
// protocol (language.h) has their bytes and reads their answers. HP-GL: esc_b (free buffer
// bytes; whole buffer free: drained), esc_o (status word, bit 3: buffer empty), esc_e (I/O error:
// the sender's check, not a drain query a profile can name). GP-GL: esc_enq (ready, moving, tray
// empty, paused).
enum class DrainQuery { none, esc_b, esc_o, esc_e, esc_enq };
inline constexpr auto kDrainQueryNames = enum_names<DrainQuery>({{DrainQuery::none, "none"},
                                                                 {DrainQuery::esc_b, "esc_b"},
                                                                 {DrainQuery::esc_o, "esc_o"},
                                                                 {DrainQuery::esc_e, "esc_e"},
                                                                 {DrainQuery::esc_enq, "esc_enq"}});
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
  // Default: esc_b when flow is esc_b, else the language's own (GP-GL: esc_enq; HP-GL: none).
  DrainQuery drain_query = DrainQuery::none;
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
  // Pacing by the motion model (flow_control "none" on a line that cannot hold popcut off, or
  // "status"): the device is assumed to take up to this much longer than the plan's motion estimate.
  int pace_margin_percent = 25;
  // The same for a device whose pace was measured ([kinematics] time_factor from a calibration):
  // the model is then the device's own, and only how far other jobs stray from it is left.
  int pace_margin_calibrated_percent = 10;
  // The device's pace was measured (its [kinematics] time_factor comes from a calibration): time
  // pacing then uses pace_margin_calibrated_percent. Set by whatever merges the calibration in.
  bool pace_measured = false;

  // The margin time pacing uses, and the key it is set by (named where a job overflows).
  int pace_margin_in_use() const { return pace_measured ? pace_margin_calibrated_percent : pace_margin_percent; }
  const char* pace_margin_key() const {
    return pace_measured ? "[transport] pace_margin_calibrated_percent" : "[transport] pace_margin_percent";
  }
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

// Where the device's head is when a job starts. anywhere: unknown (a finish need not send it
// home), so time pacing allows for a first travel across the area. origin: where the job's finish
// leaves it (and a cancel's knife-up, which then ends with the finish too) — a device that also
// stands there after a sheet is loaded; pacing then starts the model there and allows nothing.
enum class StartsAt { anywhere, origin };
inline constexpr auto kStartsAtNames =
    enum_names<StartsAt>({{StartsAt::anywhere, "anywhere"}, {StartsAt::origin, "origin"}});

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
  StartsAt starts_at = StartsAt::anywhere;  // [kinematics] starts_at
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
