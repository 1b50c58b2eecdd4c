// popcut cut's send on a terminal: a progress bar, and Ctrl-C or SIGTERM as a safe cancel.
#pragma once

#include "popcut/drivers/cut_session.h"

namespace popcut::cli {

// Sends `job` on the opened `session`. A bar on stderr shows the progress when `progress_bar` and
// stderr is a terminal. For as long as the send lasts, Ctrl-C or SIGTERM cancels it safely (the
// knife is lifted), and a second one gives up only a wait for a device that holds the line.
drivers::SendResult send_with_interrupts(drivers::CutSession& session, const EncodedJob& job,
                                         const drivers::DeviceProfile& profile, bool progress_bar);

}  // namespace popcut::cli
