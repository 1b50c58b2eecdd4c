// popcut import: mesh → voxels (or silhouette faces) → model, pattern and report, with the sheet checked against every
// device.
#include "cli/import.h"

#include <algorithm>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/common.h"
#include "cli/devices.h"
#include "validation.h"
#include "popcut/error.h"
#include "popcut/io/pattern_io.h"
#include "popcut/mesh/import_request.h"
#include "popcut/mesh/mesh_import.h"
#include "popcut/mesh/silhouette_faces.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/text.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

// What an import made, with the pop-up check of its pattern and the devices its sheet does not fit.
struct ImportOutcome {
  const MeshImport& imported;
  const PopupReport& report;
  const std::vector<std::string>& warnings;
  double sheet_w, sheet_h, closed_h;
};

json import_json(const ImportCommand& s, const ImportOutcome& o) {
  const ImportResult& r = o.imported.voxels;
  const ImportStats& st = r.stats;
  json j = validation_json(s.out_path, o.imported.pattern, o.report);
  j["sheet_mm"] = {{"width", o.sheet_w}, {"height", o.sheet_h}};
  j["closed_mm"] = {{"width", o.sheet_w}, {"height", o.closed_h}};
  j["warnings"] = o.warnings;
  j["mesh"] = {{"triangles", st.triangles}, {"degenerate", st.degenerate}};
  j["grid"] = {
      {"width", r.grid.width}, {"depth", r.grid.depth}, {"height", r.grid.height}, {"voxel_mm", r.grid.voxel_mm}};
  j["cells_filled"] = st.cells_filled;
  j["windows_added"] = st.windows_added;
  j["windows_rejected"] = st.windows_rejected;
  j["tops_dropped"] = st.tops_dropped;
  j["tops_kept"] = st.tops_kept;
  j["timings_ms"] = {
      {"read", r.timings.read_ms},    {"sampling", r.timings.sample_ms}, {"morphology", r.timings.morphology_ms},
      {"filling", r.timings.fill_ms}, {"windows", r.timings.windows_ms}, {"thin_tops", r.timings.thin_ms}};
  if (!s.pattern_path.empty()) j["pattern"] = s.pattern_path;
  if (o.imported.faces) {
    const SilhouetteComparison& c = o.imported.faces->comparison;
    j["faces"] = {
        {"outlines_redrawn", c.outlines}, {"outlines_kept", c.outlines_kept}, {"fell_back", c.fell_back},
        {"steps_kept", c.steps_kept},     {"voxel_lines", c.voxel_lines},     {"face_lines", c.face_lines},
        {"samples", c.samples},           {"voxel_mean_mm", c.voxel_mean_mm}, {"face_mean_mm", c.face_mean_mm},
        {"voxel_max_mm", c.voxel_max_mm}, {"face_max_mm", c.face_max_mm}};
  }
  return j;
}

void print_import(const ImportCommand& s, const ImportOutcome& o, int thin_top_voxels) {
  const auto mm = [](double v) { return format_fixed(v, 1); };
  const ImportResult& r = o.imported.voxels;
  const ImportStats& st = r.stats;
  std::ostream& out = s.out_path == "-" ? std::cerr : std::cout;
  out << s.mesh_path << ": " << st.triangles << " triangles"
      << (st.degenerate ? " (" + std::to_string(st.degenerate) + " of zero area dropped)" : "") << " -> "
      << r.grid.width << " x " << r.grid.depth << " x " << r.grid.height << " voxels of " << r.grid.voxel_mm
      << " mm; filled " << st.cells_filled << " cells; windows: " << st.windows_added << " added, "
      << st.windows_rejected << " rejected";
  if (thin_top_voxels > 0) out << "; thin tops: " << st.tops_dropped << " dropped, " << st.tops_kept << " kept";
  out << "; sheet " << mm(o.sheet_w) << " x " << mm(o.sheet_h) << " mm (closed " << mm(o.sheet_w) << " x "
      << mm(o.closed_h) << ")";
  out << "; wrote " << s.out_path << (s.pattern_path.empty() ? "" : " and " + s.pattern_path) << "\n";
  for (const std::string& w : o.warnings) std::cerr << "popcut: warning: " << s.mesh_path << ": " << w << "\n";
  if (o.imported.faces) {
    const SilhouetteComparison& c = o.imported.faces->comparison;
    out << "faces: " << c.outlines << " outlines follow the silhouette (" << c.outlines_kept << " kept in steps, "
        << c.steps_kept << " single steps kept"
        << (c.fell_back ? "; the redrawn model failed its check: voxel outlines written" : "") << "); lines "
        << c.voxel_lines << " (voxels) -> " << c.face_lines << " (faces); distance to the silhouette, mean "
        << mm(c.voxel_mean_mm) << " -> " << mm(c.face_mean_mm) << " mm, max " << mm(c.voxel_max_mm) << " -> "
        << mm(c.face_max_mm) << " mm over " << c.samples << " samples\n";
  }
  print_validation(out, s.out_path, o.imported.pattern, o.report);
}

