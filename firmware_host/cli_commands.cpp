// popcut subcommands: pattern, validate, repair, fold, render, import — load a model, run core, write files and reports.
#include "cli_commands.h"
#include "cli_client.h"
#include "cli_cut.h"
#include "cli_sim_plotter.h"
#include "report_json.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <system_error>
#include <unistd.h>

#include "popcut/error.h"
#include "popcut/fold/fold.h"
#include "popcut/fold/render.h"
#include "popcut/io/files.h"
#include "popcut/io/mesh_io.h"
#include "popcut/io/model_io.h"
#include "popcut/io/pattern_io.h"
#include "popcut/io/voxel_json.h"
#include "popcut/mesh/import_request.h"
#include "popcut/mesh/mesh_import.h"
#include "popcut/mesh/silhouette_faces.h"
#include "popcut/design/repair.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

// One line of JSON on stdout; file names from the command line may not be UTF-8, so replace.
void print_json(const json& j) { std::cout << rounded_numbers(j).dump(-1, ' ', false, json::error_handler_t::replace) << "\n"; }

json point(Point2 p) { return json::array({p.x_mm, p.v_mm}); }
json rect(const Rect& r) { return {{"min", point(r.min)}, {"max", point(r.max)}}; }

std::string mm(double v) {
  char buf[32];
  // -0.04 would print as "-0.0": a designer reads that as a bug, not as a rounding.
  std::snprintf(buf, sizeof buf, "%.1f", std::abs(v) < 0.05 ? 0.0 : v);
  return buf;
}

std::string range(double a, double b) { return a == b ? mm(a) : mm(a) + "–" + mm(b); }

// Where a face stands at 90°, as a 3D box: the numbers a designer measures on the card.
struct Box3 {
  Point3 min, max;
};
Box3 card_box(const PatternFace& f) {
  Box3 b{to_card(f.kind, f.t_mm, f.outer.front()), to_card(f.kind, f.t_mm, f.outer.front())};
  for (const Point2& p : f.outer) {
    const Point3 q = to_card(f.kind, f.t_mm, p);
    b.min = {std::min(b.min.x_mm, q.x_mm), std::min(b.min.y_mm, q.y_mm), std::min(b.min.z_mm, q.z_mm)};
    b.max = {std::max(b.max.x_mm, q.x_mm), std::max(b.max.y_mm, q.y_mm), std::max(b.max.z_mm, q.z_mm)};
  }
  return b;
}

std::string describe_face(const Pattern& p, int index) {
  const PatternFace& f = p.faces[static_cast<std::size_t>(index)];
  const Rect r = bounds(f.outer);
  const Box3 b = card_box(f);
  std::ostringstream o;
  o << "face " << index << " (" << (f.kind == FaceKind::vertical ? "VFace at depth y = " : "HFace at height z = ")
    << mm(f.t_mm) << " mm): pattern x " << range(r.min.x_mm, r.max.x_mm) << ", v " << range(r.min.v_mm, r.max.v_mm)
    << " mm; on the open card x " << range(b.min.x_mm, b.max.x_mm) << ", y " << range(b.min.y_mm, b.max.y_mm) << ", z "
    << range(b.min.z_mm, b.max.z_mm) << " mm";
  return o.str();
}

