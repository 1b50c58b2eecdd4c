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
#include "cli/cut_device.h"
#include "cli/sim_plotter.h"
#include "config_dir.h"
#include "popcut/drivers/calibration.h"
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
  std::string bytes;   // the whole job, in the profile's language
  EncodedJob encoded;  // what is sent: the whole job, or from --resume-from on
  NestLayout layout;   // the grid of cards the media holds
  int copies = 1;      // how many of them are cut
};

Job make_job(const CutCommands& s, const std::string& profile_path, std::size_t from_stroke = 1) {
  const std::string& model_path = s.model_path;
  Job j;
  j.profile = load_cli_profile(profile_path, s.material);
  drivers::DevicePlan d =
      drivers::plan_for_device(load_cli_pattern(model_path, s.read_as), j.profile, profile_path, {s.copies, s.gap_mm});
  j.layout = d.layout;
  j.copies = s.copies;
  j.plan = std::move(d.plan);
  j.time = d.time;
  j.encoded = std::move(d.encoded);
  j.bytes = j.encoded.bytes;
  if (from_stroke != 1) {
    try {
      j.encoded = drivers::encode_for_device(j.plan, j.profile, from_stroke);
    } catch (const Error& e) {
      throw Error(e.code(), "", "--resume-from", e.message());
    }
  }
  return j;
}

json plan_json(const Job& j, const std::string& model, const std::string& profile_path, const std::string& material) {
  const KindStats t = j.plan.total();
  json r = {{"format", "popcut.plan.v1"},
            {"source", model},
            {"profile", profile_path},
            {"device", j.profile.name},
            {"material", material.empty() ? json(nullptr) : json(material)},
            {"strokes", t.strokes},
            {"pen_lifts", t.pen_lifts},
            {"pen_lift_bound", t.pen_lift_bound},
            {"cut_mm", t.cut_mm},
            {"travel_mm", t.travel_mm},
            {"est_time_s", j.time.total_s},
            {"folds_dropped", t.folds_dropped},
            {"strokes_below_resolution", t.strokes_below_resolution},
            {"language", std::string(kCutterLanguageNames.name(j.profile.language))},
            {"job_bytes", j.bytes.size()},
            {"calibration", drivers::calibration_json(j.profile.calibration)},
            {"copies",
             {{"count", j.copies},
              {"columns", j.layout.columns},
              {"rows", j.layout.rows},
              {"fit", j.layout.count()},
              {"gap_mm", j.layout.gap_mm}}},
            {"kinds", json::object()}};
  // The name reports had before GP-GL, kept for HP-GL jobs so existing scripts read on.
  if (j.profile.language == CutterLanguage::hpgl) r["hpgl_bytes"] = j.bytes.size();
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
    const Job j = make_job(s, s.profile_path);
    write_cli_output(s.out_path, [&](std::ostream& o) { o << j.bytes; });
    const json report = plan_json(j, s.model_path, s.profile_path, s.material);
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

// Knife-down length of the strokes this run sends (all of them unless --resume-from).
double run_cut_mm(const Job& j) {
  double mm = 0;
  for (std::size_t i = j.encoded.first_stroke - 1; i < j.plan.strokes.size(); ++i)
    mm += path_length_mm(j.plan.strokes[i].points);
  return mm;
}

json cut_report(const CutCommands& s, const Target& target, const Job& j, const drivers::CutSession& session,
                const drivers::SendResult& sent, const std::optional<drivers::SimCheck>& check) {
  json report = plan_json(j, s.model_path, target.profile_path, s.material);
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
  std::cerr << "; wrote " << (dir / job_file_name(j.profile.language)).string() << (cutter ? ", cut.svg" : "")
            << " and report.json\n";
}

int run_cut(const CutCommands& s) {
  return run_guarded(s.json_out, [&] {
    Target target = cut_target(s.device, s.cut->count("--device") > 0, s.profile_path);
    if (s.resume_from < 1) throw Error(ErrorCode::invalid_input, "", "--resume-from", "strokes are numbered from 1");
    const Job j = make_job(s, target.profile_path, static_cast<std::size_t>(s.resume_from));
    use_profile_device(target, j.profile);
    drivers::CutSession session(target.device, j.profile, session_options(s.faults));
    check_device(s.faults, session, j.profile, target);
    if (!target.note.empty() && !s.json_out) std::cerr << "popcut: " << target.note << "\n";
    const std::filesystem::path dir = write_job_file(s.out_dir, j.encoded, j.profile.language);
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
    if (const std::optional<int> code = stopped_exit(sent, j.profile, j.encoded.bytes.size(), session.describe()))
      return *code;
    if (check) {
      if (const std::optional<int> code =
              sim_exit(s.faults.slowdown, j.profile, *check, (dir / "report.json").string()))
        return *code;
    }
    if (!s.json_out) print_cut_summary(j, session, sent, dir);
    return static_cast<int>(kOk);
  });
}

// --copies and --gap-mm, the same on plan and cut.
void add_copies_options(CLI::App* sub, CutCommands& s) {
  sub->add_option("--copies", s.copies,
                  "Cut this many copies of the card on one sheet, nested in a grid the device's media holds\n"
                  "(folds and cuts of every card first, then every card's outline); exit 2 if they do not fit")
      ->check(CLI::Range(1, 1000));
  sub->add_option("--gap-mm", s.gap_mm, "Space between nested copies (default 5)")->check(CLI::Range(0.0, 100.0));
}

}  // namespace

