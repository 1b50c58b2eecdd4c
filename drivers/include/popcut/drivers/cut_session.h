// One cut of an encoded job on one device: make and open its transport, send the job, judge what a simulator cut.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "popcut/drivers/device.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/names.h"

namespace popcut::drivers {

// How a cut is stopped: `cancel` asks for it (the command in flight is finished, the profile's
// abort and a knife-up follow); a device that holds the line (XOFF, CTS) takes the abort only when
// it lets popcut send again, so `waiting_to_cancel` is called once when the cancel waits for that,
// and `give_up` set afterwards ends the wait without sending the abort.
struct CutControl {
  const std::atomic<bool>* cancel = nullptr;
  const std::atomic<bool>* give_up = nullptr;
  std::function<void()> waiting_to_cancel;
  std::function<void(const SendProgress&)> progress;  // after every chunk
  // Pauses the cut at the end of the stroke in flight (SendOptions::pause): drained, knife up.
  const std::atomic<bool>* pause = nullptr;
};

// How a simulated cut went, worst first: each verdict holds only when none above it does.
enum class SimVerdict {
  not_complete,    // the job did not get through (failed or cancelled)
  stalled,         // the simulator could not execute all it held (frozen: it stopped answering)
  lost_bytes,      // bytes arrived with its buffer full and were lost
  outside_area,    // a move left its usable area
  not_as_planned,  // its knife-down paths differ from the planned ones
  command_errors,  // it cut the planned paths, but read malformed commands on the way
  exact,           // the simulator cut exactly the plan
};
inline constexpr auto kSimVerdictNames = enum_names<SimVerdict>({{SimVerdict::not_complete, "not_complete"},
                                                                 {SimVerdict::stalled, "stalled"},
                                                                 {SimVerdict::lost_bytes, "lost_bytes"},
                                                                 {SimVerdict::outside_area, "outside_area"},
                                                                 {SimVerdict::not_as_planned, "not_as_planned"},
                                                                 {SimVerdict::command_errors, "command_errors"},
                                                                 {SimVerdict::exact, "exact"}});
const char* to_string(SimVerdict verdict);

// What the simulated cutter made of a job, held against the paths it should have cut.
struct SimCheck {
  bool job_complete = false;  // SendResult::complete()
  bool ran_to_end = false;    // SimCutter::run_to_end() after the send
  std::size_t overflow_bytes = 0;
  bool outside_area = false;
  std::size_t command_errors = 0;             // SimReport::errors
  std::optional<std::size_t> first_mismatch;  // index into the planned paths (first_difference)

  SimVerdict verdict() const;
  // The one definition of a clean simulated cut: the verdict is `exact`.
  bool cut_exactly_the_plan() const { return verdict() == SimVerdict::exact; }
};

// Judges a simulator after a send: `planned` are the knife-down paths the job's strokes should
// make (from its first stroke on, see planned_paths). Lets the simulator run out what it holds
// first, as a device whose line dropped goes on cutting its buffer.
SimCheck check_sim_cut(SimCutter& sim, const SendResult& sent, const std::vector<PlotterPath>& planned);

// The plan's knife-down paths from stroke `first_stroke` on, worked out apart from the bytes sent
// (a job encoded from the wrong stroke shows as not_as_planned).
std::vector<PlotterPath> planned_paths(const StrokePlan& plan, const HpglDialect& dialect, std::size_t first_stroke);

struct CutResult {
  // Not ok: the device could not be opened, and nothing was sent (`sent` is empty).
  TransportStatus open_status;
  SendResult sent;
  std::optional<SimCheck> sim;  // the `sim` device only
};

class PacedTransport;

struct CutSessionOptions {
  SimFaults sim_faults;       // `sim` only
  double sim_time_scale = 0;  // `sim` only: > 0 keeps wall-clock time this many times its virtual time
};

// A cut in steps, for a caller that acts between them (popcut cut writes its files before the
// open and catches Ctrl-C only while sending); run() does them all.
class CutSession {
 public:
  // Makes the transport for `device` (sim, file:PATH, serial:..., usb:...): nothing is opened yet.
  CutSession(std::string_view device, const DeviceProfile& profile, const CutSessionOptions& options = {});
  ~CutSession();
  CutSession(const CutSession&) = delete;
  CutSession& operator=(const CutSession&) = delete;

  // Not ok: a malformed device string (bad_argument) or a backend this build leaves out.
  const TransportStatus& made() const { return made_.status; }
  const DeviceAddress& address() const { return made_.address; }
  std::string describe() const;
  // The simulated cutter behind `sim`, to inspect after the cut; null for any other device.
  const SimCutter* simulator() const { return made_.sim.get(); }
  // A plain file (not a /dev/ node) has no device to wait for: the job is not paced by its motion.
  bool plain_file() const;

  TransportStatus open();
  // send_job with the profile's options and the device's pace; the transport stays open.
  SendResult send(const EncodedJob& job, const CutControl& control);
  // Closes the transport and, on `sim`, judges the cut against `planned` (see check_sim_cut).
  std::optional<SimCheck> finish(const SendResult& sent, const std::vector<PlotterPath>& planned);

  // open, send and finish; a failed open sends nothing. `made()` must be ok.
  CutResult run(const EncodedJob& job, const std::vector<PlotterPath>& planned, const CutControl& control);

 private:
  Transport& transport();

  DeviceProfile profile_;
  MadeTransport made_;
  std::unique_ptr<PacedTransport> paced_;  // wraps made_.transport when sim_time_scale > 0
};

}  // namespace popcut::drivers