json report_json(const std::string& source, const Pattern& p, const PopupReport& r) {
  const LineCounts c = count_lines(p);
  json j = {{"format", "popcut.validation.v1"},
            {"source", source},
            {"pops_up", r.pops_up()},
            {"sheet_split", r.sheet_split},
            {"no_back_board", r.no_back_board},
            {"no_floor", r.no_floor},
            {"faces", p.faces.size()},
            {"lines", {{"cut", c.cut}, {"mountain", c.mountain}, {"valley", c.valley}}},
            {"line_mm", {{"cut", c.cut_mm}, {"mountain", c.mountain_mm}, {"valley", c.valley_mm}}},
            {"sheet", rect(p.sheet)},
            {"not_standing", json::array()},
            {"loose_pieces", json::array()}};
  const auto problem_json = [&](const FaceProblem& fp) {
    const PatternFace& f = p.faces[static_cast<std::size_t>(fp.face)];
    const Box3 b = card_box(f);
    return json{{"face", fp.face},
                {"kind", to_string(f.kind)},
                {"t", f.t_mm},
                {"reached_from_back", fp.from_back},
                {"reached_from_floor", fp.from_floor},
                {"bounds", rect(bounds(f.outer))},
                {"label", point(f.label)},
                {"card_bounds", {{"min", {b.min.x_mm, b.min.y_mm, b.min.z_mm}}, {"max", {b.max.x_mm, b.max.y_mm, b.max.z_mm}}}}};
  };
  j["flaps"] = json::array();
  for (const FaceProblem& fp : r.not_standing) j["not_standing"].push_back(problem_json(fp));
  for (const FaceProblem& fp : r.flaps) j["flaps"].push_back(problem_json(fp));
  for (const LoosePiece& lp : r.loose_pieces) {
    j["loose_pieces"].push_back({{"faces", lp.faces}, {"bounds", rect(lp.bounds)}, {"area_mm2", lp.area_mm2}});
  }
  return j;
}

void print_report(std::ostream& out, const std::string& source, const Pattern& p, const PopupReport& r) {
  const LineCounts c = count_lines(p);
  out << source << ": " << (r.pops_up() ? "pops up" : "does NOT pop up") << " (" << p.faces.size() << " faces; "
      << c.cut << " cut, " << c.mountain << " mountain, " << c.valley << " valley lines)\n";
  if (r.no_back_board) out << "  no back board: no vertical face at depth 0 reaches the sheet's top edge\n";
  if (r.no_floor) out << "  no floor: no horizontal face at height 0 reaches the sheet's bottom edge\n";
  if (r.sheet_split) {
    out << "  the sheet falls in two: no fold joins the floor to the back board (is the centre fold cut all along?)\n";
  }
  for (const FaceProblem& fp : r.not_standing) {
    out << "  would not stand: " << describe_face(p, fp.face) << "; not reached "
        << (!fp.from_back && !fp.from_floor ? "from the back board or the floor"
                                            : (!fp.from_back ? "from the back board" : "from the floor"))
        << "\n";
  }
  for (const FaceProblem& fp : r.flaps) {
    out << "  note: " << describe_face(p, fp.face) << " is held from the "
        << (fp.from_back ? "back board" : (fp.from_floor ? "floor" : "neither side")) << " only; it will hang or tilt\n";
  }
  for (const LoosePiece& lp : r.loose_pieces) {
    out << "  cut free, would fall out: " << lp.faces.size() << (lp.faces.size() == 1 ? " face" : " faces")
        << " at pattern x " << range(lp.bounds.min.x_mm, lp.bounds.max.x_mm) << ", v "
        << range(lp.bounds.min.v_mm, lp.bounds.max.v_mm) << " mm (" << mm(lp.area_mm2) << " mm²)\n";
  }
}

// The name a file goes by in messages: "-" is standard input.
std::string shown(const std::string& path) { return path == "-" ? "<stdin>" : path; }

// The pattern of a model file. A face model that leaves a piece cut free of the sheet is bad
// input (exit 2, naming the edit that drew it): its edits were meant to build one sheet. A voxel
// model's loose pieces (windows that float, voxel paper Fig. 8) are what validation reports.
Pattern load_pattern(const std::string& model_path) {
  const AnyModel model = load_model(model_path);
  Pattern p = make_pattern(model, shown(model_path));
  if (const FaceModel* faces = std::get_if<FaceModel>(&model)) require_attached(*faces, p, check_popup(p), shown(model_path));
  return p;
}



std::string extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return e;
}

