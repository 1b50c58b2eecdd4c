// popcut plan / cut: pattern → stroke plan → HP-GL for a device profile → a transport (sim, file, serial, usb).
#include "cli/cut.h"
#include "cli/cut_send.h"
#include "report_json.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>

#include "cli/checks.h"
#include "cli/common.h"
#include "cli/sim_plotter.h"
#include "config_dir.h"
#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/device.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/send_report.h"
#include "popcut/text.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/plan/plan.h"

namespace popcut::cli {
namespace {

using drivers::DeviceProfile;
using nlohmann::json;

json kind_json(const KindStats& k, double est_s) {
  return {{"strokes", k.strokes},
          {"pen_lifts", k.pen_lifts},
          {"pen_lift_bound", k.pen_lift_bound},
          {"cut_mm", k.cut_mm},
          {"travel_mm", k.travel_mm},
          {"est_time_s", est_s},
          {"folds_dropped", k.folds_dropped},
          {"strokes_below_resolution", k.strokes_below_resolution},
          {"precuts", k.precuts}};
}

struct Job {
  DeviceProfile profile;
  StrokePlan plan;
  TimeEstimate time;
  std::string hpgl;    // the whole job
  EncodedJob encoded;  // what is sent: the whole job, or from --resume-from on
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
      j.encoded = drivers::encode_for_device(j.plan, j.profile, from_stroke);
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

int run_plan(const CutCommands& s) {
  return run_guarded(s.json_out, [&] {
    if (s.profile_path.empty())
      throw Error(ErrorCode::invalid_input, "", "--profile", "plan needs a device profile (configs/devices/*.toml)");
    if (s.out_path == "-" && (s.json_out || s.report_path == "-")) {
      throw Error(ErrorCode::invalid_input, "", "--json",
                  "the job goes to standard output: write the report to a file instead");
    }
    const Job j = make_job(s.model_path, s.profile_path);
    write_cli_output(s.out_path, [&](std::ostream& o) { o << j.hpgl; });
    const json report = plan_json(j, s.model_path, s.profile_path);
    if (!s.report_path.empty())
      write_cli_output(s.report_path, [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
    if (s.json_out) {
      print_json_line(report);
    } else {
      const KindStats t = j.plan.total();
      std::cerr << "wrote " << s.out_path << " for " << j.profile.name << ": " << t.strokes << " strokes (bound "
                << t.pen_lift_bound << "), " << static_cast<long>(t.cut_mm) << " mm cut, "
                << static_cast<long>(t.travel_mm) << " mm travel, about " << static_cast<long>(j.time.total_s + 0.5)
                << " s\n";
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
  if (s.cut->count("--device") > 0 && s.device.empty()) {
    throw Error(ErrorCode::invalid_input, "", "--device",
                "is empty: expected sim, file:PATH, serial:/dev/PORT, serial:VID:PID or usb:VID:PID");
  }
  Target t{s.device, s.profile_path, ""};
  // A malformed device string is named first: no profile makes it right.
  if (!t.device.empty()) {
    drivers::DeviceAddress address;
    const drivers::TransportStatus parsed = drivers::parse_device(t.device, address);
    if (!parsed.ok()) throw Error(ErrorCode::invalid_input, "", "--device", parsed.message);
  }
  if (t.profile_path.empty()) {
    if (!t.device.empty() && t.device != "sim") {
      throw Error(ErrorCode::invalid_input, "", "--profile",
                  "--device " + t.device + " needs --profile (configs/devices/*.toml)");
    }
    t.profile_path = find_config_file("devices/sim.toml");
    t.device = "sim";
  }
  return t;
}

// No --device and no --profile's sim: the profile's [transport] default, said so on stderr.
void use_profile_device(Target& t, const DeviceProfile& profile) {
  if (!t.device.empty()) return;
  t.device = profile.transport.uri;
  if (t.device.empty()) {
    throw Error(ErrorCode::invalid_input, t.profile_path, "[transport] default",
                "the profile names no device: give --device (sim, file:PATH, serial:..., usb:...)");
  }
  t.note = "using the profile's device " + t.device + " ([transport] default in " + t.profile_path + ")";
}

drivers::CutSessionOptions session_options(const CutCommands& s) {
  drivers::CutSessionOptions o;
  if (s.stop_answering_after >= 0)
    o.sim_faults.stop_answering_after_bytes = static_cast<std::size_t>(s.stop_answering_after);
  if (s.drop_after >= 0) o.sim_faults.drop_after_bytes = static_cast<std::size_t>(s.drop_after);
  if (s.tray_empty_after >= 0) o.sim_faults.tray_empty_after_bytes = static_cast<std::size_t>(s.tray_empty_after);
  if (s.pause_after >= 0) o.sim_faults.pause_after_bytes = static_cast<std::size_t>(s.pause_after);
  o.sim_faults.slowdown = s.slowdown;
  return o;
}

// The device string made a transport, the --sim-* faults are for the simulator, and a USB
// device is the one the profile is for.
void check_device(const CutCommands& s, const drivers::CutSession& session, const DeviceProfile& profile,
                  const Target& target) {
  if (const drivers::TransportStatus& st = session.made(); !st.ok()) {
    if (st.error == drivers::TransportError::bad_argument)
      throw Error(ErrorCode::invalid_input, "", "--device", st.message);
    throw CliError(kCannotWrite, ErrorCode::io, "", "output", st.message);
  }
  const drivers::DeviceAddress& address = session.address();
  if (address.kind != drivers::DeviceKind::sim && (s.stop_answering_after >= 0 || s.drop_after >= 0 ||
                                                   s.tray_empty_after >= 0 || s.pause_after >= 0 || s.slowdown != 1)) {
    throw Error(ErrorCode::invalid_input, "", "--sim-*", "fault injection applies to --device sim only");
  }
  if (address.kind == drivers::DeviceKind::usb && !profile.transport.usb_ids.empty()) {
    const std::string id = drivers::usb_id_string(*address.vid, *address.pid);
    const auto& ids = profile.transport.usb_ids;
    if (std::find(ids.begin(), ids.end(), id) == ids.end()) {
      std::string list;
      for (const std::string& k : ids) list += (list.empty() ? "" : ", ") + k;
      throw Error(ErrorCode::invalid_input, target.profile_path, "[transport] usb_ids",
                  "the profile is for USB " + list + " (" + profile.name + "), not " + id +
                      ": pick the profile of that device");
    }
  }
}

// Creates --out and writes the job this run sends into it; returns the directory.
std::filesystem::path write_job_file(const std::string& out_dir, const EncodedJob& encoded) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec)
    throw CliError(kCannotWrite, ErrorCode::io, out_dir, "output", "cannot create the directory: " + ec.message());
  const std::filesystem::path dir(out_dir);
  write_cli_output((dir / "job.hpgl").string(), [&](std::ostream& o) { o << encoded.bytes; });
  return dir;
}

void open_device(drivers::CutSession& session) {
  if (const drivers::TransportStatus st = session.open(); !st.ok()) {
    // The class (docs/transports.md, "Error classes") leads the message, for people and scripts.
    const std::string message = std::string(drivers::to_string(st.error)) + ": " + st.message;
    if (st.error == drivers::TransportError::bad_argument) {
      throw Error(ErrorCode::invalid_input, session.describe(), "--device", message);
    }
    throw CliError(kCannotWrite, ErrorCode::io, session.describe(), "device", message);
  }
}

// popcut.cut.v1's `sim` object: what the simulated cutter did, held against the plan.
json sim_json(const drivers::SimCutter& cutter, const drivers::SimCheck& check, std::size_t first_stroke) {
  const drivers::SimReport& r = cutter.report();
  return {{"strokes", cutter.strokes().size()},
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
          {"strokes_match_plan", !check.first_mismatch},
          {"first_mismatch", check.first_mismatch ? json(*check.first_mismatch + first_stroke) : json(nullptr)}};
}

// Knife-down length of the strokes this run sends (all of them unless --resume-from).
double run_cut_mm(const Job& j) {
  double mm = 0;
  for (std::size_t i = j.encoded.first_stroke - 1; i < j.plan.strokes.size(); ++i)
    mm += path_length_mm(j.plan.strokes[i].points);
  return mm;
}

json cut_report(const CutCommands& s, const Target& target, const Job& j, const drivers::CutSession& session,
                const drivers::SendResult& sent, const std::optional<drivers::SimCheck>& check) {
  json report = plan_json(j, s.model_path, target.profile_path);
  report["format"] = "popcut.cut.v1";
  report["transport"] = session.describe();
  report["sent"] = drivers::send_result_json(sent, j.encoded.bytes.size());
  report["this_run"] = {
      {"first_stroke", j.encoded.first_stroke}, {"last_stroke", sent.total_strokes}, {"cut_mm", run_cut_mm(j)}};
  if (const drivers::SimCutter* cutter = session.simulator(); cutter && check) {
    report["sim"] = sim_json(*cutter, *check, j.encoded.first_stroke);
    if (check->overflow_bytes > 0 && sent.complete()) {
      // Every byte went out, but the device lost some: for a script reading `sent`, the job
      // did not get through (a real device tells only through error_query).
      report["sent"]["complete"] = false;
      report["sent"]["error"] = std::string(drivers::to_string(drivers::TransportError::io));
      report["sent"]["message"] = "the simulated cutter lost " + std::to_string(check->overflow_bytes) +
                                  " bytes to a full buffer: what it cut is not the job";
    }
  }
  return report;
}

// A job that did not get through, or was cancelled: the message and exit code; nullopt when it got through.
std::optional<int> stopped_exit(const drivers::SendResult& sent, const Job& j, const std::string& device) {
  if (sent.cancelled && sent.bytes_sent == 0) {
    std::cerr << "popcut: cancelled on " << device << " before any byte of the job was sent: nothing was cut\n";
    return static_cast<int>(kCancelled);
  }
  if (sent.cancelled) {
    std::cerr << "popcut: cancelled on " << device << ": " << drivers::cancel_text(sent, j.profile.transport) << "; "
              << drivers::counts_text(sent) << drivers::resume_advice(sent) << "\n";
    return static_cast<int>(kCancelled);
  }
  if (sent.device_stop != drivers::DeviceStop::none) {
    // The device said it cannot go on: its reason, what popcut did about it and where to resume.
    std::cerr << "popcut: error: the device stopped the job (" << device << "): " << sent.status.message;
    if (sent.bytes_sent > 0) std::cerr << "; " << drivers::counts_text(sent);
    std::cerr << drivers::resume_advice(sent) << "\n";
    return static_cast<int>(kCannotWrite);
  }
  if (!sent.status.ok() && sent.device_io_error != 0) {
    // Stroke numbers mean nothing here: the device cut something else than the job.
    std::cerr << "popcut: error: the job did not reach the cutter intact (" << device << "): " << sent.status.message
              << drivers::resume_advice(sent) << "\n";
    return static_cast<int>(kCannotWrite);
  }
  if (!sent.status.ok()) {
    std::cerr << "popcut: error: the job did not reach the cutter (" << device << "): " << sent.status.message << "; "
              << sent.bytes_sent << " of " << j.encoded.bytes.size() << " job bytes written; "
              << drivers::counts_text(sent) << drivers::resume_advice(sent) << "\n";
    return static_cast<int>(kCannotWrite);
  }
  return std::nullopt;
}

// A complete job on the simulator that did not cut the plan: the message and exit code.
// popcut cut accepts command_errors (the strokes are the plan's; report.json lists the errors),
// where popcutd's sim_match asks for `exact`.
std::optional<int> sim_exit(const CutCommands& s, const Job& j, const drivers::SimCheck& check,
                            const std::filesystem::path& dir) {
  const drivers::SimVerdict verdict = check.verdict();
  if (verdict == drivers::SimVerdict::exact || verdict == drivers::SimVerdict::command_errors) return std::nullopt;
  const drivers::TransportDefaults& tp = j.profile.transport;
  const bool by_model = tp.flow == drivers::FlowControl::none || tp.flow == drivers::FlowControl::status;
  if (check.overflow_bytes > 0 && by_model && s.slowdown > 1 + tp.pace_margin_percent / 100.0) {
    // The fault the simulator was asked for (--sim-slowdown past what pacing by the motion model
    // allows for), not popcut's: what a real device would have done, told as such. Any other
    // mismatch is a bug (below): the simulator follows every other pacing exactly.
    std::cerr << "popcut: error: the simulated cutter lost " << check.overflow_bytes
              << " bytes to a full buffer, so it did not cut the job: popcut paced it by "
              << (tp.flow == drivers::FlowControl::status ? "the motion model and its status answers (flow_control "
                                                            "\"status\")"
                                                          : "time (flow_control \"none\")")
              << ", and --sim-slowdown " << format_decimal(s.slowdown, 3)
              << " is slower than the profile allows for with pace_margin_percent (" << tp.pace_margin_percent
              << " %) (see " << (dir / "report.json").string() << ")\n";
    return static_cast<int>(kCannotWrite);
  }
  std::cerr << "popcut: internal error: the simulated cutter did not cut what was planned (see "
            << (dir / "report.json").string() << ")\n";
  return static_cast<int>(kInternal);
}

void print_cut_summary(const Job& j, const drivers::CutSession& session, const drivers::SendResult& sent,
                       const std::filesystem::path& dir) {
  const drivers::SimCutter* cutter = session.simulator();
  if (j.encoded.first_stroke > 1) {
    // A resumed run says what this run cut, not the whole job's figures.
    std::cerr << "cut on " << session.describe() << " (" << j.profile.name << "): strokes " << j.encoded.first_stroke
              << " to " << sent.total_strokes << " of " << sent.total_strokes << ", "
              << static_cast<long>(run_cut_mm(j)) << " mm cut";
  } else {
    const KindStats t = j.plan.total();
    std::cerr << "cut on " << session.describe() << " (" << j.profile.name << "): " << t.strokes << " strokes, "
              << static_cast<long>(t.cut_mm) << " mm cut, " << static_cast<long>(t.travel_mm) << " mm travel";
  }
  if (cutter) std::cerr << ", " << static_cast<long>(cutter->report().motion_time_s + 0.5) << " s of motion";
  std::cerr << "; wrote " << (dir / "job.hpgl").string() << (cutter ? ", cut.svg" : "") << " and report.json\n";
}

int run_cut(const CutCommands& s) {
  return run_guarded(s.json_out, [&] {
    Target target = cut_target(s);
    if (s.resume_from < 1) throw Error(ErrorCode::invalid_input, "", "--resume-from", "strokes are numbered from 1");
    const Job j = make_job(s.model_path, target.profile_path, static_cast<std::size_t>(s.resume_from));
    use_profile_device(target, j.profile);
    drivers::CutSession session(target.device, j.profile, session_options(s));
    check_device(s, session, j.profile, target);
    if (!target.note.empty() && !s.json_out) std::cerr << "popcut: " << target.note << "\n";
    const std::filesystem::path dir = write_job_file(s.out_dir, j.encoded);
    open_device(session);
    const drivers::SendResult sent = send_with_interrupts(session, j.encoded, j.profile, !s.no_progress && !s.json_out);
    // From --resume-from N the simulator should have cut exactly strokes N.. of the plan.
    const std::optional<drivers::SimCheck> check = session.finish(
        sent, session.simulator() ? drivers::planned_paths(j.plan, j.profile.dialect, j.encoded.first_stroke)
                                  : std::vector<PlotterPath>{});
    // A cutter whose line drops goes on cutting what it holds, as `popcut sim-plotter` does, so
    // cut.svg shows what a real one would have cut (a frozen one cuts nothing more).
    if (const drivers::SimCutter* cutter = session.simulator()) {
      write_cli_output((dir / "cut.svg").string(), [&](std::ostream& o) { cutter->write_svg(o); });
    }
    const json report = cut_report(s, target, j, session, sent, check);
    write_cli_output((dir / "report.json").string(),
                     [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
    if (s.json_out) print_json_line(report);
    if (const std::optional<int> code = stopped_exit(sent, j, session.describe())) return *code;
    if (check) {
      if (const std::optional<int> code = sim_exit(s, j, *check, dir)) return *code;
    }
    if (!s.json_out) print_cut_summary(j, session, sent, dir);
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

  s.cut = app.add_subcommand(
      "cut",
      "Plan, encode and send a job to a cutter: the simulated one (sim) or a file/device node.\n"
      "Writes DIR/job.hpgl (the job this run sends, whole; report.json says how much went out), DIR/report.json and, "
      "on sim, DIR/cut.svg.\n"
      "Exit 0: the device has the whole job (and said so, where it answers status queries).\n"
      "Exit 3: the job did not get through (disconnect, timeout, a device that does not answer, or one\n"
      "that says it has no sheet loaded or is paused): the\n"
      "message names the last stroke the device is known to have executed (E), the last it certainly\n"
      "received (M) and the last written (N): --resume-from M+1 finishes the job if the device kept its\n"
      "buffer and goes on cutting (strokes M+1..N may then be cut twice), --resume-from E+1 if it was\n"
      "reset or power-cycled (strokes E+1..M may have been cut already).\n"
      "Exit 130: cancelled by Ctrl-C or SIGTERM; the knife is lifted and the message says how much the\n"
      "device may still cut from its buffer (bytes and strokes). If the device holds the line, popcut\n"
      "says it is waiting for it to take the abort; a second Ctrl-C (or SIGTERM) gives up the wait.");
  s.cut->add_option("MODEL", s.model_path, "Model file (voxel or face model), or - for standard input")->required();
  s.cut->add_option(
      "--device", s.device,
      "sim, file:PATH (a .hpgl file or a printer-port node), serial:/dev/PORT, serial:VID:PID[:SERIAL] or\n"
      "usb:VID:PID[:SERIAL]; default: the profile's [transport] default, or sim without --profile");
  s.cut->add_option("--profile", s.profile_path, "Device profile (default: configs/devices/sim.toml on --device sim)");
  s.cut->add_option(
      "--resume-from", s.resume_from,
      "Send strokes N.. only (numbered from 1 as progress and errors count them), starting with the knife up");
  s.cut->add_option("--out", s.out_dir, "Directory for job.hpgl, cut.svg and report.json")->required();
  s.cut->add_flag("--json", s.json_out, "Print the report as JSON on standard output");
  s.cut->add_flag("--no-progress", s.no_progress, "No progress bar, even on a terminal");
  s.cut->add_option("--sim-stop-after", s.stop_answering_after, "Fault: the simulator stops answering after N bytes")
      ->check(finite_range(0, 1e12));
  s.cut->add_option("--sim-drop-after", s.drop_after, "Fault: the simulator drops the connection after N bytes")
      ->check(finite_range(0, 1e12));
  s.cut
      ->add_option("--sim-tray-empty-after", s.tray_empty_after,
                   "Fault: the simulator has no sheet loaded from the start (0) or after N bytes (it ran out)")
      ->check(finite_range(0, 1e12));
  s.cut->add_option("--sim-pause-after", s.pause_after, "Fault: the simulator's pause key is pressed after N bytes")
      ->check(finite_range(0, 1e12));
  s.cut->add_option("--sim-slowdown", s.slowdown, "Fault: the simulator moves this many times slower")
      ->check(finite_range(1.0, 1000.0));
}

std::optional<int> run_cut_commands(const CutCommands& s) {
  if (s.plan && *s.plan) return run_plan(s);
  if (s.cut && *s.cut) return run_cut(s);
  return std::nullopt;
}

}  // namespace popcut::cli
