// popcut plan / cut: pattern → stroke plan → HP-GL for a device profile → a transport (sim, file, serial, usb).
#include "cli_cut.h"
#include "resume_advice.h"
#include "report_json.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>

#include "cancel_text.h"
#include "cli/checks.h"
#include "cli/common.h"
#include "cli/sim_plotter.h"
#include "config_dir.h"
#include "popcut/drivers/device.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/text.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/plan/plan.h"

namespace popcut::cli {
namespace {

using nlohmann::json;
using drivers::DeviceProfile;

json kind_json(const KindStats& k, double est_s) {
  return {{"strokes", k.strokes},   {"pen_lifts", k.pen_lifts}, {"pen_lift_bound", k.pen_lift_bound},
          {"cut_mm", k.cut_mm},     {"travel_mm", k.travel_mm}, {"est_time_s", est_s},
          {"folds_dropped", k.folds_dropped}, {"strokes_below_resolution", k.strokes_below_resolution}, {"precuts", k.precuts}};
}

struct Job {
  DeviceProfile profile;
  StrokePlan plan;
  TimeEstimate time;
  std::string hpgl;     // the whole job
  EncodedJob encoded;   // what is sent: the whole job, or from --resume-from on
};

Job make_job(const std::string& model_path, const std::string& profile_path, std::size_t from_stroke = 1) {
  Job j;
  j.profile = drivers::load_profile(profile_path);
  drivers::DevicePlan d = drivers::plan_for_device(load_cli_pattern(model_path), j.profile, profile_path);
  j.plan = std::move(d.plan);
  j.time = d.time;
  j.encoded = std::move(d.encoded);
  j.hpgl = j.encoded.bytes;
  if (from_stroke != 1) {
    try {
      j.encoded = encode_job(j.plan, j.profile.dialect, j.profile.tools, from_stroke);
    } catch (const Error& e) {
      throw Error(e.code(), "", "--resume-from", e.message());
    }
  }
  return j;
}

json plan_json(const Job& j, const std::string& model, const std::string& profile_path) {
  const KindStats t = j.plan.total();
  json r = {{"format", "popcut.plan.v1"},
            {"source", model},
            {"profile", profile_path},
            {"device", j.profile.name},
            {"strokes", t.strokes},
            {"pen_lifts", t.pen_lifts},
            {"pen_lift_bound", t.pen_lift_bound},
            {"cut_mm", t.cut_mm},
            {"travel_mm", t.travel_mm},
            {"est_time_s", j.time.total_s},
            {"folds_dropped", t.folds_dropped},
            {"strokes_below_resolution", t.strokes_below_resolution},
            {"hpgl_bytes", j.hpgl.size()},
            {"kinds", json::object()}};
  for (PlanKind k : kAllPlanKinds) {
    json kj = kind_json(j.plan.kinds[index_of(k)], j.time.kind_s[index_of(k)]);
    kj["mode"] = to_string(j.profile.plan.kinds[index_of(k)].mode);
    r["kinds"][to_string(k)] = kj;
  }
  return r;
}

// A one-line bar on a terminal: bytes, strokes, ETA; nothing when stderr is a file or pipe.
class Progress {
 public:
  explicit Progress(bool on) : on_(on && ::isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()) {}
  void operator()(const drivers::SendProgress& p) {
    if (!on_ || p.bytes_total == 0) return;
    const int pct = static_cast<int>(p.bytes_sent * 100 / p.bytes_total);
    const auto now = std::chrono::steady_clock::now();
    if (pct == last_ && now - shown_ < std::chrono::milliseconds(500)) return;
    last_ = pct;
    shown_ = now;
    const int filled = pct * 30 / 100;
    const double elapsed_s = std::chrono::duration<double>(now - start_).count();
    std::string eta = "--";
    if (p.bytes_sent > 0 && elapsed_s > 1) {
      const double left_s = elapsed_s * static_cast<double>(p.bytes_total - p.bytes_sent) / static_cast<double>(p.bytes_sent);
      const long s = static_cast<long>(left_s + 0.5);
      eta = std::to_string(s / 60) + ":" + (s % 60 < 10 ? "0" : "") + std::to_string(s % 60);
    }
    std::cerr << "\rcutting [" << std::string(static_cast<std::size_t>(filled), '#')
              << std::string(static_cast<std::size_t>(30 - filled), '.') << "] " << pct << "% " << p.bytes_sent << "/"
              << p.bytes_total << " bytes, stroke " << p.last_stroke_written << "/" << p.total_strokes << " written, ETA " << eta
              << "   " << std::flush;
  }
  void done() {
    if (on_ && last_ >= 0) std::cerr << "\n";
    last_ = -1;
  }

