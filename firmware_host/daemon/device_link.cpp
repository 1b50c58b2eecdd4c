// DeviceLink over popcut_drivers' seam: make_transport for the device string, send_job with its
// cancel flag and stroke progress; a simulated cutter can be paced to wall-clock time.
#include "device_link.h"

#include <chrono>
#include <thread>

#include "../cancel_text.h"
#include "popcut/drivers/device.h"
#include "popcut/drivers/job_sender.h"

namespace popcut::daemon {
namespace {

using namespace std::chrono_literals;
using drivers::IoResult;
using drivers::TransportStatus;

// A simulated cutter runs on a virtual clock. This keeps wall-clock time `time_scale` times it,
// in short sleeps so a stop request is seen promptly: a watchable (or killable) simulated cut.
class PacedTransport final : public drivers::Transport {
 public:
  PacedTransport(drivers::Transport& inner, const drivers::SimCutter& sim, double time_scale, const std::atomic<bool>& stop)
      : inner_(inner), sim_(sim), time_scale_(time_scale), stop_(stop), start_(std::chrono::steady_clock::now()) {}

  TransportStatus open() override { return inner_.open(); }
  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override {
    IoResult r = inner_.write(data, timeout);
    pace();
    return r;
  }
  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override { return inner_.read(buffer, timeout); }
  TransportStatus drain(std::chrono::milliseconds timeout) override { return inner_.drain(timeout); }
  void close() override { inner_.close(); }
  std::string describe() const override { return inner_.describe(); }
  bool answers() const override { return inner_.answers(); }
  bool backpressure() const override { return inner_.backpressure(); }
  std::chrono::steady_clock::time_point now() const override { return inner_.now(); }

 private:
  void pace() {
    const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(sim_.report().clock_s * time_scale_));
    while (!stop_ && std::chrono::steady_clock::now() < due) {
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(due - std::chrono::steady_clock::now(), 50ms));
    }
  }
  drivers::Transport& inner_;
  const drivers::SimCutter& sim_;
  double time_scale_;
  const std::atomic<bool>& stop_;
  std::chrono::steady_clock::time_point start_;
};

class DriversLink final : public DeviceLink {
 public:
  explicit DriversLink(const DeviceConfig& d) : device_(d) {}

  CutOutcome cut(const EncodedJob& job, const CutControl& control,
                 const std::function<void(std::size_t)>& progress) override {
    const std::atomic<bool>& stop = control.stop;
    const drivers::DeviceProfile& profile = device_.profile;
    drivers::SimFaults faults;
    faults.slowdown = device_.sim_slowdown;
    drivers::MadeTransport made = drivers::make_transport(device_.transport, profile, faults);
    CutOutcome out;
    out.last_stroke_sent = job.first_stroke - 1;
    if (!made.status.ok()) {
      out.error = device_.transport + ": " + made.status.message;
      return out;
    }
    std::unique_ptr<PacedTransport> paced;
    if (made.sim && device_.sim_time_scale > 0) paced = std::make_unique<PacedTransport>(*made.transport, *made.sim, device_.sim_time_scale, stop);
    drivers::Transport& t = paced ? static_cast<drivers::Transport&>(*paced) : *made.transport;
    if (const TransportStatus st = t.open(); !st.ok()) {
      out.error = t.describe() + ": " + st.message;
      return out;
    }
    drivers::SendOptions opts = drivers::send_options(profile);
    opts.cancel = &stop;
    opts.give_up = &control.give_up;
    opts.waiting_to_cancel = control.waiting_to_cancel;
    // The device's pace: a real device holds up to a buffer of motion after the last byte, and one
    // with no handshake is paced by it (the simulator too, on its own clock); a plain file (not a
    // /dev/ node) needs no waiting, as `popcut cut` treats it.
    const bool plain_file = made.address.kind == drivers::DeviceKind::file && made.address.path.rfind("/dev/", 0) != 0;
    if (!plain_file) opts.motion = drivers::motion_schedule(job.bytes, profile);
    std::size_t reported = out.last_stroke_sent;
    opts.progress = [&](const drivers::SendProgress& p) {
      if (p.last_stroke_sent != reported) progress(reported = p.last_stroke_sent);
    };
    const drivers::SendResult r = drivers::send_job(t, job, opts);
    t.close();
    out.last_stroke_sent = r.last_stroke_sent;
    out.last_stroke_executed = r.last_stroke_executed;
    out.abort_sent = r.abort_sent;
    out.still_buffered = still_buffered_text(r);
    out.discarded = discarded_text(r);
    // A simulated device is made afresh for each job: nothing of this one is left to wait for.
    out.busy_for_s = made.sim ? 0 : r.busy_for_s;
    if (r.complete()) {
      out.kind = CutOutcome::Kind::complete;
    } else if (r.cancelled) {
      out.kind = CutOutcome::Kind::stopped;
      // Given up, the sender's message says what was not sent; otherwise the line failed.
      if (!r.abort_sent) {
        out.error = control.give_up ? r.status.message : "the abort sequence and the knife-up did not reach the device: " + r.status.message;
      }
    } else if (r.device_io_error != 0) {
      out.bytes_lost = true;
      out.error = t.describe() + ": " + r.status.message;
    } else {
      // Both numbers: strokes after the first may have been cut and are cut again on resume.
      out.error = t.describe() + ": " + r.status.message + "; last stroke known executed " +
                  (r.last_stroke_executed ? std::to_string(*r.last_stroke_executed) : std::string("unknown")) +
                  ", last stroke certainly received " + std::to_string(r.last_stroke_sent) + " of " + std::to_string(job.total_strokes) +
                  ", last written " + std::to_string(r.last_stroke_written);
    }
    if (made.sim && out.kind == CutOutcome::Kind::complete) {
      // A cutter that lost bytes, stalled or left its area did not cut the job, whatever it drew.
      const drivers::SimReport& rep = made.sim->report();
      const bool clean = made.sim->run_to_end() && rep.overflow_bytes == 0 && !rep.outside_area && rep.errors.empty();
      out.sim_cut = clean ? made.sim->strokes() : std::vector<drivers::SimStroke>{};
    }
    return out;
  }
  std::string describe() const override { return device_.transport; }

 private:
  DeviceConfig device_;
};

}  // namespace

std::unique_ptr<DeviceLink> make_device_link(const DeviceConfig& device) { return std::make_unique<DriversLink>(device); }

}  // namespace popcut::daemon
