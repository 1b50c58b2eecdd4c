// The pacers: XON/XOFF with status probes, ESC.B free-space credit with backoff, time pacing by the motion model.
#include "send/pacer.h"

#include <algorithm>
#include <string>

#include "send/waits.h"

namespace popcut::drivers::send {
namespace {

// The line or the OS holds popcut off (RTS/CTS, DTR/DSR, XON/XOFF in the OS, USB NAKs, a file).
class Unpaced final : public Pacer {
 public:
  bool pace(std::size_t&, std::size_t) override { return true; }
};

// XON/XOFF read by popcut (the simulator): wait for XON while the device holds us off.
class XonXoffPacer final : public Pacer {
 public:
  explicit XonXoffPacer(const PacerParts& parts) : session_(parts.session), channel_(parts.channel) {}

  bool pace(std::size_t&, std::size_t) override {
    const SendOptions& o = session_.options;
    // Take what the device said so far.
    if (!channel_.take_replies(std::chrono::milliseconds(0))) return false;
    std::chrono::milliseconds held{0}, next_probe = o.timeout;
    while (channel_.paused()) {
      if (session_.at_boundary_and_cancelled()) return true;  // no need to wait for XON to stop
      // A device answers device control even while it holds us off (it bypasses the buffer):
      // asked every timeout_ms, silence means it has stopped, not that it is busy cutting.
      if (session_.query != DrainQuery::none && held >= next_probe) {
        next_probe += o.timeout;
        if (channel_.nothing_pending() && !channel_.send_query(session_.query)) return false;
        if (!channel_.nothing_pending() &&
            !channel_.await_answers(0, channel_.newest_pending(), "while it held popcut off (XOFF)")) {
          return false;
        }
        continue;
      }
      if (held >= o.hold_timeout) {
        session_.result.status = {TransportError::timeout, 0,
                                  "the device held popcut off (XOFF) for " + duration_text(o.hold_timeout) +
                                      " (hold_timeout_ms): is it paused, out of media or stuck?"};
        return false;
      }
      if (!channel_.take_replies(kSlice)) return false;
      held += kSlice;
    }
    return true;
  }

 private:
  SendSession& session_;
  StatusChannel& channel_;
};

// ESC.B: ask for free space; poll again (letting the device work, backing off) while there is
// too little. The answer is credit for the next chunks: the device only drains meanwhile.
class EscBPacer final : public Pacer {
 public:
  explicit EscBPacer(const PacerParts& parts)
      : session_(parts.session), channel_(parts.channel), accounting_(parts.accounting) {}

  bool pace(std::size_t& n, std::size_t chunk) override {
    if (credit_ >= n) return true;
    // Time without progress: an answer with more free space than any before in this wait shows
    // the device working, and restarts the count.
    StallClock stall;
    for (int polls = 0;; ++polls) {
      if (!channel_.ask(DrainQuery::esc_b, "while sending")) return false;
      // Cancelled while waiting for the answer: finish the command in flight without it (the
      // abort that follows discards what the device holds).
      if (channel_.query_skipped() && session_.cancel_requested()) {
        const std::size_t sent = session_.result.bytes_sent;
        n = std::max<std::size_t>(1, session_.job.command_boundary_at_or_after(sent) - sent);
        return true;
      }
      ++session_.result.buffer_queries;
      const long answer = channel_.last_answer();
      credit_ = static_cast<std::size_t>(std::max(0L, answer));
      if (credit_ >= n) break;
      stall.answered(answer);
      // Enough to be worth a write: half a chunk, or half of the most the device ever said
      // was free when its buffer is smaller than the profile says (a 64-byte buffer holding
      // part of a long command never reports half of a 1024-byte profile's chunk).
      const std::size_t largest_free = accounting_.largest_free();
      const std::size_t worth =
          std::max<std::size_t>(1, largest_free > 0 ? std::min(chunk, largest_free) / 2 : chunk / 2);
      if (credit_ >= worth) {
        n = credit_;
        break;
      }
      if (session_.at_boundary_and_cancelled()) return true;
      if (stall.stalled() > session_.options.hold_timeout) {
        session_.result.status = {
            TransportError::timeout, 0,
            "the device's buffer stayed full for " + duration_text(session_.options.hold_timeout) +
                " (hold_timeout_ms) without freeing a byte, by its answers to " +
                session_.query_name(DrainQuery::esc_b) + ": is it paused, out of media or stuck?"};
        return false;
      }
      const std::chrono::milliseconds wait = poll_backoff(polls);
      if (!channel_.take_replies(wait)) return false;
      stall.waited(wait);
    }
    return true;
  }