int run_import(const ImportCommand& s) {
  // Every shipped or configured profile: --fit-mm may name one, and a sheet too big for one is warned of.
  const std::vector<NamedMedia> media = profile_media();
  ImportRequest request = parse_import_options(s.import_values, s.mesh_path, media);
  request.options.name = s.model_label;
  if (s.out_path != "-") require_extension(s.out_path, {".json"}, "model type");
  std::string pattern_ext;
  if (!s.pattern_path.empty())
    pattern_ext = require_extension(s.pattern_path, {".svg", ".json"}, "pattern type", "--pattern");
  if (s.out_path == "-" && s.json_out) {
    throw Error(ErrorCode::invalid_input, s.mesh_path, "--json",
                "cannot print a summary when the model itself goes to standard output");
  }
  const MeshImport imported = import_mesh_file(s.mesh_path, request, s.mesh_path);
  const Pattern& p = imported.pattern;
  const PopupReport report = check_popup(p);
  write_cli_output(s.out_path, [&](std::ostream& out) { out << imported.model_json; });
  if (!s.pattern_path.empty()) {
    write_cli_output(s.pattern_path, [&](std::ostream& out) {
      if (pattern_ext == ".svg")
        write_pattern_svg(out, p, {true});
      else
        write_pattern_json(out, p);
    });
  }
  const std::vector<std::string> warnings = media_warnings(p.sheet, media);
  const ImportOutcome outcome{imported,
                              report,
                              warnings,
                              p.sheet.max.x_mm - p.sheet.min.x_mm,
                              p.sheet.max.v_mm - p.sheet.min.v_mm,
                              std::max(p.sheet.max.v_mm, -p.sheet.min.v_mm)};
  if (s.json_out)
    print_json_line(import_json(s, outcome));
  else
    print_import(s, outcome, request.options.thin_top_voxels);
  return report.pops_up() ? kOk : kDoesNotPopUp;
}

}  // namespace

void add_import_options(CLI::App* cmd, ImportValues& values) {
  const ImportOptions d;
  const auto option = [&](const char* name, const std::string& help) {
    cmd->add_option_function<std::string>(
        std::string("--") + name, [&values, name](const std::string& v) { values.emplace_back(name, v); }, help);
  };
  const auto flag = [&](const char* name, const std::string& help) {
    cmd->add_flag_callback(
        std::string("--") + name, [&values, name] { values.emplace_back(name, "true"); }, help);
  };
  option("up", std::string("Mesh axis pointing up: +x, -x, +y, -y, +z or -z (default ") + to_string(d.up) + ")");
  option("front",
         std::string("Mesh axis pointing at the viewer, the card's depth (default ") + to_string(d.front) + ")");
  option("resolution", "Voxels across the card (default " + std::to_string(d.resolution) + ")");
  option("width-mm", "Card width of the model in mm (default 120)");
  option("voxel-mm", "Voxel edge in mm, instead of --width-mm");
  option("height-mm",
         "Standing height of the card (its back board, as tall as the closed card) in mm, instead of --width-mm");
  option("fit-mm",
         "The largest card whose closed outline fits WxH mm (148x105 or 148×105), or whose flat sheet fits a device's "
         "media "
         "(a profile name, e.g. sim; popcutd: a device name), instead of --width-mm");
  option("keep-depth", "Fraction of the model's depth kept, from the front (default 0.5, as the paper)");
  option("smooth", "Side of the square for opening and closing each slice, in voxels (odd; 1 = off; default " +
                       std::to_string(d.structuring_element) + ")");
  flag("no-windows", "Leave the rows filled by eq. 7 solid instead of trying them as windows");
  option("thin-tops",
         "Drop top faces at most this many voxels wide where the card stays valid (0 = keep all, the default)");
  option("depth-method", "zbuffer (rasterise triangles, the default) or raycast (CGAL AABB tree)");
  flag("faces",
       "Make a popcut.faces.v1 face model whose cut outlines (wall tops, openings) follow the mesh silhouette instead "
       "of voxel steps");
}

void add_import_command(CLI::App& app, ImportCommand& s) {
  s.app = app.add_subcommand("import",
                             "Turn a 3D mesh (OBJ, STL, OFF, PLY) into a voxel card that pops up (voxel paper §3).");
  s.app->add_option("MESH", s.mesh_path, "Mesh file: .obj, .stl (ASCII or binary), .off or .ply")->required();
  s.app
      ->add_option("-o,--output", s.out_path,
                   "Where to write the popcut.voxel.v1 model (OUT.json, or - for standard output)")
      ->required();
  add_import_options(s.app, s.import_values);
  s.app->add_option("--name", s.model_label, "Label stored in the model");
  s.app->add_option("--pattern", s.pattern_path, "Also write the pattern: OUT.svg or OUT.json");
  s.app->add_flag("--json", s.json_out, "Print the result as JSON on standard output");
}

std::optional<int> run_import_command(const ImportCommand& s) {
  if (s.app && *s.app) return run_guarded(s.json_out, [&] { return run_import(s); });
  return std::nullopt;
}

}  // namespace popcut::cli
