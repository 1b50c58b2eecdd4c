// The popcut command-line tool: subcommands and their documented exit codes.
#pragma once

#include <functional>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "popcut/mesh/import_request.h"
#include "popcut/pattern/pattern.h"

namespace CLI {
class App;
}

namespace popcut::cli {

// Exit codes (README.md): stable for scripts and CI.
enum ExitCode : int {
  kOk = 0,
  kDoesNotPopUp = 1,   // validate/repair: the card would not stand or has loose pieces
  kBadInput = 2,       // unreadable or invalid input, or a bad command line
  kCannotWrite = 3,    // an output file could not be written; cut: the job did not reach the cutter
  kInternal = 4,       // a bug in popcut
  kCancelled = 130,    // cut: stopped by Ctrl-C or SIGTERM (the shell's code for SIGINT)
};

int run(int argc, char** argv);

// Shared by the command files (cli_commands.cpp, cli_cut.cpp).

// Runs a command body, turning popcut errors into messages (and JSON with --json) and exit codes.
int run_guarded(bool json_errors, const std::function<int()>& body);
// The pattern of a model file, as every command loads it ("-" is standard input).
Pattern load_cli_pattern(const std::string& model_path);
// Writes an output file atomically; failures exit with kCannotWrite.
void write_cli_output(const std::string& path, const std::function<void(std::ostream&)>& content);
void print_json_line(const nlohmann::json& j);
// popcut import's mesh options (kImportOptionNames as --flags) on `cmd`; each one given is added to
// `values` for parse_import_options. Shared by import and submit.
void add_import_options(CLI::App* cmd, std::vector<std::pair<std::string, std::string>>& values);
// The media of every device profile in configs/devices (cli_devices.cpp), named by the file's
// stem (sim, graphtec-ce); none when no configs/ is found. A profile that does not load is left
// out here and reported where it is used.
std::vector<NamedMedia> profile_media();

}  // namespace popcut::cli
