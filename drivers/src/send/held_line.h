// Writes through a line the device may hold (XOFF or CTS in the OS, USB NAKs): job bytes, queries and the abort.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string_view>

#include "send/session.h"

namespace popcut::drivers::send {

// How a write through a line the device may hold ended.
enum class Held { written, stopped, failed };

// A write slice the device held back (a timeout on a line that can be held).
struct HeldSlice {
  std::size_t done = 0;                     // bytes of the write through so far
  bool new_hold = false;                    // the first slice of a hold: it moved no byte, the one before did
  std::chrono::milliseconds held{0};        // since the last slice that moved a byte
  std::chrono::milliseconds waited{0};      // all held slices of the write
  const TransportStatus* status = nullptr;  // the slice's timeout
};

struct HeldWrite {
  std::string_view bytes;
  bool until_out = false;                  // done only once the port has let every byte out (drain)
  std::function<void(std::size_t)> taken;  // after every write slice: the bytes it moved
  // Each held slice: written goes on waiting; stopped or failed (failed: it set the status) end it.
  std::function<Held(const HeldSlice&)> on_held;
};

// The one write loop: `write.bytes` in slices of `timeout` (at most 250 ms where the device may
// hold the line, so that a cancel is noticed). A transport error, or a timeout on a line that
// cannot be held: failed with `status` set.
Held write_through_holds(Transport& transport, std::chrono::milliseconds timeout, const HeldWrite& write,
                         TransportStatus& status);

// The sender's two uses of it.
class HeldLine {
 public:
  explicit HeldLine(SendSession& session) : session_(session) {}
  // What to do between held slices besides waiting: read what the device says (false: failed).
  void listen_with(std::function<bool()> take_replies) { take_replies_ = std::move(take_replies); }

  // Job bytes or a query: a hold is waited out up to hold_timeout (restarted by any byte that
  // moves). On a cancel meanwhile, `may_stop(done)` says whether it can stop after `done` bytes
  // (never inside a command: a half command swallows the abort), else a second interrupt may
  // give up the wait. Failed with the session's status set.
  Held write(std::string_view bytes, const std::function<void(std::size_t)>& taken,
             const std::function<bool(std::size_t)>& may_stop);
  // The abort sequence: waits for the device to let it out like any byte, up to the hold timeout
  // (at least the timeout), in slices so that the user may give up. True when it all went out.
  bool write_abort(std::string_view bytes);

  // Holds seen as write slices that moved no byte, for a transport that does not count them.
  int slice_holds() const { return slice_holds_; }

 private:
  SendSession& session_;
  std::function<bool()> take_replies_;
  int slice_holds_ = 0;
};

}  // namespace popcut::drivers::send
