// The plan and cut subcommands: stroke planning, HP-GL and sending to a cutter (or the simulator).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "cli/cut_device.h"
#include "cli/read_as.h"

namespace popcut::cli {

struct CutCommands {
  CLI::App* plan = nullptr;
  CLI::App* cut = nullptr;
  std::string model_path, profile_path, out_path, report_path, device, out_dir;  // device empty: the profile's
  ReadAs read_as;
  std::string material;  // configs/materials/NAME.toml; empty: the profile's own forces and speeds
  bool json_out = false, no_progress = false;
  SimFaultArgs faults;
  long resume_from = 1;
  int copies = 1;       // cards nested on the one sheet
  double gap_mm = 5.0;  // between them
};

// Adds `plan` and `cut` to the app; `state` receives the parsed options.
void add_cut_commands(CLI::App& app, CutCommands& state);

// Runs whichever of the two was chosen; nullopt when neither was.
std::optional<int> run_cut_commands(const CutCommands& state);

}  // namespace popcut::cli
