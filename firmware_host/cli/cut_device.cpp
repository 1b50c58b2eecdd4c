// What every command that cuts shares: the device and profile chosen, its checks, the simulator's faults, send exits.
#include "cli/cut_device.h"

#include <algorithm>
#include <chrono>
#include <iostream>

#include "cli/checks.h"
#include "cli/common.h"
#include "cli/cut_send.h"
#include "cli/sim_plotter.h"
#include "config_dir.h"
#include "popcut/drivers/device.h"
#include "popcut/drivers/material.h"
#include "popcut/drivers/send_report.h"
#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut::cli {

using drivers::DeviceProfile;
using nlohmann::json;

const char* const kMaterialHelp =
    "Material (configs/materials/NAME.toml, e.g. card-220): its forces, speeds and passes for the profile's\n"
    "device family replace the profile's own";

DeviceProfile load_cli_profile(const std::string& profile_path, const std::string& material,
                               std::string* material_source) {
  DeviceProfile profile = drivers::load_profile(profile_path);
  if (material.empty()) return profile;
  drivers::Material m;
  try {
    m = drivers::find_material(find_config_dir("materials"), material);
  } catch (const Error& e) {
    if (e.location() != "material") throw;  // the file itself is wrong: its own message
    throw Error(e.code(), "", "--material", e.message());
  }
  drivers::apply_material(profile, m);
  if (material_source) *material_source = m.source;
  return profile;
}

void add_sim_fault_options(CLI::App& cmd, SimFaultArgs& f) {
  cmd.add_option("--sim-stop-after", f.stop_answering_after, "Fault: the simulator stops answering after N bytes")
      ->check(finite_range(0, 1e12));
  cmd.add_option("--sim-drop-after", f.drop_after, "Fault: the simulator drops the connection after N bytes")
      ->check(finite_range(0, 1e12));
  cmd.add_option("--sim-tray-empty-after", f.tray_empty_after,
                 "Fault: the simulator has no sheet loaded from the start (0) or after N bytes (it ran out)")
      ->check(finite_range(0, 1e12));
  cmd.add_option("--sim-pause-after", f.pause_after, "Fault: the simulator's pause key is pressed after N bytes")
      ->check(finite_range(0, 1e12));
  cmd.add_option("--sim-slowdown", f.slowdown, "Fault: the simulator moves this many times slower")
      ->check(finite_range(1.0, 1000.0));
}

