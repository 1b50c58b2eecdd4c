// DeviceLink over popcut_drivers: send_job through a transport wrapper that paces a simulated
// cutter to wall-clock time and turns a stop request into a clean end at a command boundary.
#include "device_link.h"

#include <chrono>
#include <thread>

#include "popcut/drivers/file_transport.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/sim_cutter.h"

namespace popcut::daemon {
namespace {

using namespace std::chrono_literals;
using drivers::IoResult;
using drivers::TransportError;
using drivers::TransportStatus;

// Wraps the real transport for one cut. After `stop` it sends only up to the end of the command
// in flight (so no half-sent coordinate is taken for a whole one), then refuses further job bytes.
class StoppableTransport final : public drivers::Transport {
 public:
  StoppableTransport(drivers::Transport& inner, const std::atomic<bool>& stop, char terminator,
                     std::shared_ptr<drivers::SimCutter> sim, double time_scale)
      : inner_(inner), stop_(stop), terminator_(terminator), sim_(std::move(sim)), time_scale_(time_scale),
        start_(std::chrono::steady_clock::now()) {}

  TransportStatus open() override { return inner_.open(); }
  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override {
    if (stop_) {
      if (at_boundary_ || data.empty()) return {0, {TransportError::io, 0, "stopped"}};
      std::size_t n = 0;
      while (n < data.size() && data[n] != static_cast<std::uint8_t>(terminator_)) ++n;
      if (n == data.size()) return pass(data, timeout);  // the command goes on past this chunk
      IoResult r = pass(data.first(n + 1), timeout);
      if (r.status.ok()) r.status = {TransportError::io, 0, "stopped"};
      return r;
    }
    return pass(data, timeout);
  }
  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override { return inner_.read(buffer, timeout); }
  TransportStatus drain(std::chrono::milliseconds timeout) override { return inner_.drain(timeout); }
  void close() override { inner_.close(); }
  std::string describe() const override { return inner_.describe(); }
  bool stopped_at_boundary() const { return at_boundary_; }

 private:
  IoResult pass(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) {
    IoResult r = inner_.write(data, timeout);
    if (r.bytes > 0) at_boundary_ = data[r.bytes - 1] == static_cast<std::uint8_t>(terminator_);
    pace();
    return r;
  }
  // A simulated cutter runs on a virtual clock; keep wall-clock time `time_scale` times it, in
  // short sleeps so a stop request is seen promptly.
  void pace() {
    if (!sim_ || time_scale_ <= 0) return;
    const auto due = start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                  std::chrono::duration<double>(sim_->report().clock_s * time_scale_));
    while (!stop_ && std::chrono::steady_clock::now() < due) {
      std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(due - std::chrono::steady_clock::now(), 50ms));
    }
  }

  drivers::Transport& inner_;
  const std::atomic<bool>& stop_;
  char terminator_;
  std::shared_ptr<drivers::SimCutter> sim_;
  double time_scale_;
  std::chrono::steady_clock::time_point start_;
  bool at_boundary_ = true;
};

class DriversLink final : public DeviceLink {
 public:
  explicit DriversLink(const DeviceConfig& d) : device_(d) {}

  CutOutcome cut(const EncodedCut& job, const std::atomic<bool>& stop,
                 const std::function<void(std::size_t)>& progress) override {
    const drivers::DeviceProfile& profile = device_.profile;
    const bool sim = device_.transport == "sim";
    std::shared_ptr<drivers::SimCutter> cutter;
    std::unique_ptr<drivers::Transport> transport;
    if (sim) {
      drivers::SimFaults faults;
      faults.slowdown = device_.sim_slowdown;
      cutter = std::make_shared<drivers::SimCutter>(profile, faults);
      transport = std::make_unique<drivers::SimTransport>(cutter);
    } else {
      transport = std::make_unique<drivers::FileTransport>(device_.transport.substr(5));
    }
    const char terminator = profile.dialect.terminator.empty() ? ';' : profile.dialect.terminator.back();
    StoppableTransport t(*transport, stop, terminator, cutter, sim ? device_.sim_time_scale : 0);
    CutOutcome out;
    if (const TransportStatus st = t.open(); !st.ok()) {
      out.error = t.describe() + ": " + st.message;
      return out;
    }
    drivers::SendOptions opts = drivers::send_options(profile);
    if (!sim) opts.flow = drivers::FlowControl::none;  // a file answers no flow-control queries
    std::size_t reported = 0;
    opts.progress = [&](std::size_t sent, std::size_t) {
      const std::size_t n = strokes_sent(job, sent);
      if (n != reported) progress(reported = n);
    };
    const drivers::SendResult r = drivers::send_job(t, job.bytes, opts);
    out.strokes_sent = strokes_sent(job, r.bytes_sent);
    if (r.status.ok()) {
      out.kind = CutOutcome::Kind::complete;
    } else if (stop && t.stopped_at_boundary()) {
      // Lift the knife and put the tool away, as the job's own end would.
      const std::string tail = "PU" + profile.dialect.terminator + profile.dialect.finish;
      (void)transport->write({reinterpret_cast<const std::uint8_t*>(tail.data()), tail.size()}, opts.timeout);
      (void)transport->drain(opts.timeout);
      out.kind = CutOutcome::Kind::stopped;
    } else {
      out.error = t.describe() + ": " + r.status.message + " after " + std::to_string(r.bytes_sent) + " of " +
                  std::to_string(job.bytes.size()) + " bytes";
    }
    if (cutter && out.kind == CutOutcome::Kind::complete) {
      // A cutter that lost bytes, stalled or left its area did not cut the job, whatever it drew.
      const drivers::SimReport& rep = cutter->report();
      const bool clean = cutter->run_to_end() && rep.overflow_bytes == 0 && !rep.outside_area && rep.errors.empty();
      out.sim_cut = clean ? cutter->strokes() : std::vector<drivers::SimStroke>{};
    }
    t.close();
    return out;
  }
  std::string describe() const override { return device_.transport; }

 private:
  DeviceConfig device_;
};

}  // namespace

std::unique_ptr<DeviceLink> make_device_link(const DeviceConfig& device) { return std::make_unique<DriversLink>(device); }

}  // namespace popcut::daemon
