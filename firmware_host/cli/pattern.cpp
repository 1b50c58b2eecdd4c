// popcut pattern / validate / repair: load a model, check that it pops up, write its pattern or its repaired model.
#include "cli/pattern.h"

#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "validation.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/io/pattern_io.h"
#include "popcut/io/voxel_json.h"
#include "popcut/design/repair.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "popcut/text.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

int run_pattern(const PatternCommands& s) {
  const std::string ext =
      s.out_path == "-" ? ".json"
                        : require_extension(s.out_path, {".json", ".svg", ".fold", ".dxf", ".pdf"}, "output type");
  if (s.shade && ext != ".svg") {
    throw Error(ErrorCode::invalid_input, "", "--shade", "shading applies to SVG output only");
  }
  if (s.out_path == "-" && s.json_out) {
    throw Error(ErrorCode::invalid_input, "", "--json",
                "cannot print a summary when the pattern itself goes to standard output");
  }
  const Pattern p = load_cli_pattern(s.model_path, s.read_as);
  // A sheet's pattern is its drawn lines; the pop-up check is a card's.
  const PopupReport report = s.read_as.sheet() ? PopupReport{} : check_popup(p);
  write_cli_output(s.out_path, [&](std::ostream& out) {
    if (ext == ".svg")
      write_pattern_svg(out, p, {s.shade});
    else if (ext == ".fold")
      write_pattern_fold(out, p);
    else if (ext == ".dxf")
      write_pattern_dxf(out, p);
    else if (ext == ".pdf")
      write_pattern_pdf(out, p);
    else
      write_pattern_json(out, p);
  });
  if (s.json_out && s.read_as.sheet()) {
    const LineCounts c = count_lines(p);
    print_json_line({{"source", shown(s.model_path)},
                     {"output", s.out_path},
                     {"lines", {{"cut", c.cut}, {"mountain", c.mountain}, {"valley", c.valley}}},
                     {"length_mm", {{"cut", c.cut_mm}, {"mountain", c.mountain_mm}, {"valley", c.valley_mm}}}});
  } else if (s.json_out) {
    json j = validation_json(shown(s.model_path), p, report);
    j["output"] = s.out_path;
    print_json_line(j);
  } else if (!report.pops_up()) {
    std::cerr << "popcut: warning: the pattern was written, but the card will not pop up:\n";
    print_validation(std::cerr, shown(s.model_path), p, report);
  }
  if (!s.json_out && s.out_path != "-") {
    const LineCounts c = count_lines(p);
    std::cerr << "wrote " << s.out_path << " (" << p.faces.size() << " faces; " << c.cut << " cut, " << c.mountain
              << " mountain, " << c.valley << " valley lines; sheet "
              << format_fixed(p.sheet.max.x_mm - p.sheet.min.x_mm, 1) << " x "
              << format_fixed(p.sheet.max.v_mm - p.sheet.min.v_mm, 1) << " mm)\n";
  }
  return kOk;
}

int run_validate_sheet(const PatternCommands& s) {
  const FoldableSheet sheet = load_cli_sheet(s.model_path, s.read_as);
  const SheetMotionReport r = check_sheet_motion(sheet, s.frames);
  if (s.json_out)
    print_json_line(sheet_check_json(shown(s.model_path), sheet, r));
  else
    print_sheet_check(std::cout, shown(s.model_path), sheet, r);
  return sheet_check_exit(sheet, r);
}

int run_validate(const PatternCommands& s) {
  check_read_as(s.read_as);
  if (s.read_as.sheet()) return run_validate_sheet(s);
  const Pattern p = load_cli_pattern(s.model_path);
  const PopupReport report = check_popup(p);
  if (s.json_out)
    print_json_line(validation_json(shown(s.model_path), p, report));
  else
    print_validation(std::cout, shown(s.model_path), p, report);
  return report.pops_up() ? kOk : kDoesNotPopUp;
}

