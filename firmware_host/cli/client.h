// popcut submit / jobs / move / cancel / resume / pause / continue / sheet: the command-line client of popcutd's HTTP
// API.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/read_as.h"

namespace popcut::cli {

struct ClientCommands {
  CLI::App* submit = nullptr;
  CLI::App* jobs = nullptr;
  CLI::App* cancel = nullptr;
  CLI::App* resume = nullptr;
  CLI::App* move = nullptr;
  CLI::App* sheet = nullptr;
  CLI::App* pause = nullptr;
  CLI::App* continue_cmd = nullptr;
  std::string server, token, model_path, device, profile, name, material;
  std::string idempotency_key;                                     // submit: "" sends a new UUID
  int copies = 1;                                                  // submit --copies
  std::string states, filter_device, since;                        // jobs' filters
  int priority = 0;                                                // move --priority
  long long before_id = 0;                                         // move --before
  std::string sheet_device;                                        // sheet NAME
  std::string resume_from = "received";                            // resume --from: received or executed
  std::vector<std::pair<std::string, std::string>> import_values;  // popcut import's options, for a mesh
  long long job_id = 0;
  ReadAs read_as;  // submit: how a drawing is read
  bool json_out = false, wait = false, all = false;
};

void add_client_commands(CLI::App& app, ClientCommands& state);

// Runs whichever was chosen; nullopt when none was. Exit codes: 0 ok; 2 the daemon refused the
// request (4xx: bad model, unknown id or device, bad token ...) or bad usage; 3 the daemon could
// not be reached, was full (503), or with --wait the job ended other than done; 4 internal (5xx).
std::optional<int> run_client_commands(const ClientCommands& state);

}  // namespace popcut::cli
