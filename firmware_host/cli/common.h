// What every popcut subcommand shares: the exit codes, the error that carries one, and loading, writing and printing.
#pragma once

#include <functional>
#include <initializer_list>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

#include "popcut/error.h"
#include "popcut/pattern/pattern.h"

namespace popcut::cli {

// Exit codes (README.md): stable for scripts and CI.
enum ExitCode : int {
  kOk = 0,
  kDoesNotPopUp = 1,  // validate/repair: the card would not stand or has loose pieces
  kBadInput = 2,      // unreadable or invalid input, or a bad command line
  kCannotWrite = 3,   // an output file could not be written; cut: the job did not reach the cutter
  kInternal = 4,      // a bug in popcut
  kCancelled = 130,   // cut: stopped by Ctrl-C or SIGTERM (the shell's code for SIGINT)
};

// An error the CLI raises itself, with the exit code it ends popcut with, chosen where it is raised.
// It prints (and goes into --json errors) as any popcut Error does.
class CliError : public Error {
 public:
  CliError(int exit_code, ErrorCode code, std::string source, std::string location, std::string message);
  int exit_code() const { return exit_code_; }

 private:
  int exit_code_;
};

// The exit code an error ends popcut with: a CliError's own (chosen where it was raised); for the
// libraries' errors kInternal for a bug and kBadInput for the rest.
int exit_code_of(const Error& error);

// Runs a command body, turning popcut errors into messages (and JSON with --json) and exit codes.
int run_guarded(bool json_errors, const std::function<int()>& body);

// The pattern of a model file, as every command loads it ("-" is standard input).
Pattern load_cli_pattern(const std::string& model_path);

// Writes an output file atomically; a failure is a CliError with kCannotWrite at location "output".
void write_cli_output(const std::string& path, const std::function<void(std::ostream&)>& content);

// One line of JSON on stdout, numbers rounded (report_json.h); text that is not UTF-8 is replaced.
void print_json_line(const nlohmann::json& j);

// The name a file goes by in messages: "-" is standard input.
std::string shown(const std::string& path);

// The output's extension, lower-case, when it is one of `allowed`; else a bad-input error naming
// `option` and `what` the extension tells ("output type").
std::string require_extension(const std::string& path, std::initializer_list<const char*> allowed, const char* what,
                              const char* option = "-o");

}  // namespace popcut::cli
