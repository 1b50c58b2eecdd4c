// popcut fold / render: fold a model's card to an angle and write it as OBJ/glTF, or draw it as SVG/PNG frames.
#include "cli/fold.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

#include "cli/common.h"
#include "popcut/fold/fold.h"
#include "popcut/fold/render.h"
#include "popcut/io/mesh_io.h"
#include "popcut/text.h"

namespace popcut::cli {
namespace {

// Layers folded flat lie in one plane; pictures set them this far apart (a tenth of a pixel at
// the default width for a card-sized sheet) so the top one shows instead of a speckle of both.
constexpr double kPictureLayerGapMm = 0.02;

// The --angle after its range check; "-0" is 0, and says so.
double checked_angle(double angle_deg) {
  check_fold_angle(angle_deg, "--angle");
  return angle_deg + 0.0;
}

// A card opens to --angle; a sheet's creases each have their own, so --angle would mislead.
void refuse_angle_for_sheet(const FoldCommands& s, const CLI::App* command) {
  check_read_as(s.read_as);
  if (s.read_as.sheet() && command->count("--angle") > 0)
    throw CliError(kBadInput, ErrorCode::invalid_input, "", "--angle",
                   "--angle opens a card; a sheet's creases turn by --crease-angle, --fold LINE=DEGREES or the "
                   "drawing's own angles (FOLD edges_foldAngle)");
  if (!s.read_as.sheet() && command->count("--at") > 0)
    throw CliError(kBadInput, ErrorCode::invalid_input, "", "--at",
                   "--at is how far a sheet's motion has gone (--as sheet); a card opens to --angle");
}

}  // namespace

CardMesh folded_sheet(const FoldableSheet& sheet, double fraction, std::set<std::vector<int>>* warned,
                      double layer_gap_mm) {
  const SheetState state = fold_sheet(sheet, fraction);
  for (const SheetProblem& p : state.open_cycles) {
    std::vector<int> key = p.hinges;
    std::sort(key.begin(), key.end());
    if (!warned || warned->insert(key).second) std::cerr << "popcut: warning: " << p.what << "\n";
  }
  return sheet_mesh(sheet, state, layer_gap_mm);
}

std::string write_folded_mesh(const std::string& out_path, const CardMesh& mesh) {
  const std::string ext = require_extension(out_path, {".obj", ".gltf"}, "3D format");
  if (ext == ".gltf") {
    write_cli_output(out_path, [&](std::ostream& out) { write_gltf(out, mesh); });
    return out_path;
  }
  const std::filesystem::path mtl = std::filesystem::path(out_path).replace_extension(".mtl");
  write_cli_output(out_path, [&](std::ostream& out) { write_obj(out, mesh, mtl.filename().string()); });
  write_cli_output(mtl.string(), [&](std::ostream& out) { write_mtl(out); });
  return out_path + " and " + mtl.string();
}

namespace {

int run_fold(const FoldCommands& s) {
  refuse_angle_for_sheet(s, s.fold);
  const double angle_deg = checked_angle(s.angle_deg);
  require_extension(s.out_path, {".obj", ".gltf"}, "3D format");  // before the work
  const CardMesh mesh = s.read_as.sheet() ? folded_sheet(load_cli_sheet(s.model_path, s.read_as), s.at)
                                          : fold_card(load_cli_pattern(s.model_path), angle_deg);
  std::cerr << "wrote " << write_folded_mesh(s.out_path, mesh) << " (" << mesh.triangles.size()
            << " triangles per side, folded to "
            << (!s.read_as.sheet() ? format_significant(angle_deg, 6) + "°"
                : s.at == 1        ? std::string("each crease's angle")
                                   : format_significant(100 * s.at, 4) + "% of the motion")
            << ")\n";
  return kOk;
}

// Frame i of an animation: OUT-000.svg, OUT-001.svg, ... beside OUT.
std::string frame_path(const std::filesystem::path& out, std::size_t i, const std::string& ext) {
  char suffix[24];
  std::snprintf(suffix, sizeof suffix, "-%03zu", i);
  return (out.parent_path() / (out.stem().string() + suffix + ext)).string();
}

// A card's frames open it from closed (180°) to --angle; a sheet's fold it from flat to folded.
std::vector<CardMesh> render_meshes(const FoldCommands& s, double angle_deg) {
  std::vector<CardMesh> meshes;
  const int frames = s.frames;
  if (s.read_as.sheet()) {
    const FoldableSheet sheet = load_cli_sheet(s.model_path, s.read_as);
    std::set<std::vector<int>> warned;
    for (int i = 0; i < frames; ++i)
      meshes.push_back(folded_sheet(sheet, frames == 1 ? s.at : s.at * i / (frames - 1), &warned, kPictureLayerGapMm));
    return meshes;
  }
  const Pattern p = load_cli_pattern(s.model_path);
  for (int i = 0; i < frames; ++i)
    meshes.push_back(fold_card_for_picture(p, frames == 1 ? angle_deg : 180 + (angle_deg - 180) * i / (frames - 1)));
  return meshes;
}

int run_render(const FoldCommands& s) {
  refuse_angle_for_sheet(s, s.render);
  const double angle_deg = checked_angle(s.angle_deg);  // every frame's angle lies between 180 and it
  const int frames = s.frames;
  const std::string ext = require_extension(s.out_path, {".svg", ".png"}, "picture format");
  const std::vector<CardMesh> meshes = render_meshes(s, angle_deg);
  const ViewBox box = view_box(meshes);  // one frame for every picture, so the animation holds still
  const bool progress_on_tty = ::isatty(STDERR_FILENO) != 0;
  const std::filesystem::path out(s.out_path);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const std::string path = frames > 1 ? frame_path(out, i, ext) : s.out_path;
    if (ext == ".svg") {
      const double px_per_mm = s.width_px / (box.max_x - box.min_x);
      write_cli_output(path, [&](std::ostream& o) { write_render_svg(o, meshes[i], box, px_per_mm); });
    } else {
      const std::string png = render_png(meshes[i], box, s.width_px);
      write_cli_output(path, [&](std::ostream& o) { o.write(png.data(), static_cast<std::streamsize>(png.size())); });
    }
    // A counter redrawn with \r only makes sense on a terminal; in a log it would be one long line.
    if (frames > 1 && progress_on_tty) std::cerr << "\r" << (i + 1) << "/" << frames << " frames" << std::flush;
  }
  if (frames > 1 && progress_on_tty) std::cerr << "\n";
  std::cerr << "wrote "
            << (frames > 1 ? std::to_string(frames) + " frames like " + out.stem().string() + "-000" + ext : s.out_path)
            << (s.read_as.sheet()
                    ? (s.at == 1 ? std::string(" (folded from flat)")
                                 : " (from flat to " + format_significant(100 * s.at, 4) + "% of the motion)")
                    : " (folded to " + format_significant(angle_deg, 6) + "°)")
            << "\n";
  return kOk;
}

}  // namespace

