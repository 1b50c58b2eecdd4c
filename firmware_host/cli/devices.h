// popcut devices: the cutters attached (serial ports, USB devices a profile names), and the media of every profile.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <vector>

#include "popcut/mesh/import_request.h"

namespace popcut::cli {

struct DevicesCommand {
  CLI::App* app = nullptr;
  bool json_out = false;
  bool all_usb = false;
};

void add_devices_command(CLI::App& app, DevicesCommand& state);

// Runs devices if it was chosen; nullopt when it was not.
std::optional<int> run_devices_command(const DevicesCommand& state);

// The media of every device profile in configs/devices, named by the file's stem (sim,
// graphtec-ce); none when no configs/ is found. A profile that does not load is left out here and
// reported where it is used.
std::vector<NamedMedia> profile_media();

}  // namespace popcut::cli
