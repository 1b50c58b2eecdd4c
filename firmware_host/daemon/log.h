// popcutd's log: one line per event on standard error (journald adds the time under systemd).
#pragma once

#include <iostream>
#include <mutex>
#include <sstream>

namespace popcut::daemon {

// Writes the streamed parts as one line; lines from threads never interleave.
template <typename... Parts>
void log_line(const Parts&... parts) {
  std::ostringstream o;
  o << "popcutd: ";
  (o << ... << parts);
  o << "\n";
  static std::mutex m;
  std::lock_guard lock(m);
  std::cerr << o.str() << std::flush;
}

}  // namespace popcut::daemon