  void written(std::size_t bytes) override { credit_ -= std::min(credit_, bytes); }

 private:
  SendSession& session_;
  StatusChannel& channel_;
  const SendAccounting& accounting_;
  std::size_t credit_ = 0;  // bytes the device last said it could take, less those sent since
};

// The longest command of the job, in bytes.
std::size_t longest_command(const EncodedJob& job) {
  std::size_t longest = 0, start = 0;
  for (const std::size_t end : job.command_end) {
    longest = std::max(longest, end - std::min(end, start));
    start = end;
  }
  return longest;
}

// Paced by the motion model. No handshake at all: keep at most half a buffer more than the
// modelled device has read. Half: a device may free a command's bytes only when it ends it, not
// when it starts it. Status flow, where answers correct the model: the whole buffer less the
// longest command (held until it ends), never less than half, so that the device is kept fed.
class TimePacer final : public Pacer {
 public:
  explicit TimePacer(const PacerParts& parts)
      : session_(parts.session),
        channel_(parts.channel),
        tracker_(parts.tracker),
        longest_(parts.session.flow == FlowControl::status ? longest_command(parts.session.job) : 0) {}

  bool pace(std::size_t& n, std::size_t) override {
    const SendOptions& o = session_.options;
    Transport& t = session_.transport;
    const std::size_t sent = session_.result.bytes_sent;
    const std::size_t ahead_bytes = std::max<std::size_t>(
        1, session_.flow == FlowControl::status ? o.buffer_bytes - std::min(o.buffer_bytes / 2, longest_)
                                                : o.buffer_bytes / 2);
    const auto began = t.now();
    for (;;) {
      const std::size_t read_bytes = advance_by_line(tracker_, t, sent);
      if (sent + n <= read_bytes + ahead_bytes || session_.cancel_requested()) break;
      // A single command longer than `ahead_bytes` that the device cannot start until it is all
      // there: it holds only what it waits for, so what it lacks goes.
      if (tracker_.needs() > sent) {
        n = std::min(n, tracker_.needs() - sent);
        break;
      }
      // A device that answers says where it is (SendAccounting::learn): ESC.O when it has caught
      // up (bit 3, buffer empty), ESC.B how much it still holds. Asked while held back, every kSlice.
      if (session_.query != DrainQuery::none && channel_.nothing_pending() && t.now() - asked_idle_at_ >= kSlice) {
        asked_idle_at_ = t.now();
        if (!channel_.ask(session_.query, "while pacing")) return false;
        continue;
      }
      if (!channel_.check_overdue()) return false;
      // Answers that keep the model where it is show a device that does not move.
      if (session_.query != DrainQuery::none && t.now() - began > o.hold_timeout) {
        session_.result.status = {TransportError::timeout, 0,
                                  "the device's answers to " + session_.query_name(session_.query) +
                                      " showed no progress for " + duration_text(o.hold_timeout) +
                                      " (hold_timeout_ms): is it paused, out of media or stuck?"};
        return false;
      }
      // When the model reads far enough, at its (slowed) pace.
      const std::size_t target_bytes = sent + n - ahead_bytes;
      const double at_s = tracker_.time_past(target_bytes - 1);  // target_bytes > read_bytes >= 0
      const auto wait = std::chrono::milliseconds(
          1 + static_cast<long>(std::max(0.0, at_s - tracker_.seconds()) * tracker_.slowdown() * 1000));
      if (!channel_.take_replies(std::min(kSlice, wait))) return false;
    }
    return true;
  }

 private:
  SendSession& session_;
  StatusChannel& channel_;
  MotionTracker& tracker_;
  std::size_t longest_;                                    // status flow: the job's longest command
  std::chrono::steady_clock::time_point asked_idle_at_{};  // last query while held back
};

}  // namespace

std::unique_ptr<Pacer> make_pacer(const PacerParts& parts) {
  if (parts.session.flow == FlowControl::xon_xoff) return std::make_unique<XonXoffPacer>(parts);
  if (parts.session.time_paced()) return std::make_unique<TimePacer>(parts);
  if (parts.session.flow == FlowControl::esc_b) return std::make_unique<EscBPacer>(parts);
  return std::make_unique<Unpaced>();
}

}  // namespace popcut::drivers::send