void add_cut_commands(CLI::App& app, CutCommands& s) {
  s.plan = app.add_subcommand("plan", "Plan the knife's strokes for a device and write the HP-GL job (and a report).");
  s.plan->add_option("MODEL", s.model_path, "Model file (voxel or face model), or - for standard input")->required();
  add_read_as_options(s.plan, s.read_as, true);
  s.plan->add_option("--profile", s.profile_path, "Device profile, e.g. configs/devices/generic-hpgl.toml")->required();
  s.plan->add_option("-o,--output", s.out_path, "Where to write the HP-GL job, or - for standard output")->required();
  s.plan->add_option("--material", s.material, kMaterialHelp);
  s.plan->add_option("--report", s.report_path, "Also write the plan's figures as JSON (popcut.plan.v1)");
  s.plan->add_flag("--json", s.json_out, "Print the report as JSON on standard output");
  add_copies_options(s.plan, s);

  s.cut = app.add_subcommand(
      "cut",
      "Plan, encode and send a job to a cutter: the simulated one (sim) or a file/device node.\n"
      "Writes DIR/job.hpgl or DIR/job.gpgl (the job this run sends, in the profile's language, whole; report.json says "
      "how much went out), DIR/report.json and, "
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
  add_read_as_options(s.cut, s.read_as, true);
  s.cut->add_option(
      "--device", s.device,
      "sim, file:PATH (a .hpgl file or a printer-port node), serial:/dev/PORT, serial:VID:PID[:SERIAL] or\n"
      "usb:VID:PID[:SERIAL]; default: the profile's [transport] default, or sim without --profile");
  s.cut->add_option("--profile", s.profile_path, "Device profile (default: configs/devices/sim.toml on --device sim)");
  s.cut->add_option("--material", s.material, kMaterialHelp);
  s.cut->add_option(
      "--resume-from", s.resume_from,
      "Send strokes N.. only (numbered from 1 as progress and errors count them), starting with the knife up");
  s.cut->add_option("--out", s.out_dir, "Directory for job.hpgl (or job.gpgl), cut.svg and report.json")->required();
  s.cut->add_flag("--json", s.json_out, "Print the report as JSON on standard output");
  add_copies_options(s.cut, s);
  s.cut->add_flag("--no-progress", s.no_progress, "No progress bar, even on a terminal");
  add_sim_fault_options(*s.cut, s.faults);
}

std::optional<int> run_cut_commands(const CutCommands& s) {
  if (s.plan && *s.plan) return run_plan(s);
  if (s.cut && *s.cut) return run_cut(s);
  return std::nullopt;
}

}  // namespace popcut::cli