int run_repair(const PatternCommands& s) {
  // Voxel models only: a face model keeps the single-sheet rule by construction.
  const VoxelFile file = parse_voxel_file(read_text_file(s.model_path), shown(s.model_path));
  const RepairResult r = repair(file, {s.windows}, shown(s.model_path));
  require_valid(r.model, shown(s.model_path));
  const Pattern p = make_pattern(r.model, shown(s.model_path));
  const PopupReport report = check_popup(p);
  const std::string text = to_voxel_json(r.model);
  write_cli_output(s.out_path, [&](std::ostream& out) { out << text; });
  if (s.json_out) {
    json j = validation_json(s.out_path, p, report);
    j["cells_filled"] = r.cells_filled;
    j["windows_added"] = r.windows_added;
    j["windows_rejected"] = r.windows_rejected;
    print_json_line(j);
  } else {
    std::cout << shown(s.model_path) << ": filled " << r.cells_filled << " cells";
    if (s.windows) std::cout << "; windows: " << r.windows_added << " added, " << r.windows_rejected << " rejected";
    std::cout << "; wrote " << s.out_path << "\n";
    print_validation(std::cout, s.out_path, p, report);
  }
  return report.pops_up() ? kOk : kDoesNotPopUp;
}

}  // namespace

void add_pattern_commands(CLI::App& app, PatternCommands& s) {
  s.pattern =
      app.add_subcommand("pattern", "Write the unfolded pattern of a model as JSON or SVG (by the -o extension).");
  s.pattern
      ->add_option("MODEL", s.model_path,
                   "Model file (popcut.voxel.v1 or popcut.faces.v1 JSON), or - for standard input")
      ->required();
  s.pattern
      ->add_option("-o,--output", s.out_path,
                   "Output: OUT.json, OUT.svg, OUT.fold (crease pattern), OUT.dxf (CAD), OUT.pdf (print at 100 %), or "
                   "- for JSON on standard output")
      ->required();
  add_read_as_options(s.pattern, s.read_as, true);
  s.pattern->add_flag("--shade", s.shade, "SVG: shade VFaces and HFaces so the design reads at a glance");
  s.pattern->add_flag("--json", s.json_out, "Print a machine-readable summary (and errors) as JSON on standard output");

  s.validate = app.add_subcommand(
      "validate",
      "Check that a model makes a card that pops up (or, --as sheet, that a drawn sheet folds without an open "
      "cycle or a collision); exit 1 if not.");
  s.validate->add_option("MODEL", s.model_path, "Model file, or - for standard input")->required();
  s.validate->add_flag("--json", s.json_out,
                       "Print the report as JSON (popcut.validation.v1; popcut.sheet-check.v1 with --as sheet)");
  add_read_as_options(s.validate, s.read_as, true);
  s.validate->add_option("--frames", s.frames, "--as sheet: steps of the motion from flat to folded that are checked")
      ->check(CLI::Range(2, 720))
      ->capture_default_str();

  s.repair = app.add_subcommand("repair",
                                "Fill a model so no column is taller than the one behind it (the staircase rule), as "
                                "the voxel paper's eq. 7 does.");
  s.repair
      ->add_option("MODEL", s.model_path,
                   "Model file that may break the staircase rule (popcut.voxel.v1, heights or voxels), or -")
      ->required();
  s.repair->add_option("-o,--output", s.out_path, "Where to write the repaired popcut.voxel.v1 model")->required();
  s.repair->add_flag("--windows", s.windows, "Turn filled rows into windows where the card still pops up");
  s.repair->add_flag("--json", s.json_out, "Print the result as JSON on standard output");
}

std::optional<int> run_pattern_commands(const PatternCommands& s) {
  if (s.pattern && *s.pattern) return run_guarded(s.json_out, [&] { return run_pattern(s); });
  if (s.validate && *s.validate) return run_guarded(s.json_out, [&] { return run_validate(s); });
  if (s.repair && *s.repair) return run_guarded(s.json_out, [&] { return run_repair(s); });
  return std::nullopt;
}

}  // namespace popcut::cli
