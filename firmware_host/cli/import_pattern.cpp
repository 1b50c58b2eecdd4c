// popcut import-pattern: reads a drawing, reports what it found, and writes the card's face model or the conflicts.
#include "cli/import_pattern.h"

#include <iostream>
#include <sstream>

#include "cli/common.h"
#include "cli/fold.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/text.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

DrawingOptions drawing_options(const ImportPatternCommand& s) {
  DrawingOptions o;
  o.chord_tolerance_mm = s.chord_mm;
  o.red_is_cut = s.red_is_cut;
  o.unit_mm = s.unit_mm;
  for (const std::string& pair : s.layers) {
    const auto eq = pair.find('=');
    const auto kind = eq == std::string::npos ? std::nullopt : kDrawnKindNames.find(pair.substr(eq + 1));
    if (!kind || *kind == DrawnKind::unknown)
      throw CliError(
          kBadInput, ErrorCode::invalid_input, "", "--layer",
          "expected NAME=KIND with KIND one of cut, mountain, valley, fold, flat or outline, got \"" + pair + "\"");
    o.layer_names.emplace_back(pair.substr(0, eq), *kind);
  }
  return o;
}

json report_json(const ImportPatternCommand& s, const CardImport& r) {
  json conflicts = json::array();
  for (const CardConflict& c : r.card.conflicts)
    conflicts.push_back({{"what", c.what}, {"at", {c.at.x_mm, c.at.v_mm}}, {"drawn", c.drawn}, {"regions", c.regions}});
  json j = {{"format", "popcut.import-pattern.v1"},
            {"source", r.drawing.source},
            {"lines", r.drawing.lines.size()},
            {"regions", r.map.regions.size()},
            {"edges", r.map.edges.size()},
            {"snapped_ends", r.map.snapped_ends},
            {"notes", r.drawing.notes},
            {"card", r.card.model.has_value()},
            {"conflicts", conflicts}};
  for (const std::string& n : r.map.notes) j["notes"].push_back(n);
  if (r.card.model) {
    j["centre_fold_v_mm"] = r.card.centre_fold_v_mm;
    j["faces"] = r.card.model->face_count();
    if (!s.out_path.empty()) j["output"] = s.out_path;
  }
  return j;
}

void print_report(const ImportPatternCommand& s, const CardImport& r) {
  std::cout << shown(s.drawing_path) << ": " << r.drawing.lines.size() << " drawn lines, " << r.map.regions.size()
            << " regions\n";
  for (const std::string& n : r.drawing.notes) std::cout << "  note: " << n << "\n";
  for (const std::string& n : r.map.notes) std::cout << "  note: " << n << "\n";
  if (!r.card.model) {
    std::cout << "no OA card folds from this sheet (" << r.card.conflicts.size() << " conflict"
              << (r.card.conflicts.size() == 1 ? "" : "s") << "):\n";
    std::istringstream lines(describe_conflicts(r.card));
    for (std::string l; std::getline(lines, l);) std::cout << "  " << l << "\n";
    return;
  }
  std::cout << "an OA card of " << r.card.model->face_count() << " faces; centre fold "
            << format_decimal(r.card.centre_fold_v_mm, 3) << " mm above the sheet's bottom edge\n";
  if (!s.out_path.empty()) std::cout << "wrote " << s.out_path << "\n";
}

// --as sheet: the sheet's check, and with -o its report (JSON) or the folded sheet (OBJ, glTF).
int run_sheet(const ImportPatternCommand& s) {
  const std::string ext =
      s.out_path.empty() ? "" : require_extension(s.out_path, {".json", ".obj", ".gltf"}, "output type");
  const FoldableSheet sheet = load_cli_sheet(s.drawing_path, s.read_as, drawing_options(s), {s.snap_mm});
  const SheetMotionReport r = check_sheet_motion(sheet, s.frames);
  const nlohmann::json report = sheet_check_json(shown(s.drawing_path), sheet, r);
  std::string wrote;
  if (ext == ".json") {
    write_cli_output(s.out_path, [&](std::ostream& o) { o << report.dump(2) << "\n"; });
    wrote = s.out_path;
  } else if (!ext.empty()) {
    wrote = write_folded_mesh(s.out_path, folded_sheet(sheet, 1));
  }
  if (s.json_out) {
    print_json_line(report);
  } else {
    print_sheet_check(std::cout, shown(s.drawing_path), sheet, r);
    if (!wrote.empty()) std::cout << "wrote " << wrote << "\n";
  }
  return sheet_check_exit(sheet, r);
}

int run(const ImportPatternCommand& s) {
  check_read_as(s.read_as);
  if (s.read_as.sheet()) return run_sheet(s);
  SheetMapOptions map;
  map.snap_tolerance_mm = s.snap_mm;
  const CardImport r = import_card(s.drawing_path, drawing_options(s), map);
  if (r.card.model && !s.out_path.empty()) {
    const Pattern p = make_pattern(*r.card.model, r.drawing.source);
    require_attached(*r.card.model, p, check_popup(p), r.drawing.source);
    write_cli_output(s.out_path, [&](std::ostream& o) { o << to_face_json(*r.card.model, r.drawing.source); });
  }
  if (s.json_out)
    print_json_line(report_json(s, r));
  else
    print_report(s, r);
  return r.card.model ? kOk : kDoesNotPopUp;
}

}  // namespace

void add_import_pattern_command(CLI::App& app, ImportPatternCommand& s) {
  s.app = app.add_subcommand(
      "import-pattern",
      "Read a pattern drawn elsewhere (SVG, DXF, FOLD) as an OA card and write its face model, or (--as sheet) "
      "as a sheet that folds rigidly and check its motion; exit 1 with the conflicts when it does not fold.");
  s.app->add_option("DRAWING", s.drawing_path, "Drawing: FILE.svg, FILE.dxf or FILE.fold")->required();
  s.app->add_option("-o,--output", s.out_path,
                    "Write the card as a face model (popcut.faces.v1 JSON); --as sheet: the check report "
                    "(popcut.sheet-check.v1, OUT.json) or the folded sheet (OUT.obj, OUT.gltf)");
  add_read_as_options(s.app, s.read_as, true);
  s.app->add_option("--frames", s.frames, "--as sheet: steps of the motion from flat to folded that are checked")
      ->check(CLI::Range(2, 720))
      ->capture_default_str();
  s.app->add_option("--layer", s.layers, "NAME=KIND: a layer or group name and the kind of its lines (repeatable)");
  s.app->add_option("--chord-mm", s.chord_mm, "Curves become chords within this distance (mm)")
      ->check(CLI::Range(0.001, 10.0));
  s.app->add_option("--snap-mm", s.snap_mm, "Line ends this close to another end or line join it (mm)")
      ->check(CLI::Range(0.0, 1.0));
  s.app
      ->add_option(
          "--unit-mm,--fold-unit-mm", s.unit_mm,
          "Drawings that state no unit (FOLD without frame_unit, DXF without $INSUNITS): what one unit measures (mm)")
      ->check(CLI::Range(1e-6, 1e5));
  s.app->add_flag("--red-is-cut", s.red_is_cut,
                  "SVG and DXF: solid red lines are cuts (the laser convention), not mountains");
  s.app->add_flag("--json", s.json_out, "Print the report as JSON (popcut.import-pattern.v1) on standard output");
}

std::optional<int> run_import_pattern_command(const ImportPatternCommand& s) {
  if (!s.app || !*s.app) return std::nullopt;
  return run_guarded(s.json_out, [&] { return run(s); });
}

}  // namespace popcut::cli
