// popcut test-cut: a square cut through inside a scored triangle, placed on the device's area, cut as a job is.
#include "cli/test_cut.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <vector>

#include "cli/checks.h"
#include "cli/common.h"
#include "popcut/drivers/calibration.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/send_report.h"
#include "popcut/error.h"
#include "popcut/lang/device_check.h"
#include "popcut/text.h"
#include "report_json.h"

namespace popcut::cli {
namespace {

using drivers::DeviceProfile;
using nlohmann::json;

// Where the test goes, on the plotter's axes: its box's corner nearest the origin corner.
struct Spot {
  double x_mm = 0, y_mm = 0;
};

Spot parse_at(const std::string& text, double default_mm) {
  if (text.empty()) return {default_mm, default_mm};
  const std::size_t comma = text.find(',');
  const auto number = [&](const std::string& part, double& out) {
    std::size_t used = 0;
    try {
      out = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    return used > 0 && used == part.size() && std::isfinite(out);
  };
  Spot s;
  if (comma == std::string::npos || !number(text.substr(0, comma), s.x_mm) || !number(text.substr(comma + 1), s.y_mm))
    throw Error(ErrorCode::invalid_input, "", "--at", "'" + text + "' is not X,Y in mm (e.g. --at 20,30)");
  return s;
}

// The fold tool the triangle is scored with (valley, else mountain); cut as the square is when the
// profile skips both.
PlanKind triangle_kind(const DeviceProfile& p) {
  for (PlanKind k : {PlanKind::valley, PlanKind::mountain}) {
    if (p.plan.kinds[index_of(k)].mode != ToolMode::skip) return k;
  }
  return PlanKind::cut;
}

LineKind line_kind_of(PlanKind k) {
  return k == PlanKind::valley ? LineKind::valley : k == PlanKind::mountain ? LineKind::mountain : LineKind::cut;
}

struct Placed {
  Spot at;
  double box_x_mm = 0, box_y_mm = 0;  // on the plotter's axes
  double edge_mm = 0;                 // kept from the area's edges
};

// The test at `at` must lie inside the usable area, `edge` from its edges (the drag knife's arcs
// and the fold gap from the sheet's edge reach that far).
Placed place_test(const Spot& at, const TestCutShape& shape, const DeviceProfile& p, const std::string& at_text) {
  const PlotterFrame& f = p.dialect;
  Placed out;
  out.at = at;
  out.edge_mm = std::max(p.plan.blade_offset_mm, p.plan.fold_gap_mm) + 0.5;
  out.box_x_mm = f.swap_axes ? shape.height_mm() : shape.width_mm();
  out.box_y_mm = f.swap_axes ? shape.width_mm() : shape.height_mm();
  const double avail_x = static_cast<double>(f.area_max_x_pu - f.area_min_x_pu) / f.units_per_mm_x;
  const double avail_y = static_cast<double>(f.area_max_y_pu - f.area_min_y_pu) / f.units_per_mm_y;
  const double hi_x = avail_x - out.box_x_mm - out.edge_mm, hi_y = avail_y - out.box_y_mm - out.edge_mm;
  const double lo = out.edge_mm;
  if (at.x_mm < lo || at.y_mm < lo || at.x_mm > hi_x || at.y_mm > hi_y) {
    const auto range = [&](double hi) {
      return hi < lo ? std::string("nowhere") : format_decimal(lo, 1) + " to " + format_decimal(hi, 1);
    };
    throw Error(ErrorCode::invalid_input, p.source, "--at",
                (at_text.empty() ? std::string("the default spot") : "'" + at_text + "'") + ": the test cut (" +
                    format_decimal(out.box_x_mm, 1) + " x " + format_decimal(out.box_y_mm, 1) +
                    " mm on the plotter's axes) does not fit the usable area of " + p.name + " (" +
                    format_decimal(avail_x, 1) + " x " + format_decimal(avail_y, 1) +
                    " mm from its origin corner) there, keeping " + format_decimal(lo, 1) +
                    " mm from its edges: x may be " + range(hi_x) + ", y " + range(hi_y));
  }
  return out;
}

// Where a kind's settings are written: the profile's [tool.KIND], or the material's [family] KIND.
struct Terms {
  std::string material_source, family;
  std::string key(PlanKind k, const char* field) const {
    const std::string kind(to_string(k));
    if (material_source.empty()) return "[tool." + kind + "] " + field;
    return material_source + " [" + family + "] " + kind + " " + field;
  }
};

// A list of per-pass values ("70/140"), or the one value.
std::string values_text(const std::vector<double>& per_pass, double one) {
  if (per_pass.empty()) return format_decimal(one, 1);
  std::string out;
  for (double v : per_pass) out += (out.empty() ? "" : "/") + format_decimal(v, 1);
  return out;
}

std::string tool_text(const DeviceProfile& p, PlanKind k) {
  const ToolSetting& t = p.tools[index_of(k)];
  const KindPlan& kp = p.plan.kinds[index_of(k)];
  return "[tool." + std::string(to_string(k)) + "] " + to_string(kp.mode) + ", force_g " +
         values_text(t.pass_force_g, t.force_g) + ", speed_cm_s " + values_text(t.pass_speed_cm_s, t.speed_cm_s) +
         ", passes " + std::to_string(kp.passes);
}

// The force that cuts through: the last pass's where passes have their own.
double full_force_g(const ToolSetting& t) { return t.pass_force_g.empty() ? t.force_g : t.pass_force_g.back(); }

json look_at(const DeviceProfile& p, PlanKind tri, const TestCutShape& s) {
  json look = json::array();
  look.push_back("the " + format_decimal(s.square_mm, 1) + " mm square (" + tool_text(p, PlanKind::cut) +
                 ") comes away cleanly: card drops out with no fibres holding it, vinyl weeds off its backing "
                 "without lifting the film around it");
  look.push_back(tri == PlanKind::cut
                     ? "the triangle is cut as the square is (the profile skips both fold kinds): it should weed as "
                       "cleanly"
                     : "the " + format_decimal(s.triangle_mm, 1) + " mm triangle (" + tool_text(p, tri) +
                           ", as your folds are) stays on: card shows a crisp score with no light through it and "
                           "folds along it; vinyl stays on its backing");
  look.push_back(
      "corners: sharp and closed, no tearing; not rounded (blade offset too small), no hooks or tails "
      "(too large)");
  look.push_back("the backing sheet or mat under the square: at most a faint line, never cut through");
  return look;
}

// What to change, in the terms the settings came from, for each fault.
json adjust(const DeviceProfile& p, PlanKind tri, const Terms& terms) {
  const ToolSetting& cut = p.tools[index_of(PlanKind::cut)];
  const double cut_g = full_force_g(cut), score_g = full_force_g(p.tools[index_of(tri)]);
  const auto times = [](double g, double f) { return format_decimal(g * f, 0); };
  const char* force = cut.pass_force_g.empty() ? "force_g" : "pass_force_g (the last pass)";
  const double blade = p.plan.blade_offset_mm;
  json out = json::array();
  out.push_back("square not cut through: raise " + terms.key(PlanKind::cut, force) + " by about 10 % (" +
                format_decimal(cut_g, 0) + " -> " + times(cut_g, 1.1) + ") or add a pass (" +
                terms.key(PlanKind::cut, "passes") + "); backing or mat cut: lower it by about 10 % (-> " +
                times(cut_g, 0.9) +
                ") or shorten the blade (less blade out of the holder: about the material's "
                "thickness)");
  if (tri != PlanKind::cut) {
    out.push_back("triangle cut through: lower " + terms.key(tri, "force_g") + " by about 15 % (" +
                  format_decimal(score_g, 0) + " -> " + times(score_g, 0.85) +
                  "); score too faint to fold: raise it by about 15 % (-> " + times(score_g, 1.15) + ")");
  }
  out.push_back("torn or ragged corners: lower " + terms.key(PlanKind::cut, "speed_cm_s") + " by about a third (" +
                format_decimal(cut.speed_cm_s, 1) + " -> " + format_decimal(cut.speed_cm_s * 0.67, 1) +
                "), or use a fresh blade");
  // A GP-GL device that turns its blade itself (FC) has its offset there, not in popcut's plan.
  const bool device_offset = p.language == CutterLanguage::gpgl && p.gpgl.cutter_offset_mm && blade == 0;
  const std::string offset_key = device_offset ? "[gpgl] cutter_offset_mm" : "[plan] blade_offset_mm";
  const double offset = device_offset ? *p.gpgl.cutter_offset_mm : blade;
  out.push_back(
      "rounded corners: raise " + offset_key + " by 0.05 (" + format_decimal(offset, 2) + " -> " +
      format_decimal(offset + 0.05, 2) + "); hooks or tails at the corners: lower it by 0.05" +
      (p.plan.overcut_mm > 0 ? "" : "; a loop that does not close where it started: set [plan] overcut_mm = 0.5"));
  return out;
}

json test_json(const TestCutCommand& c, const DeviceProfile& p, const Placed& at, const TestCutShape& s, PlanKind tri,
               const drivers::DevicePlan& plan, const Terms& terms) {
  const KindStats t = plan.plan.total();
  json r = {{"format", "popcut.test_cut.v1"},
            {"profile", p.source},
            {"device", p.name},
            {"at_mm", {at.at.x_mm, at.at.y_mm}},
            {"box_mm",
             {{"min_x", at.at.x_mm},
              {"min_y", at.at.y_mm},
              {"max_x", at.at.x_mm + at.box_x_mm},
              {"max_y", at.at.y_mm + at.box_y_mm}}},
            {"square", {{"side_mm", s.square_mm}, {"kind", "cut"}, {"tool", tool_text(p, PlanKind::cut)}}},
            {"triangle",
             {{"side_mm", s.triangle_mm}, {"gap_mm", s.gap_mm}, {"kind", to_string(tri)}, {"tool", tool_text(p, tri)}}},
            {"strokes", t.strokes},
            {"cut_mm", t.cut_mm},
            {"est_time_s", plan.time.total_s},
            {"job_bytes", plan.encoded.bytes.size()},
            {"calibration", drivers::calibration_json(p.calibration)},
            {"material", c.material.empty() ? json(nullptr) : json(c.material)}};
  r["look_at"] = look_at(p, tri, s);
  r["adjust"] = adjust(p, tri, terms);
  return r;
}

int run_test_cut(const TestCutCommand& c) {
  return run_guarded(c.json_out, [&] {
    Target target = cut_target(c.device, c.app->count("--device") > 0, c.profile_path);
    std::string material_source;
    DeviceProfile p = load_cli_profile(target.profile_path, c.material, &material_source);
    use_profile_device(target, p);
    const TestCutShape shape = test_cut_shape(c.square_mm);
    const Placed at = place_test(parse_at(c.at, 10), shape, p, c.at);
    const PlanKind tri = triangle_kind(p);
    // The test alone: no sheet outline is cut around it.
    p.plan.kinds[index_of(PlanKind::outline)].mode = ToolMode::skip;
    const Point2 offset = p.dialect.swap_axes ? Point2{at.at.y_mm, at.at.x_mm} : Point2{at.at.x_mm, at.at.y_mm};
    const drivers::DevicePlan plan = drivers::plan_for_device(
        test_cut_pattern(shape, offset, at.edge_mm, line_kind_of(tri)), p, target.profile_path);
    if (!c.out_dir.empty()) write_job_file(c.out_dir, plan.encoded, p.language);
    if (!target.note.empty() && !c.json_out) std::cerr << "popcut: " << target.note << "\n";
    const DeviceRun run = run_device_job(target, p, plan, c.faults, c.out_dir, !c.no_progress && !c.json_out);
    const Terms terms{material_source, std::string(drivers::kDeviceFamilyNames.name(p.family))};
    json report = test_json(c, p, at, shape, tri, plan, terms);
    report["transport"] = run.described;
    report["sent"] = drivers::send_result_json(run.sent, plan.encoded.bytes.size());
    if (!run.sim.is_null()) report["sim"] = run.sim;
    if (!c.out_dir.empty()) {
      write_cli_output((std::filesystem::path(c.out_dir) / "report.json").string(),
                       [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
    }
    if (c.json_out) print_json_line(report);
    if (run.failed) return *run.failed;
    if (!c.json_out) {
      std::cout << "test cut on " << run.described << " (" << p.name << ") at " << format_decimal(at.at.x_mm, 1) << ","
                << format_decimal(at.at.y_mm, 1) << " mm from the origin corner (" << format_decimal(at.box_x_mm, 1)
                << " x " << format_decimal(at.box_y_mm, 1) << " mm on the plotter's axes)\nlook at:\n";
      for (const auto& line : report["look_at"]) std::cout << "  - " << line.get<std::string>() << "\n";
      std::cout << "adjust:\n";
      for (const auto& line : report["adjust"]) std::cout << "  - " << line.get<std::string>() << "\n";
    }
    return static_cast<int>(kOk);
  });
}

}  // namespace

void add_test_cut_command(CLI::App& app, TestCutCommand& c) {
  c.app = app.add_subcommand(
      "test-cut",
      "Cut the square-in-triangle test: a square cut through ([tool.cut]) inside a triangle scored as folds are\n"
      "([tool.valley]), through the planner (blade offset, overcut, passes) and the device's cut path, then say\n"
      "what to look at and how to adjust the profile. Exit codes as cut's: 0 cut, 2 bad input (a spot where it\n"
      "does not fit names the area), 3 the job did not get through, 130 cancelled.");
  c.app->add_option("--profile", c.profile_path, "Device profile (default: configs/devices/sim.toml on --device sim)");
  c.app->add_option("--device", c.device, "As for cut: sim, file:PATH, serial:..., usb:...; default: the profile's");
  c.app->add_option("--material", c.material, kMaterialHelp);
  c.app->add_option("--at", c.at,
                    "X,Y: where the test's corner nearest the origin goes, in mm from the usable area's origin corner "
                    "along the plotter's axes (default 10,10)");
  c.app->add_option("--size-mm", c.square_mm, "The square's side; the triangle is 2.8 times as wide (default 10)")
      ->check(finite_range(3, 50));
  c.app->add_option("--out", c.out_dir,
                    "Also write job.hpgl (or job.gpgl), report.json and (on sim) cut.svg into this directory");
  c.app->add_flag("--json", c.json_out, "Print the report (popcut.test_cut.v1) as JSON on standard output");
  c.app->add_flag("--no-progress", c.no_progress, "No progress bar, even on a terminal");
  add_sim_fault_options(*c.app, c.faults);
}

std::optional<int> run_test_cut_command(const TestCutCommand& c) {
  if (c.app && *c.app) return run_test_cut(c);
  return std::nullopt;
}

}  // namespace popcut::cli