// The output's extension, lower-case, when it is one of `allowed`; else a bad-input error.
std::string require_extension(const std::string& path, std::initializer_list<const char*> allowed, const char* what,
                              const char* option = "-o") {
  const std::string ext = extension(path);
  std::string list;
  for (const char* a : allowed) {
    if (ext == a) return ext;
    list += std::string(list.empty() ? "" : " or ") + a;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(ErrorCode::invalid_input, path, option, std::string("is a directory: name a file in it ending ") + list);
  }
  if (ext.empty()) throw Error(ErrorCode::invalid_input, path, option, std::string("no file extension to tell the ") + what + ": use " + list);
  throw Error(ErrorCode::invalid_input, path, option, std::string("unknown ") + what + " '" + ext + "': use " + list);
}

// Runs a command body, turning popcut errors into messages and exit codes.
template <typename Body>
int guarded(bool json_errors, Body body) {
  try {
    return body();
  } catch (const Error& e) {
    // An error in a command-line option names the option; there is no file to blame.
    const bool option_error = e.source().empty() && e.location().rfind("--", 0) == 0;
    std::cerr << "popcut: error: " << (option_error ? e.location() + ": " + e.message() : std::string(e.what())) << "\n";
    if (json_errors) {
      print_json({{"error", {{"code", to_string(e.code())}, {"source", e.source()}, {"location", e.location()},
                             {"message", e.message()}}}});
    }
    if (e.code() == ErrorCode::internal) return kInternal;
    // The job did not get through: the output could not be written, or the device not opened.
    return e.code() == ErrorCode::io && (e.location() == "output" || e.location() == "device") ? kCannotWrite : kBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "popcut: error: out of memory\n";
    return kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "popcut: internal error: " << e.what() << "\n";
    return kInternal;
  }
}

// Marks write failures (location "output") so they map to kCannotWrite, not kBadInput.
void write_output(const std::string& path, const std::function<void(std::ostream&)>& content) {
  try {
    write_text_file(path, content);
  } catch (const Error& e) {
    throw Error(ErrorCode::io, e.source(), "output", e.message());
  }
}

}  // namespace

// For the command files beside this one (cli_cut.cpp).
int run_guarded(bool json_errors, const std::function<int()>& body) { return guarded(json_errors, body); }
Pattern load_cli_pattern(const std::string& model_path) { return load_pattern(model_path); }
void write_cli_output(const std::string& path, const std::function<void(std::ostream&)>& content) { write_output(path, content); }
void print_json_line(const json& j) { print_json(j); }

void add_import_options(CLI::App* cmd, std::vector<std::pair<std::string, std::string>>& values) {
  const ImportOptions d;
  const auto option = [&](const char* name, const std::string& help) {
    cmd->add_option_function<std::string>(std::string("--") + name, [&values, name](const std::string& v) { values.emplace_back(name, v); }, help);
  };
  const auto flag = [&](const char* name, const std::string& help) {
    cmd->add_flag_callback(std::string("--") + name, [&values, name] { values.emplace_back(name, "true"); }, help);
  };
  option("up", std::string("Mesh axis pointing up: +x, -x, +y, -y, +z or -z (default ") + to_string(d.up) + ")");
  option("front", std::string("Mesh axis pointing at the viewer, the card's depth (default ") + to_string(d.front) + ")");
  option("resolution", "Voxels across the card (default " + std::to_string(d.resolution) + ")");
  option("width-mm", "Card width of the model in mm (default 120)");
  option("voxel-mm", "Voxel edge in mm, instead of --width-mm");
  option("height-mm", "Standing height of the card (its back board, as tall as the closed card) in mm, instead of --width-mm");
  option("fit-mm", "The largest card whose closed outline fits WxH mm (148x105 or 148×105), or whose flat sheet fits a device's media "
                   "(a profile name, e.g. sim; popcutd: a device name), instead of --width-mm");
  option("keep-depth", "Fraction of the model's depth kept, from the front (default 0.5, as the paper)");
  option("smooth", "Side of the square for opening and closing each slice, in voxels (odd; 1 = off; default " +
                       std::to_string(d.structuring_element) + ")");
  flag("no-windows", "Leave the rows filled by eq. 7 solid instead of trying them as windows");
  option("thin-tops", "Drop top faces at most this many voxels wide where the card stays valid (0 = keep all, the default)");
  option("depth-method", "zbuffer (rasterise triangles, the default) or raycast (CGAL AABB tree)");
  flag("faces", "Make a popcut.faces.v1 face model whose cut outlines (wall tops, openings) follow the mesh silhouette instead of voxel steps");
}

