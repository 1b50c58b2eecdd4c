// The popcut command line: every subcommand, registered from one table of command groups.
#pragma once

namespace popcut::cli {

// Parses the command line, runs the chosen subcommand and returns its exit code (cli/common.h).
int run(int argc, char** argv);

}  // namespace popcut::cli
