// How the sender keeps the device's buffer from overflowing: one pacer per flow-control strategy behind one interface.
#pragma once

#include <cstddef>
#include <memory>

#include "send/accounting.h"
#include "send/motion_tracker.h"
#include "send/session.h"
#include "send/status_channel.h"

namespace popcut::drivers::send {

class Pacer {
 public:
  virtual ~Pacer() = default;
  // Waits until `n` job bytes (of a chunk of `chunk`) may go out; may shrink n. False with the
  // session's status set.
  virtual bool pace(std::size_t& n, std::size_t chunk) = 0;
  // The transport took `bytes` more job bytes.
  virtual void written(std::size_t bytes) { (void)bytes; }
};

// What the pacers work with.
struct PacerParts {
  SendSession& session;
  StatusChannel& channel;
  const SendAccounting& accounting;
  MotionTracker& tracker;
};

// By the session's flow: XON/XOFF read by popcut, ESC.B free space, time (no handshake on a line
// that cannot hold popcut off), else none (the line or the OS holds popcut off by itself).
std::unique_ptr<Pacer> make_pacer(const PacerParts& parts);

}  // namespace popcut::drivers::send