int run(int argc, char** argv) {
  CLI::App app{"popcut — design origamic-architecture pop-up cards and cut them on a plotter.\n"
               "Exit codes: 0 ok, 1 card does not pop up, 2 bad input or usage, 3 cannot write output (or reach the cutter), 4 internal error."};
  app.set_version_flag("--version", std::string("popcut ") + POPCUT_VERSION);
  app.require_subcommand(1);

  std::string model_path, out_path;
  bool json_out = false, shade = false, windows = false;

  CLI::App* pattern = app.add_subcommand("pattern", "Write the unfolded pattern of a model as JSON or SVG (by the -o extension).");
  pattern->add_option("MODEL", model_path, "Model file (popcut.voxel.v1 or popcut.faces.v1 JSON), or - for standard input")->required();
  pattern->add_option("-o,--output", out_path, "Output: OUT.json, OUT.svg, or - for JSON on standard output")->required();
  pattern->add_flag("--shade", shade, "SVG: shade VFaces and HFaces so the design reads at a glance");
  pattern->add_flag("--json", json_out, "Print a machine-readable summary (and errors) as JSON on standard output");

  CLI::App* validate = app.add_subcommand("validate", "Check that a model makes a card that pops up; exit 1 if not.");
  validate->add_option("MODEL", model_path, "Model file, or - for standard input")->required();
  validate->add_flag("--json", json_out, "Print the report as JSON (popcut.validation.v1) on standard output");

  CLI::App* repair_cmd = app.add_subcommand("repair", "Fill a model so no column is taller than the one behind it (the staircase rule), as the voxel paper's eq. 7 does.");
  repair_cmd->add_option("MODEL", model_path, "Model file that may break the staircase rule (popcut.voxel.v1, heights or voxels), or -")->required();
  repair_cmd->add_option("-o,--output", out_path, "Where to write the repaired popcut.voxel.v1 model")->required();
  repair_cmd->add_flag("--windows", windows, "Turn filled rows into windows where the card still pops up");
  repair_cmd->add_flag("--json", json_out, "Print the result as JSON on standard output");

  double angle_deg = 90;
  // Degrees as people write them, in decimal: CLI11 alone would take "0x10" as 16.
  const CLI::Validator decimal_degrees(
      [](std::string& text) -> std::string {
        const bool ok = !text.empty() && text.find_first_not_of("0123456789.+-eE") == std::string::npos &&
                        text.find_first_of("0123456789") != std::string::npos;
        return ok ? std::string() : "'" + text + "' is not a number of degrees (a decimal number from 0 to 180)";
      },
      "DEGREES");
  CLI::App* fold = app.add_subcommand("fold", "Write the card folded to an angle as a 3D model (OBJ + MTL, or glTF).");
  fold->add_option("MODEL", model_path, "Model file (voxel or face model), or - for standard input")->required();
  fold->add_option("--angle", angle_deg, "Fold angle in degrees: 0 flat, 90 standing, 180 closed")->check(decimal_degrees)->capture_default_str();
  fold->add_option("-o,--output", out_path, "OUT.obj (writes OUT.mtl beside it) or OUT.gltf")->required();

  int frames = 1, width_px = 800;
  CLI::App* render = app.add_subcommand("render", "Draw the card in a 3/4 view at a fold angle (SVG or PNG), or an opening animation.");
  render->add_option("MODEL", model_path, "Model file (voxel or face model), or - for standard input")->required();
  render->add_option("--angle", angle_deg, "Fold angle in degrees: 0 flat, 90 standing, 180 closed")->check(decimal_degrees)->capture_default_str();
  render->add_option("-o,--output", out_path, "OUT.svg or OUT.png; with --frames, OUT-000.svg, OUT-001.svg, ...")->required();
  render->add_option("--frames", frames, "Frames of an opening animation from closed (180°) to --angle")->check(CLI::Range(1, 360))->capture_default_str();
  render->add_option("--width", width_px, "Picture width in pixels")->check(CLI::Range(16, 8192))->capture_default_str();

  // Every import option is read as text and checked by parse_import_options, as popcutd checks
  // the same options of an uploaded mesh (CLI11 would say only "Could not convert").
  std::vector<std::pair<std::string, std::string>> import_values;
  std::string pattern_path;
  CLI::App* import_cmd = app.add_subcommand("import", "Turn a 3D mesh (OBJ, STL, OFF, PLY) into a voxel card that pops up (voxel paper §3).");
  import_cmd->add_option("MESH", model_path, "Mesh file: .obj, .stl (ASCII or binary), .off or .ply")->required();
  import_cmd->add_option("-o,--output", out_path, "Where to write the popcut.voxel.v1 model (OUT.json, or - for standard output)")->required();
  add_import_options(import_cmd, import_values);
  std::string model_label;
  import_cmd->add_option("--name", model_label, "Label stored in the model");
  import_cmd->add_option("--pattern", pattern_path, "Also write the pattern: OUT.svg or OUT.json");
  import_cmd->add_flag("--json", json_out, "Print the result as JSON on standard output");


  // Stroke planning and cutting (issue 5): their options and handlers live in cli_cut.cpp.
  CutCommands cut_commands;
  add_cut_commands(app, cut_commands);
  // The popcutd client (issue 7): cli_client.cpp.
  ClientCommands client_commands;
  add_client_commands(app, client_commands);

  // Cutters (issue 6): what is attached, and a simulated one behind a pseudo-terminal.
  DevicesCommand devices_command;
  add_devices_command(app, devices_command);
  SimPlotterCommand sim_plotter_command;
  add_sim_plotter_command(app, sim_plotter_command);

  // A first word that is no subcommand is named as such, not reported as "subcommand required".
  if (argc > 1 && argv[1][0] != '-' && app.get_subcommands([&](CLI::App* sub) { return sub->get_name() == argv[1]; }).empty()) {
    std::cerr << "popcut: error: unknown command '" << argv[1] << "' (expected pattern, validate, repair, fold, render, import, plan, cut, submit, jobs, cancel, devices or sim-plotter)\n"
              << "Run 'popcut --help' for usage.\n";
    return kBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const auto used = app.get_subcommands();
    std::cerr << "popcut: error: " << e.what() << "\nRun 'popcut " << (used.empty() ? "" : used.front()->get_name() + " ")
              << "--help' for usage.\n";
    return kBadInput;
  }

  if (const std::optional<int> rc = run_cut_commands(cut_commands)) return *rc;
  if (const std::optional<int> rc = run_client_commands(client_commands)) return *rc;
  if (const std::optional<int> rc = run_devices_command(devices_command)) return *rc;
  if (const std::optional<int> rc = run_sim_plotter_command(sim_plotter_command)) return *rc;
  if (*pattern) {
    return guarded(json_out, [&] {
      const std::string ext = out_path == "-" ? ".json" : require_extension(out_path, {".json", ".svg"}, "output type");
      if (shade && ext != ".svg") {
        throw Error(ErrorCode::invalid_input, "", "--shade", "shading applies to SVG output only");
      }
      if (out_path == "-" && json_out) {
        throw Error(ErrorCode::invalid_input, "", "--json", "cannot print a summary when the pattern itself goes to standard output");
      }
      const Pattern p = load_pattern(model_path);
      const PopupReport report = check_popup(p);
      write_output(out_path, [&](std::ostream& out) {
        if (ext == ".svg") write_pattern_svg(out, p, {shade});
        else write_pattern_json(out, p);
      });
      if (json_out) {
        json j = report_json(shown(model_path), p, report);
        j["output"] = out_path;
        print_json(j);
      } else if (!report.pops_up()) {
        std::cerr << "popcut: warning: the pattern was written, but the card will not pop up:\n";
        print_report(std::cerr, shown(model_path), p, report);
      }
      if (!json_out && out_path != "-") {
        const LineCounts c = count_lines(p);
        std::cerr << "wrote " << out_path << " (" << p.faces.size() << " faces; " << c.cut << " cut, " << c.mountain
                  << " mountain, " << c.valley << " valley lines; sheet " << mm(p.sheet.max.x_mm - p.sheet.min.x_mm) << " x "
                  << mm(p.sheet.max.v_mm - p.sheet.min.v_mm) << " mm)\n";
      }
      return kOk;
    });
  }
  if (*validate) {
    return guarded(json_out, [&] {
      const Pattern p = load_pattern(model_path);
      const PopupReport report = check_popup(p);
      if (json_out) print_json(report_json(shown(model_path), p, report));
      else print_report(std::cout, shown(model_path), p, report);
      return report.pops_up() ? kOk : kDoesNotPopUp;
    });
  }
  if (*fold) {
    return guarded(false, [&] {
      check_fold_angle(angle_deg, "--angle");
      angle_deg += 0.0;  // "-0" is 0, and says so
      const std::string ext = require_extension(out_path, {".obj", ".gltf"}, "3D format");
      const Pattern p = load_pattern(model_path);
      const CardMesh mesh = fold_card(p, angle_deg);
      if (ext == ".gltf") {
        write_output(out_path, [&](std::ostream& out) { write_gltf(out, mesh); });
        std::cerr << "wrote " << out_path;
      } else {
        const std::filesystem::path mtl = std::filesystem::path(out_path).replace_extension(".mtl");
        write_output(out_path, [&](std::ostream& out) { write_obj(out, mesh, mtl.filename().string()); });
        write_output(mtl.string(), [&](std::ostream& out) { write_mtl(out); });
        std::cerr << "wrote " << out_path << " and " << mtl.string();
      }
      std::cerr << " (" << mesh.triangles.size() << " triangles per side, folded to " << angle_deg << "°)\n";
      return kOk;
    });
  }
  if (*render) {
    return guarded(false, [&] {
      check_fold_angle(angle_deg, "--angle");  // every frame's angle lies between 180 and it
      angle_deg += 0.0;                         // "-0" is 0, and says so
      const std::string ext = require_extension(out_path, {".svg", ".png"}, "picture format");
      const Pattern p = load_pattern(model_path);
      std::vector<double> angles;
      for (int i = 0; i < frames; ++i) angles.push_back(frames == 1 ? angle_deg : 180 + (angle_deg - 180) * i / (frames - 1));
      std::vector<CardMesh> meshes;
      for (double a : angles) meshes.push_back(fold_card_for_picture(p, a));
      const ViewBox box = view_box(meshes);  // one frame for every picture, so the animation holds still
      const bool progress_on_tty = ::isatty(STDERR_FILENO) != 0;
      const std::filesystem::path out(out_path);
      for (std::size_t i = 0; i < meshes.size(); ++i) {
        std::string path = out_path;
        if (frames > 1) {
          char suffix[16];
          std::snprintf(suffix, sizeof suffix, "-%03zu", i);
          path = (out.parent_path() / (out.stem().string() + suffix + ext)).string();
        }
        if (ext == ".svg") {
          const double px_per_mm = width_px / (box.max_x - box.min_x);
          write_output(path, [&](std::ostream& o) { write_render_svg(o, meshes[i], box, px_per_mm); });
        } else {
          const std::string png = render_png(meshes[i], box, width_px);
          write_output(path, [&](std::ostream& o) { o.write(png.data(), static_cast<std::streamsize>(png.size())); });
        }
        // A counter redrawn with \r only makes sense on a terminal; in a log it would be one long line.
        if (frames > 1 && progress_on_tty) std::cerr << "\r" << (i + 1) << "/" << frames << " frames" << std::flush;
      }
      if (frames > 1 && progress_on_tty) std::cerr << "\n";
      std::cerr << "wrote " << (frames > 1 ? std::to_string(frames) + " frames like " + out.stem().string() + "-000" + ext : out_path)
                << " (folded to " << angle_deg << "°)\n";
      return kOk;
    });
  }
  if (*repair_cmd) {
    return guarded(json_out, [&] {
      // Voxel models only: a face model keeps the single-sheet rule by construction.
      const VoxelFile file = parse_voxel_file(read_text_file(model_path), shown(model_path));
      const RepairResult r = repair(file, {windows}, shown(model_path));
      require_valid(r.model, shown(model_path));
      const Pattern p = make_pattern(r.model, shown(model_path));
      const PopupReport report = check_popup(p);
      const std::string text = to_voxel_json(r.model);
      write_output(out_path, [&](std::ostream& out) { out << text; });
      if (json_out) {
        json j = report_json(out_path, p, report);
        j["cells_filled"] = r.cells_filled;
        j["windows_added"] = r.windows_added;
        j["windows_rejected"] = r.windows_rejected;
        print_json(j);
      } else {
        std::cout << shown(model_path) << ": filled " << r.cells_filled << " cells";
        if (windows) std::cout << "; windows: " << r.windows_added << " added, " << r.windows_rejected << " rejected";
        std::cout << "; wrote " << out_path << "\n";
        print_report(std::cout, out_path, p, report);
      }
      return report.pops_up() ? kOk : kDoesNotPopUp;
    });
  }
  if (*import_cmd) {
    return guarded(json_out, [&] {
      // Every shipped or configured profile: --fit-mm may name one, and a sheet too big for one is warned of.
      const std::vector<NamedMedia> media = profile_media();
      ImportRequest request = parse_import_options(import_values, model_path, media);
      request.options.name = model_label;
      const ImportOptions& import_opt = request.options;
      if (out_path != "-") require_extension(out_path, {".json"}, "model type");
      std::string pattern_ext;
      if (!pattern_path.empty()) pattern_ext = require_extension(pattern_path, {".svg", ".json"}, "pattern type", "--pattern");
      if (out_path == "-" && json_out) {
        throw Error(ErrorCode::invalid_input, model_path, "--json", "cannot print a summary when the model itself goes to standard output");
      }
      const MeshImport imported = import_mesh_file(model_path, request, model_path);
      const ImportResult& r = imported.voxels;
      const std::optional<SilhouetteFaces>& faces = imported.faces;
      const Pattern& p = imported.pattern;
      const PopupReport report = check_popup(p);
      write_output(out_path, [&](std::ostream& out) { out << imported.model_json; });
      if (!pattern_path.empty()) {
        write_output(pattern_path, [&](std::ostream& out) {
          if (pattern_ext == ".svg") write_pattern_svg(out, p, {true});
          else write_pattern_json(out, p);
        });
      }
      const ImportStats& s = r.stats;
      const std::vector<std::string> warnings = media_warnings(p.sheet, media);
      const double sheet_w = p.sheet.max.x_mm - p.sheet.min.x_mm, sheet_h = p.sheet.max.v_mm - p.sheet.min.v_mm;
      const double closed_h = std::max(p.sheet.max.v_mm, -p.sheet.min.v_mm);
      if (json_out) {
        json j = report_json(out_path, p, report);
        j["sheet_mm"] = {{"width", sheet_w}, {"height", sheet_h}};
        j["closed_mm"] = {{"width", sheet_w}, {"height", closed_h}};
        j["warnings"] = warnings;
        j["mesh"] = {{"triangles", s.triangles}, {"degenerate", s.degenerate}};
        j["grid"] = {{"width", r.grid.width}, {"depth", r.grid.depth}, {"height", r.grid.height}, {"voxel_mm", r.grid.voxel_mm}};
        j["cells_filled"] = s.cells_filled;
        j["windows_added"] = s.windows_added;
        j["windows_rejected"] = s.windows_rejected;
        j["tops_dropped"] = s.tops_dropped;
        j["tops_kept"] = s.tops_kept;
        j["timings_ms"] = {{"read", r.timings.read_ms}, {"sampling", r.timings.sample_ms}, {"morphology", r.timings.morphology_ms},
                           {"filling", r.timings.fill_ms}, {"windows", r.timings.windows_ms}, {"thin_tops", r.timings.thin_ms}};
        if (!pattern_path.empty()) j["pattern"] = pattern_path;
        if (faces) {
          const SilhouetteComparison& c = faces->comparison;
          j["faces"] = {{"outlines_redrawn", c.outlines}, {"outlines_kept", c.outlines_kept}, {"fell_back", c.fell_back}, {"steps_kept", c.steps_kept}, {"voxel_lines", c.voxel_lines},
                        {"face_lines", c.face_lines}, {"samples", c.samples},
                        {"voxel_mean_mm", c.voxel_mean_mm}, {"face_mean_mm", c.face_mean_mm},
                        {"voxel_max_mm", c.voxel_max_mm}, {"face_max_mm", c.face_max_mm}};
        }
        print_json(j);
      } else {
        std::ostream& out = out_path == "-" ? std::cerr : std::cout;
        out << model_path << ": " << s.triangles << " triangles" << (s.degenerate ? " (" + std::to_string(s.degenerate) + " of zero area dropped)" : "")
            << " -> " << r.grid.width << " x " << r.grid.depth << " x " << r.grid.height << " voxels of " << r.grid.voxel_mm
            << " mm; filled " << s.cells_filled << " cells; windows: " << s.windows_added << " added, " << s.windows_rejected
            << " rejected";
        if (import_opt.thin_top_voxels > 0) out << "; thin tops: " << s.tops_dropped << " dropped, " << s.tops_kept << " kept";
        out << "; sheet " << mm(sheet_w) << " x " << mm(sheet_h) << " mm (closed " << mm(sheet_w) << " x " << mm(closed_h) << ")";
        out << "; wrote " << out_path << (pattern_path.empty() ? "" : " and " + pattern_path) << "\n";
        for (const std::string& w : warnings) std::cerr << "popcut: warning: " << model_path << ": " << w << "\n";
        if (faces) {
          const SilhouetteComparison& c = faces->comparison;
          out << "faces: " << c.outlines << " outlines follow the silhouette (" << c.outlines_kept << " kept in steps, " << c.steps_kept
              << " single steps kept" << (c.fell_back ? "; the redrawn model failed its check: voxel outlines written" : "") << "); lines "
              << c.voxel_lines << " (voxels) -> " << c.face_lines << " (faces); distance to the silhouette, mean "
              << mm(c.voxel_mean_mm) << " -> " << mm(c.face_mean_mm) << " mm, max " << mm(c.voxel_max_mm) << " -> "
              << mm(c.face_max_mm) << " mm over " << c.samples << " samples\n";
        }
        print_report(out, out_path, p, report);
      }
      return report.pops_up() ? kOk : kDoesNotPopUp;
    });
  }
  return kBadInput;
}

}  // namespace popcut::cli
