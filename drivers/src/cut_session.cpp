// A cut on one device: the transport for its string, send_job at the device's pace, the simulator's verdict.
#include "popcut/drivers/cut_session.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace popcut::drivers {

// A simulated cutter runs on a virtual clock. This keeps wall-clock time `time_scale` times it,
// in short sleeps so a cancel is seen promptly: a watchable (or killable) simulated cut.
class PacedTransport final : public Transport {
 public:
  PacedTransport(Transport& inner, const SimCutter& sim, double time_scale)
      : inner_(inner), sim_(sim), time_scale_(time_scale), start_(std::chrono::steady_clock::now()) {}

  void stop_on(const std::atomic<bool>* stop) { stop_ = stop; }
  TransportStatus open() override { return inner_.open(); }
  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override {
    IoResult r = inner_.write(data, timeout);
    pace();
    return r;
  }
  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override {
    return inner_.read(buffer, timeout);
  }
  TransportStatus drain(std::chrono::milliseconds timeout) override { return inner_.drain(timeout); }
  void close() override { inner_.close(); }
  std::string describe() const override { return inner_.describe(); }
  bool answers() const override { return inner_.answers(); }
  bool backpressure() const override { return inner_.backpressure(); }
  std::chrono::steady_clock::time_point now() const override { return inner_.now(); }

 private:
  void pace() {
    using Clock = std::chrono::steady_clock;
    const auto due = start_ + std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(sim_.report().clock_s * time_scale_));
    while (!(stop_ && *stop_) && Clock::now() < due) {
      std::this_thread::sleep_for(std::min<Clock::duration>(due - Clock::now(), std::chrono::milliseconds(50)));
    }
  }
  Transport& inner_;
  const SimCutter& sim_;
  double time_scale_;
  const std::atomic<bool>* stop_ = nullptr;
  std::chrono::steady_clock::time_point start_;
};

const char* to_string(SimVerdict verdict) { return kSimVerdictNames.name(verdict).data(); }

SimVerdict SimCheck::verdict() const {
  if (!job_complete) return SimVerdict::not_complete;
  if (!ran_to_end) return SimVerdict::stalled;
  if (overflow_bytes > 0) return SimVerdict::lost_bytes;
  if (outside_area) return SimVerdict::outside_area;
  if (first_mismatch) return SimVerdict::not_as_planned;
  if (command_errors > 0) return SimVerdict::command_errors;
  return SimVerdict::exact;
}

SimCheck check_sim_cut(SimCutter& sim, const SendResult& sent, const std::vector<PlotterPath>& planned) {
  SimCheck c;
  c.job_complete = sent.complete();
  c.ran_to_end = sim.run_to_end();
  const SimReport& r = sim.report();
  c.overflow_bytes = r.overflow_bytes;
  c.outside_area = r.outside_area;
  c.command_errors = r.errors.size();
  c.first_mismatch = first_difference(planned, sim.strokes());
  return c;
}

std::vector<PlotterPath> planned_paths(const StrokePlan& plan, const HpglDialect& dialect, std::size_t first_stroke) {
  std::vector<PlotterPath> paths = plan_in_plotter_units(plan, dialect);
  const std::size_t skipped = std::min(paths.size(), first_stroke > 0 ? first_stroke - 1 : 0);
  paths.erase(paths.begin(), paths.begin() + static_cast<std::ptrdiff_t>(skipped));
  return paths;
}

CutSession::CutSession(std::string_view device, const DeviceProfile& profile, const CutSessionOptions& options)
    : profile_(profile), made_(make_transport(device, profile, options.sim_faults)) {
  if (made_.sim && options.sim_time_scale > 0)
    paced_ = std::make_unique<PacedTransport>(*made_.transport, *made_.sim, options.sim_time_scale);
}

CutSession::~CutSession() = default;

Transport& CutSession::transport() { return paced_ ? static_cast<Transport&>(*paced_) : *made_.transport; }

std::string CutSession::describe() const {
  return made_.transport ? made_.transport->describe() : std::string(made_.address.text);
}

bool CutSession::plain_file() const {
  return made_.address.kind == DeviceKind::file && made_.address.path.rfind("/dev/", 0) != 0;
}

TransportStatus CutSession::open() { return transport().open(); }

SendResult CutSession::send(const EncodedJob& job, const CutControl& control) {
  SendOptions opts = send_options(profile_);
  // The device's pace: a real device (or a printer node) holds up to a buffer of motion after the
  // last byte, and one with no handshake is paced by it (the simulator too, on its virtual clock).
  // A plain file needs no waiting.
  if (!plain_file()) opts.motion = motion_schedule(job, profile_);
  opts.cancel = control.cancel;
  opts.give_up = control.give_up;
  opts.waiting_to_cancel = control.waiting_to_cancel;
  opts.progress = control.progress;
  opts.pause = control.pause;
  if (paced_) paced_->stop_on(control.cancel);
  return send_job(transport(), job, opts);
}

std::optional<SimCheck> CutSession::finish(const SendResult& sent, const std::vector<PlotterPath>& planned) {
  transport().close();
  if (!made_.sim) return std::nullopt;
  return check_sim_cut(*made_.sim, sent, planned);
}

CutResult CutSession::run(const EncodedJob& job, const std::vector<PlotterPath>& planned, const CutControl& control) {
  CutResult r;
  r.open_status = open();
  if (!r.open_status.ok()) return r;
  r.sent = send(job, control);
  r.sim = finish(r.sent, planned);
  return r;
}

}  // namespace popcut::drivers
