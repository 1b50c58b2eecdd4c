// popcut fold / render: the card folded to an angle, as a 3D model or as a picture (or an opening animation).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cli/read_as.h"

namespace popcut::cli {

struct FoldCommands {
  CLI::App* fold = nullptr;
  CLI::App* render = nullptr;
  std::string model_path, out_path;
  double angle_deg = 90;
  double at = 1;       // --as sheet: the share of the motion from flat (0) to folded (1)
  int frames = 1;      // render --frames
  int width_px = 800;  // render --width
  ReadAs read_as;
};

// The sheet folded to `fraction` of its motion; cycles that cannot close are warned about on
// stderr, each once over the frames that share `warned`.
// `layer_gap_mm` as sheet_mesh takes it (pictures only).
CardMesh folded_sheet(const FoldableSheet& sheet, double fraction, std::set<std::vector<int>>* warned = nullptr,
                      double layer_gap_mm = 0);

// Writes OUT.obj (and OUT.mtl) or OUT.gltf, by the extension (else exit 2 naming -o); returns what
// was written, for the "wrote" line.
std::string write_folded_mesh(const std::string& out_path, const CardMesh& mesh);

// Adds fold and render to the app; `state` receives the parsed options.
void add_fold_commands(CLI::App& app, FoldCommands& state);

// Runs whichever of the two was chosen; nullopt when neither was.
std::optional<int> run_fold_commands(const FoldCommands& state);

}  // namespace popcut::cli
