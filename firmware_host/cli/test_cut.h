// popcut test-cut: the square-in-triangle test at a chosen spot, through the planner and the device's cut path.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "cli/cut_device.h"

namespace popcut::cli {

struct TestCutCommand {
  CLI::App* app = nullptr;
  std::string profile_path, device, material, at, out_dir;
  double square_mm = 10;
  bool json_out = false, no_progress = false;
  SimFaultArgs faults;
};

void add_test_cut_command(CLI::App& app, TestCutCommand& state);

// Runs test-cut if it was chosen; nullopt when it was not.
std::optional<int> run_test_cut_command(const TestCutCommand& state);

}  // namespace popcut::cli
