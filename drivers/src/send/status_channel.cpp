// Status queries and their answers: pipelined pings, round trips, the reader of the device's replies, silence and
// overdue answers.
#include "send/status_channel.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <span>
#include <thread>
#include <utility>

#include "send/waits.h"

namespace popcut::drivers::send {
namespace {

constexpr std::uint8_t kXon = 0x11;
constexpr std::uint8_t kXoff = 0x13;

std::string printable(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f)
      out += c;
    else {
      static const char kHex[] = "0123456789abcdef";
      out += std::string("\\x") + kHex[u >> 4] + kHex[u & 15];
    }
  }
  return out + "'";
}

}  // namespace

StatusChannel::StatusChannel(SendSession& session, HeldLine& line, std::function<void(const Answer&)> heard)
    : session_(session),
      line_(line),
      heard_(std::move(heard)),
      status_every_(session.options.status_every_bytes ? session.options.status_every_bytes
                                                       : std::max<std::size_t>(64, session.options.buffer_bytes / 4)) {}

bool StatusChannel::send_query(DrainQuery q) {
  const Held h = line_.write(
      session_.host.query_bytes(q), [](std::size_t) {}, [](std::size_t done) { return done == 0; });
  query_skipped_ = h == Held::stopped;
  if (h != Held::written) return h == Held::stopped;
  pending_.push_back({session_.result.bytes_sent, q, session_.transport.now()});
  ++session_.result.status_queries;
  return true;
}

bool StatusChannel::ping_if_due() {
  const SendResult& r = session_.result;
  if (session_.query == DrainQuery::none || session_.flow == FlowControl::esc_b)
    return take_replies(std::chrono::milliseconds(0));
  if (r.bytes_sent - last_ping_ >= status_every_ &&
      session_.job.command_boundary_at_or_after(r.bytes_sent) == r.bytes_sent) {
    last_ping_ = r.bytes_sent;
    if (!send_query(session_.query)) return false;
  }
  return take_replies(std::chrono::milliseconds(0)) && check_overdue();
}

bool StatusChannel::take_replies(std::chrono::milliseconds wait) {
  Transport& t = session_.transport;
  if (!t.answers()) {
    // Nothing can come back (a file or printer node, USB without bulk IN): only let the time
    // pass. Such a transport's clock is the real one, and its read() refuses.
    if (wait.count() > 0) std::this_thread::sleep_for(wait);
    return true;
  }
  // Nothing expected: only let the time pass (on the transport's clock).
  const bool expect = session_.flow == FlowControl::xon_xoff || !pending_.empty();
  std::uint8_t buf[64];
  const IoResult got = t.read(std::span<std::uint8_t>(buf, expect ? sizeof buf : 0), wait);
  bytes_heard_ += got.bytes;
  for (std::size_t i = 0; i < got.bytes; ++i) {
    const std::uint8_t b = buf[i];
    if (b == kXoff && !paused_) {
      paused_ = true;
      ++xoffs_read_;
    } else if (b == kXon) {
      paused_ = false;
    } else if (b != kXoff) {
      const ReplyByte kind = session_.host.reply_byte(static_cast<char>(b));
      if (kind == ReplyByte::end && !answer_line()) return false;
      if (kind == ReplyByte::part) text_.push_back(static_cast<char>(b));
    }
  }
  if (!got.status.ok() && got.status.error != TransportError::timeout) {
    session_.result.status = got.status;
    return false;
  }
  return true;
}

bool StatusChannel::answer_line() {
  const std::string text = std::exchange(text_, std::string());
  const std::optional<long> number = session_.host.read_answer(text);
  if (pending_.empty() || !number) {
    session_.result.status = {
        TransportError::io, 0,
        "the device answered " + printable(text) +
            (pending_.empty() ? " unasked" : " to " + session_.query_name(pending_.front().query)) +
            ", not a status number: " + (answers_ == 0 ? mismatch_or_line_hint(text) : check_line_hint())};
    return false;
  }
  const Pending asked = pending_.front();
  pending_.pop_front();
  last_answer_ = *number;
  ++answers_;
  heard_({asked.bytes_before, asked.query, last_answer_});
  return true;
}

std::string StatusChannel::mismatch_or_line_hint(const std::string& heard) const {
  const std::string mismatch = session_.host.mismatch_hint(heard);
  return mismatch.empty() ? check_line_hint() : mismatch;
}

