// popcut plan / cut: pattern → stroke plan → HP-GL for a device profile → a transport (sim or file).
#include "cli_cut.h"

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli_commands.h"
#include "config_dir.h"
#include "popcut/drivers/file_transport.h"
#include "popcut/drivers/job_sender.h"
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
  std::string hpgl;
};

Job make_job(const std::string& model_path, const std::string& profile_path) {
  Job j;
  j.profile = drivers::load_profile(profile_path);
  const Pattern pattern = load_cli_pattern(model_path);
  j.plan = plan_strokes(pattern, j.profile.plan);
  try {
    // Report what is sent: strokes shorter than the plotter's resolution are not.
    j.plan = drop_below_resolution(j.plan, j.profile.dialect);
    j.time = estimate_time(j.plan, j.profile.kinematics, j.profile.cut_speed_mm_s());
    j.hpgl = encode_hpgl(j.plan, j.profile.dialect, j.profile.tools);
  } catch (const Error& e) {
    // Name the profile: the sheet is fine, it is this device that is too small.
    if (e.code() != ErrorCode::invalid_input) throw;
    throw Error(e.code(), profile_path, e.location(), e.message());
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

// A one-line bar on a terminal; nothing when stderr is a file or pipe.
class Progress {
 public:
  explicit Progress(bool on) : on_(on && ::isatty(STDERR_FILENO)) {}
  void operator()(std::size_t sent, std::size_t total) {
    if (!on_ || total == 0) return;
    const int pct = static_cast<int>(sent * 100 / total);
    if (pct == last_) return;
    last_ = pct;
    const int filled = pct * 30 / 100;
    std::cerr << "\rcutting [" << std::string(static_cast<std::size_t>(filled), '#')
              << std::string(static_cast<std::size_t>(30 - filled), '.') << "] " << pct << "% " << sent << "/" << total
              << " bytes" << std::flush;
  }
  void done() {
    if (on_ && last_ >= 0) std::cerr << "\n";
  }

 private:
  bool on_;
  int last_ = -1;
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
    if (!s.report_path.empty()) write_cli_output(s.report_path, [&](std::ostream& o) { o << report.dump(2) << "\n"; });
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

int run_cut(const CutCommands& s) {
  return run_guarded(s.json_out, [&] {
    const bool sim = s.device == "sim";
    if (!sim && s.device.rfind("file:", 0) != 0) {
      throw Error(ErrorCode::invalid_input, "", "--device",
                  "unknown device '" + s.device + "': use sim or file:PATH (serial and USB cutters are not supported yet)");
    }
    if (!sim && s.device.size() == 5) throw Error(ErrorCode::invalid_input, "", "--device", "file: needs a path, e.g. file:job.hpgl");
    if (!sim && (s.stop_answering_after >= 0 || s.drop_after >= 0 || s.slowdown != 1)) {
      throw Error(ErrorCode::invalid_input, "", "--sim-*", "fault injection applies to --device sim only");
    }
    const std::string profile_path =
        !s.profile_path.empty() ? s.profile_path : (sim ? find_config_file("devices/sim.toml") : "");
    if (profile_path.empty()) throw Error(ErrorCode::invalid_input, "", "--profile", "a file: device needs --profile");
    const Job j = make_job(s.model_path, profile_path);
    std::error_code ec;
    std::filesystem::create_directories(s.out_dir, ec);
    if (ec) throw Error(ErrorCode::io, s.out_dir, "output", "cannot create the directory: " + ec.message());
    const std::filesystem::path dir(s.out_dir);
    write_cli_output((dir / "job.hpgl").string(), [&](std::ostream& o) { o << j.hpgl; });

    drivers::SimFaults faults;
    if (s.stop_answering_after >= 0) faults.stop_answering_after_bytes = static_cast<std::size_t>(s.stop_answering_after);
    if (s.drop_after >= 0) faults.drop_after_bytes = static_cast<std::size_t>(s.drop_after);
    faults.slowdown = s.slowdown;
    std::shared_ptr<drivers::SimCutter> cutter;
    std::unique_ptr<drivers::Transport> transport;
    if (sim) {
      cutter = std::make_shared<drivers::SimCutter>(j.profile, faults);
      transport = std::make_unique<drivers::SimTransport>(cutter);
    } else {
      transport = std::make_unique<drivers::FileTransport>(s.device.substr(5));
    }
    if (const drivers::TransportStatus st = transport->open(); !st.ok()) {
      throw Error(ErrorCode::io, transport->describe(), "output", st.message);
    }
    Progress progress(!s.no_progress && !s.json_out);
    drivers::SendOptions opts = drivers::send_options(j.profile);
    // A file or printer-port node cannot answer XON/XOFF or ESC.B: the kernel's blocking writes
    // pace a printer port, and a file needs no pacing. Asking would fail after truncating it.
    if (!sim) opts.flow = drivers::FlowControl::none;
    opts.progress = [&](std::size_t sent, std::size_t total) { progress(sent, total); };
    const drivers::SendResult sent = drivers::send_job(*transport, j.hpgl, opts);
    progress.done();
    transport->close();

    json report = plan_json(j, s.model_path, profile_path);
    report["format"] = "popcut.cut.v1";
    report["transport"] = transport->describe();
    report["sent"] = {{"bytes", sent.bytes_sent},
                      {"complete", sent.status.ok()},
                      {"error", sent.status.ok() ? "" : std::string(drivers::to_string(sent.status.error))},
                      {"message", sent.status.message},
                      {"xoff_pauses", sent.xoff_pauses},
                      {"buffer_queries", sent.buffer_queries}};
    bool match = true;
    if (cutter) {
      const bool finished = sent.status.ok() && cutter->run_to_end();
      const drivers::SimReport& r = cutter->report();
      const std::optional<std::size_t> diff = drivers::first_difference(plan_in_plotter_units(j.plan, j.profile.dialect), cutter->strokes());
      match = finished && !diff && r.overflow_bytes == 0 && !r.outside_area;
      json unknown = json::array();
      for (const auto& u : r.unknown) unknown.push_back({{"offset", u.offset}, {"command", u.command}});
      json errors = json::array();
      for (const auto& e : r.errors) errors.push_back({{"offset", e.offset}, {"command", e.command}, {"message", e.message}});
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
                       {"unknown_commands", unknown},
                       {"errors", errors},
                       {"strokes_match_plan", !diff},
                       {"first_mismatch", diff ? json(*diff) : json(nullptr)}};
      write_cli_output((dir / "cut.svg").string(), [&](std::ostream& o) { cutter->write_svg(o); });
    }
    write_cli_output((dir / "report.json").string(), [&](std::ostream& o) { o << report.dump(2) << "\n"; });
    if (s.json_out) print_json_line(report);
    if (!sent.status.ok()) {
      std::cerr << "popcut: error: the job did not reach the cutter (" << transport->describe() << "): " << sent.status.message
                << " after " << sent.bytes_sent << " of " << j.hpgl.size() << " bytes\n";
      return static_cast<int>(kCannotWrite);
    }
    if (cutter && !match) {
      std::cerr << "popcut: internal error: the simulated cutter did not cut what was planned (see " << (dir / "report.json").string() << ")\n";
      return static_cast<int>(kInternal);
    }
    if (!s.json_out) {
      const KindStats t = j.plan.total();
      std::cerr << "cut on " << transport->describe() << " (" << j.profile.name << "): " << t.strokes << " strokes, "
                << static_cast<long>(t.cut_mm) << " mm cut, " << static_cast<long>(t.travel_mm) << " mm travel";
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
                                    "Writes DIR/job.hpgl, DIR/report.json and, on sim, DIR/cut.svg. Exit 3 if the job does not get through.");
  s.cut->add_option("MODEL", s.model_path, "Model file (voxel or face model), or - for standard input")->required();
  s.cut->add_option("--device", s.device, "sim, or file:PATH (a .hpgl file or a printer-port node)")->capture_default_str();
  s.cut->add_option("--profile", s.profile_path, "Device profile (default for sim: configs/devices/sim.toml)");
  s.cut->add_option("--out", s.out_dir, "Directory for job.hpgl, cut.svg and report.json")->required();
  s.cut->add_flag("--json", s.json_out, "Print the report as JSON on standard output");
  s.cut->add_flag("--no-progress", s.no_progress, "No progress bar, even on a terminal");
  s.cut->add_option("--sim-stop-after", s.stop_answering_after, "Fault: the simulator stops answering after N bytes")
      ->check(CLI::NonNegativeNumber);
  s.cut->add_option("--sim-drop-after", s.drop_after, "Fault: the simulator drops the connection after N bytes")
      ->check(CLI::NonNegativeNumber);
  s.cut->add_option("--sim-slowdown", s.slowdown, "Fault: the simulator moves this many times slower")->check(CLI::Range(1.0, 1000.0));
}

std::optional<int> run_cut_commands(const CutCommands& s) {
  if (s.plan && *s.plan) return run_plan(s);
  if (s.cut && *s.cut) return run_cut(s);
  return std::nullopt;
}

}  // namespace popcut::cli
