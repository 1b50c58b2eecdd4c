// popcutd's command line: options, startup checks, serving until SIGTERM.
#pragma once

namespace popcut::daemon {

// Exit codes: 0 stopped by SIGTERM/SIGINT, 2 bad command line or configuration, 3 cannot bind or
// open the data directory, 4 internal error.
int run_popcutd(int argc, char** argv);

}  // namespace popcut::daemon