Target cut_target(const std::string& device, bool device_given, const std::string& profile_path) {
  if (device_given && device.empty()) {
    throw Error(ErrorCode::invalid_input, "", "--device",
                "is empty: expected sim, file:PATH, serial:/dev/PORT, serial:VID:PID or usb:VID:PID");
  }
  Target t{device, profile_path, ""};
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

void use_profile_device(Target& t, const DeviceProfile& profile) {
  if (!t.device.empty()) return;
  t.device = profile.transport.uri;
  if (t.device.empty()) {
    throw Error(ErrorCode::invalid_input, t.profile_path, "[transport] default",
                "the profile names no device: give --device (sim, file:PATH, serial:..., usb:...)");
  }
  t.note = "using the profile's device " + t.device + " ([transport] default in " + t.profile_path + ")";
}

drivers::CutSessionOptions session_options(const SimFaultArgs& f) {
  drivers::CutSessionOptions o;
  if (f.stop_answering_after >= 0)
    o.sim_faults.stop_answering_after_bytes = static_cast<std::size_t>(f.stop_answering_after);
  if (f.drop_after >= 0) o.sim_faults.drop_after_bytes = static_cast<std::size_t>(f.drop_after);
  if (f.tray_empty_after >= 0) o.sim_faults.tray_empty_after_bytes = static_cast<std::size_t>(f.tray_empty_after);
  if (f.pause_after >= 0) o.sim_faults.pause_after_bytes = static_cast<std::size_t>(f.pause_after);
  o.sim_faults.slowdown = f.slowdown;
  return o;
}

void check_device(const SimFaultArgs& f, const drivers::CutSession& session, const DeviceProfile& profile,
                  const Target& target) {
  if (const drivers::TransportStatus& st = session.made(); !st.ok()) {
    if (st.error == drivers::TransportError::bad_argument)
      throw Error(ErrorCode::invalid_input, "", "--device", st.message);
    throw CliError(kCannotWrite, ErrorCode::io, "", "output", st.message);
  }
  const drivers::DeviceAddress& address = session.address();
  if (address.kind != drivers::DeviceKind::sim && f.any()) {
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

std::optional<int> stopped_exit(const drivers::SendResult& sent, const DeviceProfile& profile, std::size_t job_bytes,
                                const std::string& device) {
  if (sent.cancelled && sent.bytes_sent == 0) {
    std::cerr << "popcut: cancelled on " << device << " before any byte of the job was sent: nothing was cut\n";
    return static_cast<int>(kCancelled);
  }
  if (sent.cancelled) {
    std::cerr << "popcut: cancelled on " << device << ": " << drivers::cancel_text(sent, profile.transport) << "; "
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
              << sent.bytes_sent << " of " << job_bytes << " job bytes written; " << drivers::counts_text(sent)
              << drivers::resume_advice(sent) << "\n";
    return static_cast<int>(kCannotWrite);
  }
  return std::nullopt;
}

std::optional<int> sim_exit(double slowdown, const DeviceProfile& profile, const drivers::SimCheck& check,
                            const std::string& report) {
  const drivers::SimVerdict verdict = check.verdict();
  if (verdict == drivers::SimVerdict::exact || verdict == drivers::SimVerdict::command_errors) return std::nullopt;
  const drivers::TransportDefaults& tp = profile.transport;
  const double allowed = (1 + tp.pace_margin_in_use() / 100.0) * profile.calibration.time_factor;
  const bool by_model = tp.flow == drivers::FlowControl::none || tp.flow == drivers::FlowControl::status;
  if (check.overflow_bytes > 0 && by_model && slowdown > allowed) {
    // The fault the simulator was asked for (--sim-slowdown past what pacing by the motion model
    // allows for), not popcut's: what a real device would have done, told as such. Any other
    // mismatch is a bug (below): the simulator follows every other pacing exactly.
    std::cerr << "popcut: error: the simulated cutter lost " << check.overflow_bytes
              << " bytes to a full buffer, so it did not cut the job: popcut paced it by "
              << (tp.flow == drivers::FlowControl::status
                      ? "the motion model and its status answers (flow_control \"status\")"
                      : "time (flow_control \"none\")")
              << ", and --sim-slowdown " << format_decimal(slowdown, 3)
              << " is slower than the profile allows for with a pace margin of " << tp.pace_margin_in_use() << " % ("
              << drivers::pace_margin_from(profile) << ") (see " << report << ")\n";
    return static_cast<int>(kCannotWrite);
  }
  std::cerr << "popcut: internal error: the simulated cutter did not cut what was planned (see " << report << ")\n";
  return static_cast<int>(kInternal);
}

std::filesystem::path write_job_file(const std::string& out_dir, const EncodedJob& encoded, CutterLanguage language) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec)
    throw CliError(kCannotWrite, ErrorCode::io, out_dir, "output", "cannot create the directory: " + ec.message());
  const std::filesystem::path dir(out_dir);
  write_cli_output((dir / job_file_name(language)).string(), [&](std::ostream& o) { o << encoded.bytes; });
  return dir;
}

DeviceRun run_device_job(const Target& target, const DeviceProfile& profile, const drivers::DevicePlan& job,
                         const SimFaultArgs& faults, const std::string& out_dir, bool progress_bar) {
  drivers::CutSession session(target.device, profile, session_options(faults));
  check_device(faults, session, profile, target);
  open_device(session);
  DeviceRun run;
  run.described = session.describe();
  const auto start = std::chrono::steady_clock::now();
  run.sent = send_with_interrupts(session, job.encoded, profile, progress_bar);
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.check = session.finish(run.sent, session.simulator() ? drivers::planned_paths(job.plan, profile.dialect, 1)
                                                           : std::vector<PlotterPath>{});
  const std::string report =
      out_dir.empty() ? "the --json report" : (std::filesystem::path(out_dir) / "report.json").string();
  if (const drivers::SimCutter* cutter = session.simulator(); cutter && run.check) {
    run.sim = sim_json(*cutter, *run.check, 1);
    run.sim_motion_s = cutter->report().motion_time_s;
    if (!out_dir.empty()) {
      write_cli_output((std::filesystem::path(out_dir) / "cut.svg").string(),
                       [&](std::ostream& o) { cutter->write_svg(o); });
    }
  }
  run.failed = stopped_exit(run.sent, profile, job.encoded.bytes.size(), run.described);
  if (!run.failed && run.check) run.failed = sim_exit(faults.slowdown, profile, *run.check, report);
  return run;
}

}  // namespace popcut::cli
