// Send accounting: received, executed and buffered counts from the transport's counts and the device's answers.
#include "send/accounting.h"

#include <algorithm>
#include <string>

namespace popcut::drivers::send {

std::size_t stroke_executed_by(const EncodedJob& job, std::size_t bytes) {
  const std::size_t s = job.last_stroke_within(bytes);
  if (s < job.first_stroke) return s;
  const std::size_t next_end = job.command_boundary_at_or_after(job.stroke_end[s - job.first_stroke] + 1);
  return next_end > bytes ? s - 1 : s;
}

std::size_t stroke_touched_by(const EncodedJob& job, std::size_t bytes) {
  const std::size_t done = job.last_stroke_within(bytes);
  const std::size_t last = job.first_stroke + job.stroke_end.size() - 1;
  const std::size_t done_end = done >= job.first_stroke ? job.stroke_end[done - job.first_stroke] : 0;
  // The next stroke is touched once its knife-down command went out: its travel and tool
  // set-up before that cut nothing. A job with no such record (raw bytes): from its end.
  const std::size_t next = done + 1 - job.first_stroke;
  const std::size_t knife_down = next < job.stroke_cut_start.size() ? job.stroke_cut_start[next] : done_end;
  return done < last && bytes > knife_down ? done + 1 : done;
}

std::size_t SendAccounting::device_buffer() const { return std::max(session_.options.buffer_bytes, largest_free_); }

Whereabouts SendAccounting::learn(const Answer& asked) {
  confirmed_ = std::max(confirmed_, asked.bytes_before);
  if (asked.query == DrainQuery::esc_b) {
    if (asked.value < 0) return {};
    const auto free_bytes = static_cast<std::size_t>(asked.value);
    largest_free_ = std::max(largest_free_, free_bytes);
    const std::size_t held = device_buffer() - free_bytes;
    const std::size_t left_buffer = asked.bytes_before - std::min(held, asked.bytes_before);
    executed_ = std::max(executed_, left_buffer);
    return {Whereabouts::Kind::at, left_buffer};
  }
  const StatusMeaning said = session_.host.meaning(asked.query, asked.value);
  if (said == StatusMeaning::idle) {
    executed_ = std::max(executed_, asked.bytes_before);
    return {Whereabouts::Kind::at_least, asked.bytes_before};
  }
  // Status flow trusts the model only as far as the answers allow.
  if (said == StatusMeaning::busy && session_.flow == FlowControl::status) {
    return {Whereabouts::Kind::before, asked.bytes_before};
  }
  return {};
}

std::size_t SendAccounting::received() const {
  const SendResult& r = session_.result;
  Transport& t = session_.transport;
  // Drained: everything arrived, whatever the port's own counts still hold back as unseen.
  if (drained_) return r.bytes_sent;
  const std::size_t gone =
      t.writes_acknowledged() ? r.bytes_sent : r.bytes_sent - std::min(r.bytes_sent, t.in_flight());
  if (session_.query != DrainQuery::none)
    return t.writes_acknowledged() ? r.bytes_sent : std::min(confirmed_, r.bytes_sent);
  // No handshake and no answers: a device that stopped (paused, stuck) went on taking bytes and
  // lost all that found its buffer full, and nothing tells when it stopped. Only its buffer's
  // worth from the start is certainly in it. While all goes well (progress) it is what left.
  if (session_.time_paced() && ended_badly_) return std::min(gone, session_.options.buffer_bytes);
  return gone;
}

void SendAccounting::settle(int answers) {
  SendResult& r = session_.result;
  const EncodedJob& job = session_.job;
  r.bytes_received = received();
  r.last_stroke_sent = job.last_stroke_within(r.bytes_received);
  r.last_stroke_written = job.last_stroke_within(r.bytes_sent);
  // Executed is known only from the device's answers (or an answered drain); it never runs
  // ahead of what it received.
  if (session_.query != DrainQuery::none && answers > 0 && r.device_io_error == 0) {
    // Drained, the device executed everything sent: a job paused after stroke K (no command of
    // the job after it) has executed K too, not only once the next command went.
    const std::size_t executed = drained_ ? job.last_stroke_within(r.bytes_sent)
                                          : stroke_executed_by(job, std::min(executed_, r.bytes_received));
    r.last_stroke_executed = std::min(executed, r.last_stroke_sent);
  } else {  // unknown: no answers, or lost bytes made what it executed something else than the job
    r.last_stroke_executed.reset();
  }
  r.received_before_abort = r.last_stroke_sent;
  if (discarding_) {
    // The abort makes the device drop its buffer: of what it received, only what it executed
    // is cut, and the rest must be sent again (strokes E+1..N may have been cut already).
    const std::size_t none = job.first_stroke - 1;
    const std::size_t e = std::min(r.last_stroke_executed.value_or(none), r.last_stroke_sent);
    r.last_stroke_sent = e;
    r.bytes_received = e > none ? std::min(r.bytes_received, job.stroke_end[e - job.first_stroke]) : 0;
  }
}

void SendAccounting::bound_buffered(std::size_t on_the_way) {
  SendResult& r = session_.result;
  r.buffered_bytes = std::min(r.bytes_sent, device_buffer() + on_the_way);
  r.buffer_known = false;
}

void SendAccounting::measured_buffered(long free_answer) {
  SendResult& r = session_.result;
  // Exact when the device once said its whole buffer was free (so its size is known); else an
  // upper bound: a device smaller than the profile says holds less.
  const std::size_t free_now = static_cast<std::size_t>(std::max(0L, free_answer));
  std::size_t held = device_buffer() - std::min(device_buffer(), free_now);
  // Asked after the abort: the knife-up sent with it is in the buffer too, and is no part of
  // the job (a device that honoured ESC.K holds only that).
  if (r.abort_sent) held -= std::min(held, session_.host.buffered_bytes(session_.options.abort_bytes));
  r.buffered_bytes = std::min(r.bytes_sent, held);
  r.buffer_known = largest_free_ >= device_buffer();
}

void SendAccounting::buffered_strokes() {
  SendResult& r = session_.result;
  const EncodedJob& job = session_.job;
  r.buffered_first_stroke = job.last_stroke_within(r.bytes_sent - r.buffered_bytes) + 1;
  // Nothing after the last stroke known executed is known cut: the range starts no later.
  if (r.last_stroke_executed) r.buffered_first_stroke = std::min(r.buffered_first_stroke, *r.last_stroke_executed + 1);
  r.buffered_last_stroke = stroke_touched_by(job, r.bytes_sent);
  if (r.buffered_bytes == 0) r.buffered_first_stroke = r.buffered_last_stroke + 1;
}

}  // namespace popcut::drivers::send
