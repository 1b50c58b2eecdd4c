// popcut pattern / validate / repair: a model's unfolded pattern, its pop-up check, and the staircase repair.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "cli/read_as.h"

namespace popcut::cli {

struct PatternCommands {
  CLI::App* pattern = nullptr;
  CLI::App* validate = nullptr;
  CLI::App* repair = nullptr;
  std::string model_path, out_path;
  bool json_out = false;
  bool shade = false;    // pattern --shade
  bool windows = false;  // repair --windows
  int frames = 24;       // validate --as sheet: steps of the motion checked
  ReadAs read_as;
};

// Adds pattern, validate and repair to the app; `state` receives the parsed options.
void add_pattern_commands(CLI::App& app, PatternCommands& state);

// Runs whichever of the three was chosen; nullopt when none was.
std::optional<int> run_pattern_commands(const PatternCommands& state);

}  // namespace popcut::cli
