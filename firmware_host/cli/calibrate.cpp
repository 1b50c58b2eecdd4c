// popcut calibrate: cuts the frame, reads the measured lengths, writes scale, skew and time factor into the overlay.
#include "cli/calibrate.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/checks.h"
#include "cli/common.h"
#include "popcut/drivers/calibration.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/motion_model.h"
#include "popcut/drivers/send_report.h"
#include "popcut/error.h"
#include "popcut/lang/device_check.h"
#include "popcut/text.h"
#include "report_json.h"

namespace popcut::cli {
namespace {

using drivers::DeviceProfile;
using nlohmann::json;

// How long the frame really took against the motion model's time for it.
struct Timing {
  std::string timed_by;  // status, sim_clock, enter, stopwatch
  double real_s = 0, modelled_s = 0;
  double factor() const { return real_s / modelled_s; }
};

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

// The frame alone (no sheet outline), a margin from the area's origin corner.
drivers::DevicePlan frame_job(DeviceProfile p, const FrameSize& size, const std::string& profile_path) {
  p.plan.kinds[index_of(PlanKind::outline)].mode = ToolMode::skip;
  try {
    return drivers::plan_for_device(calibration_frame_pattern(size, p.plan.blade_offset_mm + 1), p, profile_path);
  } catch (const Error& e) {
    if (e.location() != "usable area") throw;
    throw Error(e.code(), e.source(), "--width-mm/--height-mm", e.message() + ": cut a smaller frame");
  }
}

// The cut's time where it can be known: the simulator's clock, the device's own drain (it answers
// status), or the user pressing Enter when the knife stops (a terminal, a device that cannot be asked).
std::optional<Timing> measure_timing(const CalibrateCommand& c, const DeviceProfile& p, const drivers::DevicePlan& job,
                                     const DeviceRun& run, bool is_sim) {
  Timing t;
  t.modelled_s = drivers::modelled_motion_s(job.encoded.bytes, p);
  if (t.modelled_s <= 0) return std::nullopt;
  const auto start = std::chrono::steady_clock::now() - std::chrono::duration<double>(run.wall_s);
  if (c.app->count("--measured-time-s") > 0) {
    t.timed_by = "stopwatch";
    t.real_s = c.measured_time_s;
  } else if (is_sim) {
    t.timed_by = "sim_clock";
    t.real_s = run.sim_motion_s;
  } else if (run.sent.drained_by == drivers::DrainedBy::esc_b || run.sent.drained_by == drivers::DrainedBy::esc_o) {
    t.timed_by = "status";
    t.real_s = run.wall_s;
  } else if (::isatty(STDIN_FILENO) && run.sent.drained_by != drivers::DrainedBy::none) {
    std::cerr << "Press Enter when the knife has stopped (type s and Enter to skip timing; if it stopped already, "
                 "skip: the time would be too long): "
              << std::flush;
    std::string line;
    if (!std::getline(std::cin, line) || line == "s") return std::nullopt;
    t.timed_by = "enter";
    t.real_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } else {
    return std::nullopt;
  }
  return t;
}

// One length from the terminal (or a pipe): a few tries on a terminal, one on a pipe.
double ask_length(const std::string& prompt) {
  const int tries = ::isatty(STDIN_FILENO) ? 3 : 1;
  for (int i = 0; i < tries; ++i) {
    std::cerr << prompt << std::flush;
    std::string line;
    if (!std::getline(std::cin, line)) break;
    std::size_t used = 0;
    double v = 0;
    try {
      v = std::stod(line, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < line.size() && std::isspace(static_cast<unsigned char>(line[used]))) ++used;
    if (used > 0 && used == line.size()) return v;
    std::cerr << "popcut: '" << line << "' is not a length in mm\n";
  }
  throw Error(ErrorCode::invalid_input, "", "measurements",
              "no lengths were entered: answer the prompts, or give --measured-x-mm, --measured-y-mm and "
              "--measured-diagonal-mm");
}

FrameMeasurement measurements(const CalibrateCommand& c, const FrameSize& size) {
  const int given = static_cast<int>(c.app->count("--measured-x-mm") + c.app->count("--measured-y-mm") +
                                     c.app->count("--measured-diagonal-mm"));
  if (given == 3) return {c.measured_x_mm, c.measured_y_mm, c.measured_diagonal_mm};
  if (given > 0) {
    throw Error(ErrorCode::invalid_input, "", "--measured-*",
                "give all three of --measured-x-mm, --measured-y-mm and --measured-diagonal-mm, or none to be asked");
  }
  std::cerr << "Measure the frame corner to corner, in mm (a steel rule; to 0.1 mm or better):\n";
  FrameMeasurement m;
  m.width_mm =
      ask_length("  the width side, cut " + format_decimal(size.width_mm, 1) + " mm (the one with the tick): ");
  m.height_mm = ask_length("  the height side, cut " + format_decimal(size.height_mm, 1) + " mm: ");
  m.diagonal_mm = ask_length("  the diagonal, cut " + format_decimal(size.diagonal_mm(), 2) + " mm: ");
  return m;
}

// The core's refusal, named by the option the value came from when it came from one.
AxisCalibration checked_calibration(const CalibrateCommand& c, const FrameSize& size, const FrameMeasurement& m,
                                    const DeviceProfile& p) {
  const drivers::DeviceCalibration& now = p.calibration;
  try {
    return calibrate_axes(size, m, p.dialect, {now.scale_x, now.scale_y, now.skew_deg});
  } catch (const Error& e) {
    std::string where = e.location();
    if (c.app->count("--measured-x-mm") > 0) {
      if (where == "measured width") where = "--measured-x-mm";
      if (where == "measured height") where = "--measured-y-mm";
      if (where == "measured diagonal") where = "--measured-diagonal-mm";
    }
    throw Error(e.code(), p.source, where, e.message());
  }
}

drivers::CalibrationOverlay overlay_of(const DeviceProfile& p, const FrameSize& size, const FrameMeasurement& m,
                                       const AxisCalibration& cal, const std::optional<Timing>& timing) {
  drivers::CalibrationOverlay o;
  o.profile = std::filesystem::absolute(p.source).string();
  o.measured_at = utc_now();
  o.frame_width_mm = size.width_mm;
  o.frame_height_mm = size.height_mm;
  o.measured_width_mm = m.width_mm;
  o.measured_height_mm = m.height_mm;
  o.measured_diagonal_mm = m.diagonal_mm;
  o.scale_x = cal.correction.scale_x;
  o.scale_y = cal.correction.scale_y;
  o.skew_deg = cal.correction.skew_deg;
  if (timing) {
    o.time_factor = timing->factor();
    o.timed_by = timing->timed_by;
    o.real_s = timing->real_s;
    o.modelled_s = timing->modelled_s;
  } else if (p.calibration.time_factor != 1) {
    o.time_factor = p.calibration.time_factor;  // kept from the overlay in effect: not measured this time
  }
  return o;
}

json error_json(const AxisError& e) {
  return {{"side_x_mm", e.side_x_mm},
          {"side_y_mm", e.side_y_mm},
          {"x_percent", (e.ratio_x - 1) * 100},
          {"y_percent", (e.ratio_y - 1) * 100},
          {"x_mm", e.off_x_mm},
          {"y_mm", e.off_y_mm},
          {"skew_deg", e.skew_deg},
          {"skew_mm", e.skew_mm}};
}

std::string signed_text(double v, int decimals) { return (v >= 0 ? "+" : "") + format_decimal(v, decimals); }

void print_result(const AxisCalibration& cal, const drivers::CalibrationOverlay& o, const std::optional<Timing>& t,
                  const std::string& path) {
  const AxisError& e = cal.error;
  std::cout << "the device was off by: x " << signed_text((e.ratio_x - 1) * 100, 2) << " % ("
            << signed_text(e.off_x_mm, 2) << " mm over " << format_decimal(e.side_x_mm, 1) << " mm), y "
            << signed_text((e.ratio_y - 1) * 100, 2) << " % (" << signed_text(e.off_y_mm, 2) << " mm over "
            << format_decimal(e.side_y_mm, 1) << " mm), axes " << signed_text(e.skew_deg, 3) << "° off square ("
            << signed_text(e.skew_mm, 2) << " mm over " << format_decimal(e.side_y_mm, 1) << " mm)\n";
  if (t) {
    std::cout << "timing (" << t->timed_by << "): " << format_decimal(t->real_s, 2) << " s against the model's "
              << format_decimal(t->modelled_s, 2) << " s: time_factor " << format_decimal(t->factor(), 3) << "\n";
  }
  std::cout << "wrote " << path << ": scale_x " << format_significant(cal.correction.scale_x, 7) << ", scale_y "
            << format_significant(cal.correction.scale_y, 7) << ", skew_deg "
            << format_significant(cal.correction.skew_deg, 4)
            << (o.time_factor ? ", time_factor " + format_significant(*o.time_factor, 4) : std::string())
            << "; every later job on this profile uses it\n";
}

// The overlay to write: --overlay, else the profile's own place (calibration.h).
std::string overlay_target(const CalibrateCommand& c, const std::string& profile_path) {
  if (!c.overlay_path.empty()) return c.overlay_path;
  const std::string path = drivers::calibration_overlay_path(profile_path);
  if (path.empty()) {
    throw Error(ErrorCode::invalid_input, "", "--overlay",
                "no place for the calibration (neither POPCUT_CALIBRATION_DIR, XDG_CONFIG_HOME nor HOME is set): give "
                "--overlay PATH");
  }
  return path;
}

// A frame cut on the simulator measures nothing about a real device: its correction (and its sim-clock
// time_factor) must not land in the overlay every later real job on that profile uses.
void refuse_sim_into_real_overlay(const CalibrateCommand& c, const Target& target, const DeviceProfile& p) {
  if (c.no_cut || target.device != "sim" || p.transport.uri == "sim" || !c.overlay_path.empty()) return;
  throw Error(ErrorCode::invalid_input, "", "--overlay",
              "--device sim with the profile of a real device (" + p.name + ", [transport] default = \"" +
                  p.transport.uri + "\" in " + target.profile_path +
                  ") would write a simulated calibration into that device's overlay: give --overlay PATH to "
                  "write it elsewhere, or calibrate on the device itself");
}

int run_calibrate(const CalibrateCommand& c) {
  return run_guarded(c.json_out, [&] {
    Target target = cut_target(c.device, c.app->count("--device") > 0, c.profile_path);
    const std::string overlay_path = overlay_target(c, target.profile_path);
    std::error_code ec;
    const DeviceProfile p = drivers::load_profile_with_overlay(
        target.profile_path, std::filesystem::exists(overlay_path, ec) ? overlay_path : std::string());
    refuse_sim_into_real_overlay(c, target, p);
    const FrameSize size{c.width_mm, c.height_mm};
    json report = {{"format", "popcut.calibrate.v1"},
                   {"profile", p.source},
                   {"device", p.name},
                   {"overlay", overlay_path},
                   {"frame_mm", {size.width_mm, size.height_mm, size.diagonal_mm()}},
                   {"in_effect", drivers::calibration_json(p.calibration)}};
    std::optional<Timing> timing;
    if (!c.no_cut) {
      use_profile_device(target, p);
      const drivers::DevicePlan job = frame_job(p, size, target.profile_path);
      if (!c.out_dir.empty()) write_job_file(c.out_dir, job.encoded, p.language);
      if (!target.note.empty() && !c.json_out) std::cerr << "popcut: " << target.note << "\n";
      const DeviceRun run = run_device_job(target, p, job, c.faults, c.out_dir, !c.no_progress && !c.json_out);
      report["transport"] = run.described;
      report["sent"] = drivers::send_result_json(run.sent, job.encoded.bytes.size());
      if (!run.sim.is_null()) report["sim"] = run.sim;
      if (run.failed) {
        if (c.json_out) print_json_line(report);
        return *run.failed;
      }
      timing = measure_timing(c, p, job, run, run.sim.is_object());
      if (timing && (timing->factor() < drivers::kMinTimeFactor || timing->factor() > drivers::kMaxTimeFactor)) {
        const std::string what = "the cut took " + format_decimal(timing->real_s, 2) + " s against the model's " +
                                 format_decimal(timing->modelled_s, 2) + " s: a time_factor of " +
                                 format_decimal(timing->factor(), 3) + " is outside 0.5–5";
        if (timing->timed_by == "stopwatch") throw Error(ErrorCode::invalid_input, "", "--measured-time-s", what);
        std::cerr << "popcut: warning: " << what << "; no time_factor written (check [kinematics])\n";
        timing.reset();
      }
    }
    const FrameMeasurement m = measurements(c, size);
    const AxisCalibration cal = checked_calibration(c, size, m, p);
    const drivers::CalibrationOverlay overlay = overlay_of(p, size, m, cal, timing);
    drivers::save_calibration_overlay(overlay_path, overlay);
    report["measured_mm"] = {m.width_mm, m.height_mm, m.diagonal_mm};
    report["error"] = error_json(cal.error);
    report["correction"] = {{"scale_x", cal.correction.scale_x},
                            {"scale_y", cal.correction.scale_y},
                            {"skew_deg", cal.correction.skew_deg},
                            {"time_factor", overlay.time_factor ? json(*overlay.time_factor) : json(nullptr)}};
    report["timing"] = timing ? json{{"timed_by", timing->timed_by},
                                     {"real_s", timing->real_s},
                                     {"modelled_s", timing->modelled_s},
                                     {"time_factor", timing->factor()}}
                              : json(nullptr);
    if (!c.out_dir.empty()) {
      write_cli_output((std::filesystem::path(c.out_dir) / "report.json").string(),
                       [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
    }
    if (c.json_out) {
      print_json_line(report);
    } else {
      print_result(cal, overlay, timing, overlay_path);
    }
    return static_cast<int>(kOk);
  });
}

}  // namespace

void add_calibrate_command(CLI::App& app, CalibrateCommand& c) {
  c.app = app.add_subcommand(
      "calibrate",
      "Cut a calibration frame (a rectangle with a diagonal and a tick on its width side), then take the lengths\n"
      "measured on it (asked for, or --measured-*) and write the correction (scale per plotter axis, skew,\n"
      "and the device's time against the motion model where it can be known) into the profile's calibration\n"
      "overlay, which every later job on the profile uses (docs/profiles.md, \"Calibration\").\n"
      "Exit codes: 0 written, 2 bad input (a measurement out of 0.9-1.1 of its length, a diagonal no frame has),\n"
      "3 the frame did not get through (nothing written), 130 cancelled.");
  c.app->add_option("--profile", c.profile_path, "Device profile (default: configs/devices/sim.toml on --device sim)");
  c.app->add_option("--device", c.device, "As for cut: sim, file:PATH, serial:..., usb:...; default: the profile's");
  c.app->add_option("--width-mm", c.width_mm, "The frame's side along the card's x (default 100)")
      ->check(finite_range(20, 1000));
  c.app->add_option("--height-mm", c.height_mm, "The frame's side along the card's height (default 150)")
      ->check(finite_range(20, 1000));
  c.app->add_option("--measured-x-mm", c.measured_x_mm, "The width side as measured (the one with the tick)");
  c.app->add_option("--measured-y-mm", c.measured_y_mm, "The height side as measured");
  c.app->add_option("--measured-diagonal-mm", c.measured_diagonal_mm, "The diagonal as measured");
  c.app
      ->add_option("--measured-time-s", c.measured_time_s,
                   "Stopwatch: seconds from the knife's first move to its last (for a device that cannot be asked)")
      ->check(finite_range(0.01, 1e6));
  c.app->add_flag("--no-cut", c.no_cut,
                  "Do not cut: the measurements are of a frame cut earlier with the calibration now in effect");
  c.app->add_option(
      "--overlay", c.overlay_path,
      "The overlay to read and write (default: POPCUT_CALIBRATION_DIR, XDG_CONFIG_HOME/popcut/calibration "
      "or ~/.config/popcut/calibration, then the profile's file name)");
  c.app->add_option("--out", c.out_dir,
                    "Also write job.hpgl (or job.gpgl), report.json and (on sim) cut.svg into this directory");
  c.app->add_flag("--json", c.json_out, "Print the report (popcut.calibrate.v1) as JSON on standard output");
  c.app->add_flag("--no-progress", c.no_progress, "No progress bar, even on a terminal");
  add_sim_fault_options(*c.app, c.faults);
}

std::optional<int> run_calibrate_command(const CalibrateCommand& c) {
  if (c.app && *c.app) return run_calibrate(c);
  return std::nullopt;
}

}  // namespace popcut::cli
