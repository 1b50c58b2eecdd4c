// The write loop through a line the device may hold, with the job's and the abort's hold policies.
#include "send/held_line.h"

#include <algorithm>
#include <cstdint>
#include <span>

#include "send/waits.h"

namespace popcut::drivers::send {
namespace {

std::span<const std::uint8_t> bytes_of(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

}  // namespace

Held write_through_holds(Transport& transport, std::chrono::milliseconds timeout, const HeldWrite& write,
                         TransportStatus& status) {
  const bool held_line = transport.backpressure();
  const auto slice = held_line ? std::min(timeout, std::chrono::milliseconds(250)) : timeout;
  const std::string_view bytes = write.bytes;
  HeldSlice at;
  for (;;) {
    if (at.done == bytes.size() && !write.until_out) return Held::written;
    // Bytes the port took may still wait in its queue for the device to let them out.
    TransportStatus st;
    std::size_t moved = 0;
    if (at.done < bytes.size()) {
      IoResult w = transport.write(bytes_of(bytes.substr(at.done)), slice);
      moved = w.bytes;
      at.done += moved;
      if (write.taken) write.taken(moved);
      st = std::move(w.status);
    } else {
      st = transport.drain(slice);
    }
    if (at.done == bytes.size() && (st.ok() || !write.until_out))
      return Held::written;  // all of it queued for the line
    if (st.ok()) continue;
    if (st.error != TransportError::timeout || !held_line) {
      status = st;
      return Held::failed;
    }
    // A slice without a byte taken: the device holds the line.
    at.new_hold = moved == 0 && at.held.count() == 0;
    at.held = moved > 0 ? std::chrono::milliseconds(0) : at.held + slice;
    at.waited += slice;
    at.status = &st;
    if (const Held h = write.on_held(at); h != Held::written) return h;
  }
}

Held HeldLine::write(std::string_view bytes, const std::function<void(std::size_t)>& taken,
                     const std::function<bool(std::size_t)>& may_stop) {
  const SendOptions& o = session_.options;
  const auto on_held = [&](const HeldSlice& s) {
    if (s.new_hold) ++slice_holds_;  // counted once per hold, where the transport does not count them itself
    if (s.held >= o.hold_timeout) {
      session_.result.status = {TransportError::timeout, s.status->os_error,
                                "the device held popcut off for " + duration_text(o.hold_timeout) +
                                    " without taking a byte (hold_timeout_ms): is it paused, out of media or stuck? (" +
                                    s.status->message + ")"};
      return Held::failed;
    }
    if (session_.cancel_requested()) {
      if (may_stop(s.done)) return Held::stopped;
      if (session_.given_up_while_held()) return Held::failed;  // inside a command: no abort can follow
    }
    return take_replies_ && !take_replies_() ? Held::failed : Held::written;
  };
  return write_through_holds(session_.transport, o.timeout, {bytes, false, taken, on_held}, session_.result.status);
}

bool HeldLine::write_abort(std::string_view bytes) {
  const SendOptions& o = session_.options;
  const auto limit = session_.transport.backpressure() ? std::max(o.timeout, o.hold_timeout) : o.timeout;
  std::size_t done = 0;
  const auto taken = [&](std::size_t k) { done += k; };
  const auto on_held = [&](const HeldSlice& s) {
    if (session_.given_up_while_held()) return Held::failed;
    if (s.waited >= limit) {
      session_.result.status = {TransportError::timeout, s.status->os_error,
                                "the device held the line for " + duration_text(limit) +
                                    " (hold_timeout_ms) and did not take the abort sequence: " + s.status->message};
      return Held::failed;
    }
    return Held::written;
  };
  write_through_holds(session_.transport, o.timeout, {bytes, true, taken, on_held}, session_.result.status);
  return session_.result.status.ok() && done == bytes.size();
}

}  // namespace popcut::drivers::send
