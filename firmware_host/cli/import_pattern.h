// popcut import-pattern: a pattern drawn elsewhere (SVG, DXF, FOLD) read as an OA card or as a folding sheet.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/read_as.h"

namespace popcut::cli {

struct ImportPatternCommand {
  CLI::App* app = nullptr;
  std::string drawing_path, out_path;
  std::vector<std::string> layers;  // NAME=KIND
  double chord_mm = 0.05, snap_mm = 0.01, unit_mm = 1;
  bool red_is_cut = false;
  bool json_out = false;
  int frames = 24;  // --as sheet: steps of the motion checked
  ReadAs read_as;
};

void add_import_pattern_command(CLI::App& app, ImportPatternCommand& state);

// Runs import-pattern if it was chosen; nullopt when it was not.
std::optional<int> run_import_pattern_command(const ImportPatternCommand& state);

}  // namespace popcut::cli
