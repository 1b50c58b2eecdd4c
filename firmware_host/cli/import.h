// popcut import: a 3D mesh made into a voxel (or face) card that pops up, and the mesh options submit shares.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace popcut::cli {

// Each mesh option given, as (name without "--", text): read as text and checked by
// parse_import_options, as popcutd checks the same options of an uploaded mesh.
using ImportValues = std::vector<std::pair<std::string, std::string>>;

struct ImportCommand {
  CLI::App* app = nullptr;
  std::string mesh_path, out_path, pattern_path, model_label;
  ImportValues import_values;
  bool json_out = false;
};

// popcut import's mesh options (kImportOptionNames as --flags) on `cmd`; each one given is added to
// `values` for parse_import_options. Shared by import and submit.
void add_import_options(CLI::App* cmd, ImportValues& values);

void add_import_command(CLI::App& app, ImportCommand& state);

// Runs import if it was chosen; nullopt when it was not.
std::optional<int> run_import_command(const ImportCommand& state);

}  // namespace popcut::cli
