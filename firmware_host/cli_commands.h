// The popcut command-line tool: subcommands and their documented exit codes.
#pragma once

namespace popcut::cli {

// Exit codes (README.md): stable for scripts and CI.
enum ExitCode : int {
  kOk = 0,
  kDoesNotPopUp = 1,   // validate/repair: the card would not stand or has loose pieces
  kBadInput = 2,       // unreadable or invalid input, or a bad command line
  kCannotWrite = 3,    // an output file could not be written
  kInternal = 4,       // a bug in popcut
};

int run(int argc, char** argv);

}  // namespace popcut::cli
