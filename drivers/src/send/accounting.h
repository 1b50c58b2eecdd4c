// Send accounting: what the device can be shown to have received, executed and still hold (E <= M <= N), never
// over-claimed.
#pragma once

#include <cstddef>

#include "send/motion_tracker.h"
#include "send/session.h"
#include "send/status_channel.h"

namespace popcut::drivers::send {

// The last stroke the first `bytes` (taken out of the device's buffer) have certainly cut: its
// commands and the one after it have left the buffer, so its last move has ended (a device
// starts a command when the one before is done).
std::size_t stroke_executed_by(const EncodedJob& job, std::size_t bytes);
// The last stroke the first `bytes` may cut: the last complete one, or the next one when its
// knife went down (a cancel stops it at a command boundary).
std::size_t stroke_touched_by(const EncodedJob& job, std::size_t bytes);

class SendAccounting {
 public:
  explicit SendAccounting(SendSession& session) : session_(session) {}

  // What an answer tells about execution, and so where the device is. ESC.B: the bytes written
  // before the query, less what its buffer still holds (its size less the free space), have
  // left the buffer. Its size is the profile's or the largest free space it ever reported, if
  // larger (asked before the job, an idle device reports all of it): a profile that understates
  // the buffer must not make popcut think more has been executed. An answer its language reads
  // as idle (ESC.O bit 3, GP-GL "ready"): everything written before it has been executed.
  Whereabouts learn(const Answer& answer);

  // The result's counts from what is known now: bytes and strokes received, written, executed.
  // `answers`: status answers heard so far.
  void settle(int answers);

  // The device's buffer at its largest: the profile's size, or more if the device ever said it
  // had more free. What it holds is never less than this size less its free space, so what it
  // executed is never over-claimed (a profile overstating the buffer under-claims it).
  std::size_t device_buffer() const;
  std::size_t largest_free() const { return largest_free_; }
  std::size_t executed() const { return executed_; }

  // The job went out whole and the device finished it.
  void drained() { drained_ = true; }
  // A cancel or failure: counts are final and must assume the worst.
  void ended_badly() { ended_badly_ = true; }
  // An abort that makes the device drop its buffer is going out or went (false: it did not, or
  // the device kept its buffer after all).
  void set_discarding(bool discarding) { discarding_ = discarding; }
  bool discarding() const { return discarding_; }

  // After a cancel or failure, what the device may still cut: its buffer plus `on_the_way`, at
  // most what was sent (an upper bound).
  void bound_buffered(std::size_t on_the_way);
  // Its ESC.B answer after the cancel (`free_answer` free bytes): what it holds, less the
  // knife-up the abort put there; exact when its buffer's size is known.
  void measured_buffered(long free_answer);
  // The strokes that buffered_bytes carry.
  void buffered_strokes();

 private:
  // What the device can be shown to have received: what it took, where the transport's count
  // says so; else its answers where it is asked; else what the port says has left (written,
  // less its OS queue and what may still be in flight).
  std::size_t received() const;

  SendSession& session_;
  std::size_t confirmed_ = 0;     // job bytes written before the last answered query
  std::size_t executed_ = 0;      // job bytes the device has been seen to take out of its buffer and start
  std::size_t largest_free_ = 0;  // the most free space ESC.B ever reported
  bool drained_ = false;
  bool ended_badly_ = false;
  bool discarding_ = false;
};

}  // namespace popcut::drivers::send
