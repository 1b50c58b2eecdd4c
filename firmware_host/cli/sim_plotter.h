// popcut sim-plotter: the simulated cutter behind a pseudo-terminal, a stand-in serial cutter.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "popcut/drivers/sim_cutter.h"

namespace popcut::cli {

// A simulated cutter's unknown or malformed commands for a report: each one's byte offset in what
// it received, the command and what was wrong.
nlohmann::json sim_issues_json(const std::vector<drivers::SimIssue>& issues);

struct SimPlotterCommand {
  CLI::App* app = nullptr;
  std::string profile_path, link, report_path, svg_path;
  int baud = 0;
  long buffer_bytes = 0;
  double slowdown = 1;
  long drop_after = -1, stop_after = -1;
  long tray_empty_after = -1, pause_after = -1;  // its own stops, said in its status answer (-1: never)
};

void add_sim_plotter_command(CLI::App& app, SimPlotterCommand& state);

// Runs sim-plotter if it was chosen; nullopt when it was not.
std::optional<int> run_sim_plotter_command(const SimPlotterCommand& state);

}  // namespace popcut::cli