void add_fold_commands(CLI::App& app, FoldCommands& s) {
  // Numbers as people write them, in decimal: CLI11 alone would take "0x10" as 16.
  const auto decimal = [](const std::string& what, const std::string& name) {
    return CLI::Validator(
        [what](std::string& text) -> std::string {
          return is_decimal_text(text) ? std::string() : "'" + text + "' is not " + what;
        },
        name);
  };
  const CLI::Validator decimal_degrees = decimal("a number of degrees (a decimal number from 0 to 180)", "DEGREES");
  const CLI::Validator decimal_fraction =
      decimal("a fraction of the motion (a decimal number from 0 to 1)", "FRACTION");
  s.fold = app.add_subcommand("fold", "Write the card folded to an angle as a 3D model (OBJ + MTL, or glTF).");
  s.fold->add_option("MODEL", s.model_path, "Model file (voxel or face model), or - for standard input")->required();
  s.fold->add_option("--angle", s.angle_deg, "Fold angle in degrees: 0 flat, 90 standing, 180 closed")
      ->check(decimal_degrees)
      ->capture_default_str();
  s.fold->add_option("-o,--output", s.out_path, "OUT.obj (writes OUT.mtl beside it) or OUT.gltf")->required();
  add_read_as_options(s.fold, s.read_as, true);
  const auto at_help = "--as sheet: how far the motion from flat (0) to folded (1) has gone";
  s.fold->add_option("--at", s.at, at_help)
      ->check(decimal_fraction)
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();

  s.render = app.add_subcommand("render",
                                "Draw the card in a 3/4 view at a fold angle (SVG or PNG), or an opening animation.");
  s.render->add_option("MODEL", s.model_path, "Model file (voxel or face model), or - for standard input")->required();
  s.render->add_option("--angle", s.angle_deg, "Fold angle in degrees: 0 flat, 90 standing, 180 closed")
      ->check(decimal_degrees)
      ->capture_default_str();
  s.render->add_option("-o,--output", s.out_path, "OUT.svg or OUT.png; with --frames, OUT-000.svg, OUT-001.svg, ...")
      ->required();
  add_read_as_options(s.render, s.read_as, true);
  s.render->add_option("--at", s.at, std::string(at_help) + "; with --frames, where the frames end")
      ->check(decimal_fraction)
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  s.render
      ->add_option("--frames", s.frames,
                   "Frames of an opening animation from closed (180°) to --angle; --as sheet: from flat to folded "
                   "(or to --at)")
      ->check(CLI::Range(1, 360))
      ->capture_default_str();
  s.render->add_option("--width", s.width_px, "Picture width in pixels")
      ->check(CLI::Range(16, 8192))
      ->capture_default_str();
}

std::optional<int> run_fold_commands(const FoldCommands& s) {
  if (s.fold && *s.fold) return run_guarded(false, [&] { return run_fold(s); });
  if (s.render && *s.render) return run_guarded(false, [&] { return run_render(s); });
  return std::nullopt;
}

}  // namespace popcut::cli