 private:
  bool on_;
  int last_ = -1;
  std::chrono::steady_clock::time_point start_, shown_{};
};

// Ctrl-C asks the sender to stop safely. A second one never kills popcut between a PD and the
// abort that lifts the knife: it is absorbed, unless popcut has said it is waiting for a device
// that holds the line to take that abort (g_waiting); then it gives up the wait (give_up).
std::atomic<bool> g_cancel{false};
std::atomic<bool> g_waiting{false};
std::atomic<bool> g_give_up{false};

extern "C" void on_interrupt(int) {
  if (!g_cancel.exchange(true)) {
    static const char msg[] = "\npopcut: cancelling: finishing the command in flight, then lifting the knife\n";
    (void)!::write(STDERR_FILENO, msg, sizeof msg - 1);
  } else if (g_waiting.load()) {
    if (!g_give_up.exchange(true)) {
      static const char msg[] = "\npopcut: giving up on the abort: nothing more is sent to the device\n";
      (void)!::write(STDERR_FILENO, msg, sizeof msg - 1);
    }
  } else {
    static const char msg[] = "\npopcut: already cancelling; the knife is being lifted, please wait\n";
    (void)!::write(STDERR_FILENO, msg, sizeof msg - 1);
  }
}

// Installs on_interrupt for SIGINT and SIGTERM for its lifetime.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_cancel = false;
    g_waiting = false;
    g_give_up = false;
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    ::sigaction(SIGINT, &sa, &old_int_);
    ::sigaction(SIGTERM, &sa, &old_term_);
  }
  ~InterruptGuard() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

int run_plan(const CutCommands& s) {
  return run_guarded(s.json_out, [&] {
    if (s.profile_path.empty()) throw Error(ErrorCode::invalid_input, "", "--profile", "plan needs a device profile (configs/devices/*.toml)");
    if (s.out_path == "-" && (s.json_out || s.report_path == "-")) {
      throw Error(ErrorCode::invalid_input, "", "--json", "the job goes to standard output: write the report to a file instead");
    }
    const Job j = make_job(s.model_path, s.profile_path);
    write_cli_output(s.out_path, [&](std::ostream& o) { o << j.hpgl; });
    const json report = plan_json(j, s.model_path, s.profile_path);
    if (!s.report_path.empty()) write_cli_output(s.report_path, [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
    if (s.json_out) {
      print_json_line(report);
    } else {
      const KindStats t = j.plan.total();
      std::cerr << "wrote " << s.out_path << " for " << j.profile.name << ": " << t.strokes << " strokes (bound "
                << t.pen_lift_bound << "), " << static_cast<long>(t.cut_mm) << " mm cut, " << static_cast<long>(t.travel_mm)
                << " mm travel, about " << static_cast<long>(j.time.total_s + 0.5) << " s\n";
    }
    return static_cast<int>(kOk);
  });
}

// The device and profile a cut uses: --device, else the profile's [transport] default; the sim
// profile and `sim` stand in when neither is given.
struct Target {
  std::string device, profile_path, note;
};

Target cut_target(const CutCommands& s) {
  Target t{s.device, s.profile_path, ""};
  // A malformed device string is named first: no profile makes it right.
  if (!t.device.empty()) {
    drivers::DeviceAddress address;
    const drivers::TransportStatus parsed = drivers::parse_device(t.device, address);
    if (!parsed.ok()) throw Error(ErrorCode::invalid_input, "", "--device", parsed.message);
  }
  if (t.profile_path.empty()) {
    if (!t.device.empty() && t.device != "sim") {
      throw Error(ErrorCode::invalid_input, "", "--profile", "--device " + t.device + " needs --profile (configs/devices/*.toml)");
    }
    t.profile_path = find_config_file("devices/sim.toml");
    t.device = "sim";
  }
  return t;
}

int run_cut(const CutCommands& s) {
  return run_guarded(s.json_out, [&] {
    if (s.cut->count("--device") > 0 && s.device.empty()) {
      throw Error(ErrorCode::invalid_input, "", "--device", "is empty: expected sim, file:PATH, serial:/dev/PORT, serial:VID:PID or usb:VID:PID");
    }
    Target target = cut_target(s);
    if (s.resume_from < 1) throw Error(ErrorCode::invalid_input, "", "--resume-from", "strokes are numbered from 1");
    const Job j = make_job(s.model_path, target.profile_path, static_cast<std::size_t>(s.resume_from));
    if (target.device.empty()) {
      target.device = j.profile.transport.uri;
      if (target.device.empty()) {
        throw Error(ErrorCode::invalid_input, target.profile_path, "[transport] default",
                    "the profile names no device: give --device (sim, file:PATH, serial:..., usb:...)");
      }
      target.note = "using the profile's device " + target.device + " ([transport] default in " + target.profile_path + ")";
    }
    drivers::SimFaults faults;
    if (s.stop_answering_after >= 0) faults.stop_answering_after_bytes = static_cast<std::size_t>(s.stop_answering_after);
    if (s.drop_after >= 0) faults.drop_after_bytes = static_cast<std::size_t>(s.drop_after);
    faults.slowdown = s.slowdown;
    drivers::MadeTransport made = drivers::make_transport(target.device, j.profile, faults);
    if (!made.status.ok()) {
      const bool usage = made.status.error == drivers::TransportError::bad_argument;
      throw Error(usage ? ErrorCode::invalid_input : ErrorCode::io, "", usage ? "--device" : "output", made.status.message);
    }
    const bool sim = made.address.kind == drivers::DeviceKind::sim;
    if (!sim && (s.stop_answering_after >= 0 || s.drop_after >= 0 || s.slowdown != 1)) {
      throw Error(ErrorCode::invalid_input, "", "--sim-*", "fault injection applies to --device sim only");
    }
    if (made.address.kind == drivers::DeviceKind::usb && !j.profile.transport.usb_ids.empty()) {
      const std::string id = drivers::usb_id_string(*made.address.vid, *made.address.pid);
      const auto& ids = j.profile.transport.usb_ids;
      if (std::find(ids.begin(), ids.end(), id) == ids.end()) {
        std::string list;
        for (const std::string& k : ids) list += (list.empty() ? "" : ", ") + k;
        throw Error(ErrorCode::invalid_input, target.profile_path, "[transport] usb_ids",
                    "the profile is for USB " + list + " (" + j.profile.name + "), not " + id + ": pick the profile of that device");
      }
    }
    if (!target.note.empty() && !s.json_out) std::cerr << "popcut: " << target.note << "\n";
    std::error_code ec;
    std::filesystem::create_directories(s.out_dir, ec);
    if (ec) throw Error(ErrorCode::io, s.out_dir, "output", "cannot create the directory: " + ec.message());
    const std::filesystem::path dir(s.out_dir);
    write_cli_output((dir / "job.hpgl").string(), [&](std::ostream& o) { o << j.encoded.bytes; });

    drivers::Transport& transport = *made.transport;
    if (const drivers::TransportStatus st = transport.open(); !st.ok()) {
      // The class (docs/transports.md, "Error classes") leads the message, for people and scripts.
      const bool usage = st.error == drivers::TransportError::bad_argument;
      throw Error(usage ? ErrorCode::invalid_input : ErrorCode::io, transport.describe(), usage ? "--device" : "device",
                  std::string(drivers::to_string(st.error)) + ": " + st.message);
    }
    Progress progress(!s.no_progress && !s.json_out);
    drivers::SendOptions opts = drivers::send_options(j.profile);
    // The device's pace: a real device (or a printer node) holds up to a buffer of motion, and one
    // with no handshake is paced by it (the simulator too, on its virtual clock). A plain file
    // needs no waiting.
    const bool plain_file = made.address.kind == drivers::DeviceKind::file && made.address.path.rfind("/dev/", 0) != 0;
    if (!plain_file) opts.motion = drivers::motion_schedule(j.encoded.bytes, j.profile);
    opts.progress = [&](const drivers::SendProgress& p) { progress(p); };
    opts.cancel = &g_cancel;
    opts.give_up = &g_give_up;
    opts.waiting_to_cancel = [&] {
      g_waiting = true;
      progress.done();
      std::cerr << "popcut: the device holds the line (XOFF or CTS): waiting up to " << j.profile.transport.hold_timeout_ms / 1000
                << " s (hold_timeout_ms) for it to take the abort sequence and the knife-up; Ctrl-C (or SIGTERM) again gives up, and the "
                   "device may then cut everything its buffer holds\n";
    };
    drivers::SendResult sent;
    {
      InterruptGuard guard;
      sent = drivers::send_job(transport, j.encoded, opts);
    }
    progress.done();
    transport.close();

    json report = plan_json(j, s.model_path, target.profile_path);
    report["format"] = "popcut.cut.v1";
    report["transport"] = transport.describe();
    report["sent"] = {{"bytes", sent.bytes_sent},
                      {"bytes_total", j.encoded.bytes.size()},
                      {"complete", sent.complete()},
                      {"cancelled", sent.cancelled},
                      {"abort_sent", sent.abort_sent},
                      {"buffer_discarded", sent.buffer_discarded},
                      {"error", sent.status.ok() ? "" : std::string(drivers::to_string(sent.status.error))},
                      {"message", sent.status.message},
                      {"first_stroke", sent.first_stroke},
                      {"bytes_received", sent.bytes_received},
                      {"received_counted_by", sent.received_counted_by},
                      {"last_stroke_sent", sent.last_stroke_sent},
                      {"last_stroke_written", sent.last_stroke_written},
                      {"last_stroke_executed", sent.last_stroke_executed ? json(*sent.last_stroke_executed) : json(nullptr)},
                      {"total_strokes", sent.total_strokes},
                      {"buffered_bytes", sent.buffered_bytes},
                      {"buffer_known", sent.buffer_known},
                      {"buffered_strokes", sent.buffered_bytes == 0 ? json(nullptr)
                                                                    : json::array({sent.buffered_first_stroke, sent.buffered_last_stroke})},
                      {"status_queries", sent.status_queries},
                      {"drained_by", sent.drained_by},
                      {"holds", sent.holds},
                      {"buffer_queries", sent.buffer_queries},
                      {"device_io_error", sent.device_io_error == 0 ? json(nullptr) : json(sent.device_io_error)},
                      {"busy_for_s", sent.busy_for_s}};
    // Knife-down length of the strokes this run sends (all of them unless --resume-from).
    double run_cut_mm = 0;
    for (std::size_t i = j.encoded.first_stroke - 1; i < j.plan.strokes.size(); ++i) run_cut_mm += path_length_mm(j.plan.strokes[i].points);
    report["this_run"] = {{"first_stroke", j.encoded.first_stroke}, {"last_stroke", sent.total_strokes}, {"cut_mm", run_cut_mm}};
    bool match = true;
    const std::shared_ptr<drivers::SimCutter>& cutter = made.sim;
    if (cutter) {
      // A cutter whose line drops goes on cutting what it holds, as `popcut sim-plotter` does, so
      // the report shows what a real one would have cut (a frozen one cuts nothing more).
      const bool ran_out = cutter->run_to_end();
      const bool finished = sent.status.ok() && ran_out;
      const drivers::SimReport& r = cutter->report();
      // From --resume-from N the simulator should have cut exactly strokes N.. of the plan.
      std::vector<PlotterPath> planned = plan_in_plotter_units(j.plan, j.profile.dialect);
      planned.erase(planned.begin(), planned.begin() + static_cast<std::ptrdiff_t>(std::min(planned.size(), j.encoded.first_stroke - 1)));
      const std::optional<std::size_t> diff = drivers::first_difference(planned, cutter->strokes());
      match = finished && !diff && r.overflow_bytes == 0 && !r.outside_area;
      report["sim"] = {{"strokes", cutter->strokes().size()},
                       {"knife_downs", r.knife_downs},
                       {"cut_mm", r.knife_down_mm},
                       {"travel_mm", r.knife_up_mm},
                       {"motion_time_s", r.motion_time_s},
                       {"clock_s", r.clock_s},
                       {"bytes_received", r.bytes_received},
                       {"commands", r.commands},
                       {"max_buffer_used", r.max_buffer_used},
                       {"overflow_bytes", r.overflow_bytes},
                       {"xoff_sent", r.xoff_sent},
                       {"outside_area", r.outside_area},
                       {"unknown_commands", sim_issues_json(r.unknown)},
                       {"errors", sim_issues_json(r.errors)},
                       {"strokes_match_plan", !diff},
                       {"first_mismatch", diff ? json(*diff + j.encoded.first_stroke) : json(nullptr)}};
      write_cli_output((dir / "cut.svg").string(), [&](std::ostream& o) { cutter->write_svg(o); });
      if (r.overflow_bytes > 0 && sent.complete()) {
        // Every byte went out, but the device lost some: for a script reading `sent`, the job
        // did not get through (a real device tells only through error_query).
        report["sent"]["complete"] = false;
        report["sent"]["error"] = std::string(drivers::to_string(drivers::TransportError::io));
        report["sent"]["message"] = "the simulated cutter lost " + std::to_string(r.overflow_bytes) + " bytes to a full buffer: what it cut is not the job";
      }
    }
    write_cli_output((dir / "report.json").string(), [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
    if (s.json_out) print_json_line(report);
    const std::string where = counts_text(sent);
    const std::string resume = resume_advice(sent);
    if (sent.cancelled && sent.bytes_sent == 0) {
      std::cerr << "popcut: cancelled on " << transport.describe() << " before any byte of the job was sent: nothing was cut\n";
      return static_cast<int>(kCancelled);
    }
    if (sent.cancelled) {
      const std::string left = still_buffered_text(sent);
      std::cerr << "popcut: cancelled on " << transport.describe() << ": "
                << (sent.abort_sent ? (j.profile.transport.abort.empty() ? "lifted the knife (the profile names no abort sequence)"
                                                                       : "sent the abort sequence and lifted the knife")
                                    : "could NOT send the abort sequence: " + sent.status.message)
                << (sent.buffer_discarded ? "; the device discarded its buffer on it and cuts nothing more"
                                          : "; the device may still cut " + left + " from its buffer")
                << (sent.buffer_discarded || sent.buffered_bytes == 0 || !sent.abort_sent || sent.buffer_known || !j.profile.transport.abort_discards_buffer
                        ? ""  // known, or an abort that keeps the buffer: the figure stands
                        : " unless it honours the abort sequence")
                << "; " << where
                << resume << "\n";
      return static_cast<int>(kCancelled);
    }
    if (!sent.status.ok() && sent.device_io_error != 0) {
      // Stroke numbers mean nothing here: the device cut something else than the job.
      std::cerr << "popcut: error: the job did not reach the cutter intact (" << transport.describe() << "): " << sent.status.message
                << resume << "\n";
      return static_cast<int>(kCannotWrite);
    }
    if (!sent.status.ok()) {
      std::cerr << "popcut: error: the job did not reach the cutter (" << transport.describe() << "): " << sent.status.message
                << "; " << sent.bytes_sent << " of " << j.encoded.bytes.size() << " job bytes written; " << where << resume << "\n";
      return static_cast<int>(kCannotWrite);
    }
    if (cutter && !match && cutter->report().overflow_bytes > 0 && j.profile.transport.flow == drivers::FlowControl::none &&
        s.slowdown > 1 + j.profile.transport.pace_margin_percent / 100.0) {
      // The fault the simulator was asked for (--sim-slowdown past what time pacing allows for),
      // not popcut's: what a real device would have done, told as such. Any other mismatch is a
      // bug (below): the simulator follows every other pacing exactly.
      std::cerr << "popcut: error: the simulated cutter lost " << cutter->report().overflow_bytes
                << " bytes to a full buffer, so it did not cut the job: popcut paced it by time (flow_control \"none\"), and --sim-slowdown "
                << format_decimal(s.slowdown, 3) << " is slower than the profile allows for with pace_margin_percent ("
                << j.profile.transport.pace_margin_percent << " %) (see " << (dir / "report.json").string() << ")\n";
      return static_cast<int>(kCannotWrite);
    }
    if (cutter && !match) {
      std::cerr << "popcut: internal error: the simulated cutter did not cut what was planned (see " << (dir / "report.json").string() << ")\n";
      return static_cast<int>(kInternal);
    }
    if (!s.json_out) {
      const KindStats t = j.plan.total();
      if (j.encoded.first_stroke > 1) {
        // A resumed run says what this run cut, not the whole job's figures.
        std::cerr << "cut on " << transport.describe() << " (" << j.profile.name << "): strokes " << j.encoded.first_stroke << " to "
                  << sent.total_strokes << " of " << sent.total_strokes << ", " << static_cast<long>(run_cut_mm) << " mm cut";
      } else {
        std::cerr << "cut on " << transport.describe() << " (" << j.profile.name << "): " << t.strokes << " strokes, "
                  << static_cast<long>(t.cut_mm) << " mm cut, " << static_cast<long>(t.travel_mm) << " mm travel";
      }
      if (cutter) std::cerr << ", " << static_cast<long>(cutter->report().motion_time_s + 0.5) << " s of motion";
      std::cerr << "; wrote " << (dir / "job.hpgl").string() << (cutter ? ", cut.svg" : "") << " and report.json\n";
    }
    return static_cast<int>(kOk);
  });
}

}  // namespace

void add_cut_commands(CLI::App& app, CutCommands& s) {
  s.plan = app.add_subcommand("plan", "Plan the knife's strokes for a device and write the HP-GL job (and a report).");
  s.plan->add_option("MODEL", s.model_path, "Model file (voxel or face model), or - for standard input")->required();
  s.plan->add_option("--profile", s.profile_path, "Device profile, e.g. configs/devices/generic-hpgl.toml")->required();
  s.plan->add_option("-o,--output", s.out_path, "Where to write the HP-GL job, or - for standard output")->required();
  s.plan->add_option("--report", s.report_path, "Also write the plan's figures as JSON (popcut.plan.v1)");
  s.plan->add_flag("--json", s.json_out, "Print the report as JSON on standard output");

  s.cut = app.add_subcommand("cut", "Plan, encode and send a job to a cutter: the simulated one (sim) or a file/device node.\n"
                                    "Writes DIR/job.hpgl (the job this run sends, whole; report.json says how much went out), DIR/report.json and, on sim, DIR/cut.svg.\n"
                                    "Exit 0: the device has the whole job (and said so, where it answers status queries).\n"
                                    "Exit 3: the job did not get through (disconnect, timeout, a device that does not answer): the\n"
                                    "message names the last stroke the device is known to have executed (E), the last it certainly\n"
                                    "received (M) and the last written (N): --resume-from M+1 finishes the job if the device kept its\n"
                                    "buffer and goes on cutting (strokes M+1..N may then be cut twice), --resume-from E+1 if it was\n"
                                    "reset or power-cycled (strokes E+1..M may have been cut already).\n"
                                    "Exit 130: cancelled by Ctrl-C or SIGTERM; the knife is lifted and the message says how much the\n"
                                    "device may still cut from its buffer (bytes and strokes). If the device holds the line, popcut\n"
                                    "says it is waiting for it to take the abort; a second Ctrl-C (or SIGTERM) gives up the wait.");
  s.cut->add_option("MODEL", s.model_path, "Model file (voxel or face model), or - for standard input")->required();
  s.cut->add_option("--device", s.device,
                    "sim, file:PATH (a .hpgl file or a printer-port node), serial:/dev/PORT, serial:VID:PID[:SERIAL] or\n"
                    "usb:VID:PID[:SERIAL]; default: the profile's [transport] default, or sim without --profile");
  s.cut->add_option("--profile", s.profile_path, "Device profile (default: configs/devices/sim.toml on --device sim)");
  s.cut->add_option("--resume-from", s.resume_from,
                    "Send strokes N.. only (numbered from 1 as progress and errors count them), starting with the knife up");
  s.cut->add_option("--out", s.out_dir, "Directory for job.hpgl, cut.svg and report.json")->required();
  s.cut->add_flag("--json", s.json_out, "Print the report as JSON on standard output");
  s.cut->add_flag("--no-progress", s.no_progress, "No progress bar, even on a terminal");
  s.cut->add_option("--sim-stop-after", s.stop_answering_after, "Fault: the simulator stops answering after N bytes")
      ->check(finite_range(0, 1e12));
  s.cut->add_option("--sim-drop-after", s.drop_after, "Fault: the simulator drops the connection after N bytes")
      ->check(finite_range(0, 1e12));
  s.cut->add_option("--sim-slowdown", s.slowdown, "Fault: the simulator moves this many times slower")->check(finite_range(1.0, 1000.0));
}

std::optional<int> run_cut_commands(const CutCommands& s) {
  if (s.plan && *s.plan) return run_plan(s);
  if (s.cut && *s.cut) return run_cut(s);
  return std::nullopt;
}

}  // namespace popcut::cli
