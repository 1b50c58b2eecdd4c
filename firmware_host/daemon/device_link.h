// The daemon's one seam to a cutter: send a job from a stroke on, report strokes fully sent, stop safely on request.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "config.h"
#include "popcut/hpgl/hpgl.h"

namespace popcut::daemon {

struct CutOutcome {
  // paused: stopped at a stroke boundary, drained and the knife lifted: strokes through
  // last_stroke_sent are cut, no more.
  enum class Kind { complete, stopped, failed, paused } kind = Kind::failed;
  std::size_t last_stroke_sent = 0;  // stroke number (from 1) of the last stroke the device certainly received
  std::optional<std::size_t> last_stroke_executed;  // the last it is known to have executed (nullopt: unknown)
  std::string error;           // failed: what the transport said; stopped: why the knife-up did not reach the device
  bool abort_sent = false;     // stopped: the abort sequence and knife-up reached the device
  std::string still_buffered;  // stopped or failed: what the device may still cut ("up to 212 bytes (strokes 5..9)")
  // stopped by an abort that makes the device drop its buffer: last_stroke_sent is then what it
  // executed, and this says so and which strokes a resume may cut a second time ("" otherwise)
  std::string discarded;
  // failed: the device reported lost or garbled bytes (ESC.E 15 or 16): what it cut is not the
  // job, so no resume point repairs it.
  bool bytes_lost = false;
  // failed before the first byte: the device said no sheet is loaded (GP-GL tray empty), and
  // nothing was sent.
  bool no_sheet = false;
  // stopped or failed on a device paced by time: how long it may go on cutting what it holds
  // (seconds, by the profile's pace); a job sent to it sooner would overrun its buffer.
  double busy_for_s = 0;
  // sim devices, complete cuts: the simulated cutter cut exactly the planned paths
  // (drivers::SimCheck::cut_exactly_the_plan).
  bool sim_match = false;
};

// How a cut is stopped: `stop` asks for it; a device that holds the line (XOFF, CTS) takes the
// abort only when it lets popcut send again, so `waiting_to_cancel` is called once when the stop
// waits for that, and `give_up` set afterwards ends the wait without sending the abort.
struct CutControl {
  const std::atomic<bool>& stop;
  const std::atomic<bool>& give_up;
  std::function<void()> waiting_to_cancel;
  // Set: finish the stroke in flight, lift the knife, let the device drain; the outcome is paused.
  const std::atomic<bool>* pause = nullptr;
};

class DeviceLink {
 public:
  virtual ~DeviceLink() = default;
  // Sends `job`; `progress` whenever another stroke is fully sent. When `control.stop` becomes
  // true the command in flight is completed, the profile's abort bytes and a knife-up follow,
  // and the outcome is `stopped`. `planned`: the knife-down paths the job should cut
  // (drivers::planned_paths), held against a simulated cutter's.
  virtual CutOutcome cut(const EncodedJob& job, const std::vector<PlotterPath>& planned, const CutControl& control,
                         const std::function<void(std::size_t last_stroke_sent)>& progress) = 0;
  virtual std::string describe() const = 0;
};

// Any device string drivers::make_transport takes (sim, file:PATH, serial:..., usb:...); a sim
// device gets a fresh simulated cutter per job, optionally paced to wall-clock time.
std::unique_ptr<DeviceLink> make_device_link(const DeviceConfig& device);

}  // namespace popcut::daemon
