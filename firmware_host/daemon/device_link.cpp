// DeviceLink over popcut_drivers' cut session: the device string's transport, send_job with the
// worker's stop flag and stroke progress, and the session's outcome in the daemon's terms.
#include "device_link.h"

#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/send_report.h"

namespace popcut::daemon {
namespace {

// The session's result as a job outcome: complete, stopped (cancel) or failed, with the words
// the job's error message carries.
CutOutcome outcome_of(const drivers::CutResult& r, const std::string& device, bool gave_up) {
  CutOutcome out;
  const drivers::SendResult& sent = r.sent;
  out.last_stroke_sent = sent.last_stroke_sent;
  out.last_stroke_executed = sent.last_stroke_executed;
  out.abort_sent = sent.abort_sent;
  out.still_buffered = drivers::still_buffered_text(sent);
  out.discarded = drivers::discarded_text(sent);
  out.busy_for_s = sent.busy_for_s;
  if (sent.paused_cleanly()) {
    out.kind = CutOutcome::Kind::paused;
  } else if (sent.complete()) {
    out.kind = CutOutcome::Kind::complete;
    out.sim_match = r.sim && r.sim->cut_exactly_the_plan();
  } else if (sent.cancelled) {
    out.kind = CutOutcome::Kind::stopped;
    // Given up, the sender's message says what was not sent; otherwise the line failed.
    if (!sent.abort_sent) {
      out.error = gave_up ? sent.status.message
                          : "the abort sequence and the knife-up did not reach the device: " + sent.status.message;
    }
  } else if (sent.device_io_error != 0) {
    out.bytes_lost = true;
    out.error = device + ": " + sent.status.message;
  } else {
    // Both numbers: strokes after the first may have been cut and are cut again on resume.
    out.error = device + ": " + sent.status.message + "; " + drivers::counts_brief(sent);
    out.no_sheet = sent.device_stop == drivers::DeviceStop::tray_empty && sent.bytes_sent == 0;
  }
  return out;
}

class DriversLink final : public DeviceLink {
 public:
  explicit DriversLink(const DeviceConfig& d) : device_(d) {}

  CutOutcome cut(const EncodedJob& job, const std::vector<PlotterPath>& planned, const CutControl& control,
                 const std::function<void(std::size_t)>& progress) override {
    drivers::CutSessionOptions options;
    options.sim_faults.slowdown = device_.sim_slowdown;
    options.sim_time_scale = device_.sim_time_scale;
    drivers::CutSession session(device_.transport, device_.profile, options);
    CutOutcome failed;
    failed.last_stroke_sent = job.first_stroke - 1;
    if (!session.made().ok()) {
      failed.error = device_.transport + ": " + session.made().message;
      return failed;
    }
    std::size_t reported = failed.last_stroke_sent;
    drivers::CutControl send_control{&control.stop, &control.give_up, control.waiting_to_cancel,
                                     [&](const drivers::SendProgress& p) {
                                       if (p.last_stroke_sent != reported) progress(reported = p.last_stroke_sent);
                                     },
                                     control.pause};
    const drivers::CutResult r = session.run(job, planned, send_control);
    if (!r.open_status.ok()) {
      failed.error = session.describe() + ": " + r.open_status.message;
      return failed;
    }
    CutOutcome out = outcome_of(r, session.describe(), control.give_up);
    // A simulated device is made afresh for each job: nothing of this one is left to wait for.
    if (session.simulator()) out.busy_for_s = 0;
    return out;
  }
  std::string describe() const override { return device_.transport; }

 private:
  DeviceConfig device_;
};

}  // namespace

std::unique_ptr<DeviceLink> make_device_link(const DeviceConfig& device) {
  return std::make_unique<DriversLink>(device);
}

}  // namespace popcut::daemon
