// popcut calibrate: cut a frame, take the lengths measured on it, write the axis and timing correction to an overlay.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "cli/cut_device.h"

namespace popcut::cli {

struct CalibrateCommand {
  CLI::App* app = nullptr;
  std::string profile_path, device, overlay_path, out_dir;
  double width_mm = 100, height_mm = 150;
  double measured_x_mm = 0, measured_y_mm = 0, measured_diagonal_mm = 0;  // given when the option was
  double measured_time_s = 0;
  bool no_cut = false, json_out = false, no_progress = false;
  SimFaultArgs faults;
};

void add_calibrate_command(CLI::App& app, CalibrateCommand& state);

// Runs calibrate if it was chosen; nullopt when it was not.
std::optional<int> run_calibrate_command(const CalibrateCommand& state);

}  // namespace popcut::cli