std::string StatusChannel::check_line_hint() const {
  if (session_.transport.describe().rfind("serial:", 0) != 0) {
    return "check the cable and that the device is on and is the one the profile is for";
  }
  const int baud = session_.options.baud;
  return "check the cable, the port and the baud rate" +
         (baud > 0 ? " (the profile says " + std::to_string(baud) + " baud)" : std::string());
}

bool StatusChannel::ask(DrainQuery q, const std::string& when) {
  if (!send_query(q)) return false;
  if (query_skipped_) {
    last_answer_ = 0;  // a cancel came first: nothing learnt (no free space, not empty)
    return true;
  }
  answer_dropped_ = false;
  if (!await_answers(0, q, when)) return false;
  if (std::exchange(answer_dropped_, false)) {
    query_skipped_ = true;  // a cancel ended the wait: nothing learnt, as above
    last_answer_ = 0;
  }
  return true;
}

bool StatusChannel::await_answers(std::size_t keep, DrainQuery q, const std::string& when) {
  const std::chrono::milliseconds timeout = session_.options.timeout;
  std::chrono::milliseconds left = timeout;
  // In slices, so that a cancel before the first job byte (a device that does not answer
  // yet) is noticed at once rather than after the whole timeout. Silence is counted on the
  // transport's clock (the simulator's runs faster than real time), chatter on the real one.
  std::chrono::milliseconds silent{0}, held{0};
  auto until = std::chrono::steady_clock::now() + timeout;
  while (pending_.size() > keep) {
    if (session_.result.bytes_sent == 0 && session_.cancel_requested()) {
      session_.result.cancelled = true;
      return false;
    }
    if (session_.cancel_requested() && !aborting_) {
      // A cancel while a device is slow to answer (or has stopped): stop waiting and go on to
      // the abort; the answer, should it come, is taken for this query later.
      answer_dropped_ = true;
      return true;
    }
    const std::size_t before = bytes_heard_;
    const auto slice = std::max(std::chrono::milliseconds(1), std::min(left, kSlice));
    if (!take_replies(slice)) return false;
    if (held < session_.options.hold_timeout && !session_.cancel_requested() && session_.transport.holding_line()) {
      // The query waits behind a line the device holds (it is cutting a full buffer): not
      // silence yet. Up to hold_timeout, as for any byte the device holds back; the silence
      // count starts again when the line moves. A cancel ends this grace (its own wait for
      // the held line, which a second interrupt may give up, follows).
      held += slice;
      silent = std::chrono::milliseconds(0);
      until = std::chrono::steady_clock::now() + timeout;
      left = timeout;
      continue;
    }
    silent = bytes_heard_ == before ? silent + slice : std::chrono::milliseconds(0);
    if (silent >= timeout) break;  // silence for the whole timeout
    left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;  // chatter, but no answer
  }
  if (pending_.size() <= keep) return true;
  return no_answer(q, when, held);
}

bool StatusChannel::no_answer(DrainQuery q, const std::string& when, std::chrono::milliseconds held) {
  const std::string waited = std::to_string(session_.options.timeout.count()) + " ms" +
                             (held.count() > 0 ? " after " + duration_text(held) + " behind a line it held" : "") +
                             (text_.empty() ? "" : " (it sent " + printable(text_) + ")");
  if (answers_ > 0) {
    session_.result.status = {TransportError::timeout, ETIMEDOUT,
                              "the device stopped answering: no answer to " + session_.query_name(q) + " " + when +
                                  " within " + waited + ", though it answered the " + std::to_string(answers_) +
                                  " queries before: it is paused, out of media or stuck, or it lost power"};
  } else {
    session_.result.status = {TransportError::timeout, ETIMEDOUT,
                              "the device did not answer " + session_.query_name(q) + " " + when + " within " + waited +
                                  ": " + mismatch_or_line_hint(text_)};
  }
  return false;
}

bool StatusChannel::check_overdue() {
  if (pending_.empty()) return true;
  Transport& t = session_.transport;
  const std::size_t after = session_.result.bytes_sent - pending_.front().bytes_before;
  const std::size_t on_the_way = t.writes_acknowledged() ? 0 : t.in_flight();
  // Paced by time, nothing holds the line: an answer later than timeout_ms is a device that
  // stopped, and everything sent to it from here overruns its buffer and is lost. (Elsewhere
  // answers may wait behind bytes a held line or an adapter still holds.)
  const bool late = session_.time_paced() && t.now() - pending_.front().sent_at > session_.options.timeout;
  if (!late && after <= std::max(status_every_, on_the_way)) return true;
  return await_answers(pending_.size() - 1, pending_.front().query, "while sending");
}

}  // namespace popcut::drivers::send
