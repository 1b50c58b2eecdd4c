// Streams a job to a Transport, pacing it by the profile's flow control, with progress callbacks.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string_view>

#include "popcut/drivers/profile.h"
#include "popcut/drivers/transport.h"

namespace popcut::drivers {

struct SendOptions {
  FlowControl flow = FlowControl::none;
  std::size_t buffer_bytes = 1024;  // the device's buffer: chunks stay well inside it
  std::chrono::milliseconds timeout{5000};  // for one write or one reply
  // How long the device may hold us off (XOFF, or a full buffer under ESC.B) while it cuts: a
  // full buffer can take minutes of motion to drain.
  std::chrono::milliseconds hold_timeout{120000};
  std::function<void(std::size_t sent, std::size_t total)> progress;  // after every chunk
};

struct SendResult {
  std::size_t bytes_sent = 0;
  int xoff_pauses = 0;     // times the device said XOFF and we waited for XON
  int buffer_queries = 0;  // ESC.B round trips
  TransportStatus status;
};

SendOptions send_options(const DeviceProfile& profile);

// Writes `job`; stops at the first transport error (reported with the bytes that got through).
SendResult send_job(Transport& transport, std::string_view job, const SendOptions& options);

}  // namespace popcut::drivers
