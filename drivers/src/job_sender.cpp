// Job streaming: chunks on command boundaries, paced by XON/XOFF or ESC.B, with cancel and drain.
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/hpgl_reader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <string>
#include <thread>
#include <utility>

namespace popcut::drivers {
namespace {

constexpr std::uint8_t kXon = 0x11;
constexpr std::uint8_t kXoff = 0x13;
// Waits are cut into slices this long so a cancel is noticed promptly.
constexpr std::chrono::milliseconds kSlice{100};

std::span<const std::uint8_t> bytes_of(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

class Sender {
 public:
  Sender(Transport& t, const EncodedJob& job, const SendOptions& o) : t_(t), job_(job), o_(o) {
    // XON/XOFF is popcut's to read only where the transport does not do it (the simulator); a
    // serial port stops its transmitter in the OS, which then blocks popcut's writes.
    flow_ = t.answers() ? o.flow : FlowControl::none;
    if (flow_ == FlowControl::xon_xoff && t.os_flow_control()) flow_ = FlowControl::none;
    query_ = t.answers() ? o.drain_query : DrainQuery::none;
    if (flow_ == FlowControl::esc_b && query_ == DrainQuery::none) query_ = DrainQuery::esc_b;
    status_every_ = o.status_every_bytes ? o.status_every_bytes : std::max<std::size_t>(64, o.buffer_bytes / 4);
    r_.first_stroke = job.first_stroke;
    r_.last_stroke_sent = job.first_stroke - 1;
    r_.last_stroke_written = job.first_stroke - 1;
    r_.total_strokes = job.total_strokes;
    r_.received_counted_by = query_ != DrainQuery::none    ? (t.writes_acknowledged() ? "transport" : "status_answers")
                             : time_paced()                 ? "buffer_size"
                             : t.writes_acknowledged()      ? "transport"
                                                            : "os_queue";
  }

  SendResult run() {
    // Before the first byte: a device that should answer and does not is on the wrong port or
    // baud, or is off; nothing of the job has gone out yet.
    if (query_ != DrainQuery::none && !ask_status("before sending")) {
      if (r_.cancelled) return r_;  // Ctrl-C before the first byte: nothing went out, nothing to abort
      return fail_tail();
    }
    // Reading ESC.E clears it: an error left from before this job must not fail it. A device
    // the profile says answers ESC.E and does not is found here, before any byte of the job.
    if (o_.error_query && t_.answers() && !ask(DrainQuery::esc_e, "before sending")) {
      if (r_.cancelled) return r_;
      return fail_tail();
    }
    // Small chunks: under XON/XOFF the device says XOFF at 3/4 full, so one chunk in flight must
    // fit in the last quarter.
    const std::size_t chunk = std::max<std::size_t>(1, std::min<std::size_t>(256, o_.buffer_bytes / 8));
    std::size_t limit = job_.bytes.size();
    while (r_.bytes_sent < limit) {
      if (!r_.cancelled && cancel_requested()) {
        // Finish the command in flight (a half command would swallow the abort), then stop.
        r_.cancelled = true;
        limit = job_.command_boundary_at_or_after(r_.bytes_sent);
        continue;
      }
      std::size_t n = std::min(chunk, limit - r_.bytes_sent);
      if (!pace(n, chunk)) return fail_tail();
      if (!r_.cancelled && cancel_requested()) continue;  // noticed while waiting: stop properly
      n = on_boundary(n);
      if (!write_job_bytes(n)) return fail_tail();
      if (r_.cancelled && r_.bytes_sent >= limit) break;
      if (!ping_if_due()) return fail_tail();
    }
    if (!r_.cancelled) {
      if (const TransportStatus st = t_.drain(o_.timeout); !st.ok()) {
        r_.status = st;
        return fail_tail();
      }
      wait_until_drained();
      if (!r_.status.ok()) return fail_tail();
      if (!r_.cancelled) {
        if (!check_device_errors()) return fail_tail();  // lost bytes: nothing is known executed
        drained_ = true;  // the device said it has executed everything (or the estimate passed)
        settle_counts();
        return r_;
      }
    }
    send_abort();
    return r_;
  }

 private:
  // A query awaiting its answer: the job bytes written before it, and which query it was.
  struct Pending {
    std::size_t bytes_before;
    DrainQuery query;
    std::chrono::steady_clock::time_point sent_at;  // by the transport's clock
  };

  bool cancel_requested() const { return o_.cancel && o_.cancel->load(); }
  // A cancel while the device holds us off: stop waiting unless a command is half sent.
  bool at_boundary_and_cancelled() const {
    return cancel_requested() && job_.command_boundary_at_or_after(r_.bytes_sent) == r_.bytes_sent;
  }

  // What the device can be shown to have received: what it took, where the transport's count says
  // so; else its answers where it is asked; else what the port says has left (written, less its
  // OS queue and what may still be in flight).
  std::size_t received() {
    // Drained: everything arrived, whatever the port's own counts still hold back as unseen.
    if (drained_) return r_.bytes_sent;
    const std::size_t gone = t_.writes_acknowledged() ? r_.bytes_sent : r_.bytes_sent - std::min(r_.bytes_sent, t_.in_flight());
    if (query_ != DrainQuery::none) return t_.writes_acknowledged() ? r_.bytes_sent : std::min(confirmed_, r_.bytes_sent);
    // No handshake and no answers: a device that stopped (paused, stuck) went on taking bytes and
    // lost all that found its buffer full, and nothing tells when it stopped. Only its buffer's
    // worth from the start is certainly in it. While all goes well (progress) it is what left.
    if (time_paced() && ended_badly_) return std::min(gone, o_.buffer_bytes);
    return gone;
  }

  void settle_counts() {
    r_.holds = xoffs_read_ + t_.holds().value_or(slice_holds_);
    r_.bytes_received = received();
    r_.last_stroke_sent = job_.last_stroke_within(r_.bytes_received);
    r_.last_stroke_written = job_.last_stroke_within(r_.bytes_sent);
    // Executed is known only from the device's answers (or an answered drain); it never runs
    // ahead of what it received.
    if (query_ != DrainQuery::none && answers_ > 0 && r_.device_io_error == 0) {
      const std::size_t bytes = drained_ ? r_.bytes_sent : std::min(executed_, r_.bytes_received);
      r_.last_stroke_executed = std::min(stroke_executed_by(bytes), r_.last_stroke_sent);
    } else {  // unknown: no answers, or lost bytes made what it executed something else than the job
      r_.last_stroke_executed.reset();
    }
    r_.received_before_abort = r_.last_stroke_sent;
    if (discarding_) {
      // The abort makes the device drop its buffer: of what it received, only what it executed
      // is cut, and the rest must be sent again (strokes E+1..N may have been cut already).
      const std::size_t none = job_.first_stroke - 1;
      const std::size_t e = std::min(r_.last_stroke_executed.value_or(none), r_.last_stroke_sent);
      r_.last_stroke_sent = e;
      r_.bytes_received = e > none ? std::min(r_.bytes_received, job_.stroke_end[e - job_.first_stroke]) : 0;
    }
  }

  void report_progress() {
    if (!o_.progress) return;
    settle_counts();
    o_.progress({r_.bytes_sent, job_.bytes.size(), r_.last_stroke_sent, r_.last_stroke_written, job_.first_stroke,
                 job_.total_strokes});
  }

  // Writes the next n job bytes; a cancel while the device holds the line stops them at a command
  // boundary. False with r_.status set.
  bool write_job_bytes(std::size_t n) {
    const std::size_t from = r_.bytes_sent;
    const auto taken = [&](std::size_t k) {
      r_.bytes_sent += k;
      credit_ -= std::min(credit_, k);
      report_progress();
    };
    const auto may_stop = [&](std::size_t) { return at_boundary_and_cancelled(); };
    return through_holds(std::string_view(job_.bytes).substr(from, n), taken, may_stop) != Held::failed;
  }

  // How a write through a line the device may hold ended.
  enum class Held { written, stopped, failed };

  // Writes `bytes` (job bytes or a query). A device holding the line (XOFF or CTS in the OS, USB
  // NAKs) blocks the write: that is waited out up to hold_timeout in short slices, so that a cancel
  // is noticed; `taken(k)` follows every write. On a cancel meanwhile, `may_stop(done)` says
  // whether it can stop after `done` bytes (never inside a command: a half command swallows the
  // abort), else a second interrupt may give up the wait. Failed with r_.status set.
  template <class Taken, class MayStop>
  Held through_holds(std::string_view bytes, Taken taken, MayStop may_stop) {
    const bool held_line = t_.backpressure();
    const auto slice = held_line ? std::min(o_.timeout, std::chrono::milliseconds(250)) : o_.timeout;
    std::size_t done = 0;
    std::chrono::milliseconds held{0};
    while (done < bytes.size()) {
      const IoResult w = t_.write(bytes_of(bytes.substr(done)), slice);
      done += w.bytes;
      taken(w.bytes);
      if (w.status.ok() || done == bytes.size()) continue;  // all of it queued for the line
      if (w.status.error != TransportError::timeout || !held_line) {
        r_.status = w.status;
        return Held::failed;
      }
      // A slice without a byte taken: the device holds the line. Counted once per hold, where the
      // transport does not count them itself.
      if (w.bytes == 0 && held.count() == 0) ++slice_holds_;
      held = w.bytes > 0 ? std::chrono::milliseconds(0) : held + slice;
      if (held >= o_.hold_timeout) {
        r_.status = {TransportError::timeout, w.status.os_error,
                     "the device held popcut off for " + duration_text(o_.hold_timeout) +
                         " without taking a byte (hold_timeout_ms): is it paused, out of media or stuck? (" + w.status.message + ")"};
        return Held::failed;
      }
      if (cancel_requested()) {
        if (may_stop(done)) return Held::stopped;
        if (given_up_while_held()) return Held::failed;  // inside a command: no abort can follow
      }
      if (!take_replies(std::chrono::milliseconds(0))) return Held::failed;
    }
    return Held::written;
  }

  static std::string duration_text(std::chrono::milliseconds d) {
    if (d.count() % 1000 == 0 || d.count() >= 10000) return std::to_string((d.count() + 500) / 1000) + " s";
    return std::to_string(d.count()) + " ms";
  }

  // Ends a chunk of up to n bytes on the last command boundary inside it, when there is one.
  std::size_t on_boundary(std::size_t n) const {
    const std::size_t end = r_.bytes_sent + n;
    if (end == job_.bytes.size()) return n;
    const auto& ends = job_.command_end;
    auto it = std::upper_bound(ends.begin(), ends.end(), end);
    if (it == ends.begin()) return n;
    --it;
    return *it > r_.bytes_sent ? *it - r_.bytes_sent : n;
  }

  const char* query_bytes(DrainQuery q) const { return q == DrainQuery::esc_b ? "\x1b.B" : q == DrainQuery::esc_e ? "\x1b.E" : "\x1b.O"; }
  const char* query_name(DrainQuery q) const { return q == DrainQuery::esc_b ? "ESC.B" : q == DrainQuery::esc_e ? "ESC.E" : "ESC.O"; }

  // Sends a status query without waiting for its answer: when it comes, every job byte written
  // before the query has reached the device (answers come back in order). A line the device
  // holds holds a query like any byte; a cancel before a byte of it has gone leaves it unsent
  // (query_skipped_), so the abort follows.
  bool send_query(DrainQuery q) {
    const Held h = through_holds(query_bytes(q), [](std::size_t) {}, [](std::size_t done) { return done == 0; });
    query_skipped_ = h == Held::stopped;
    if (h != Held::written) return h == Held::stopped;
    pending_.push_back({r_.bytes_sent, q, t_.now()});
    ++r_.status_queries;
    return true;
  }

  // Every status_every_bytes, at a command boundary, a pipelined query that costs no round trip.
  bool ping_if_due() {
    if (query_ == DrainQuery::none || flow_ == FlowControl::esc_b) return take_replies(std::chrono::milliseconds(0));
    if (r_.bytes_sent - last_ping_ >= status_every_ && job_.command_boundary_at_or_after(r_.bytes_sent) == r_.bytes_sent) {
      last_ping_ = r_.bytes_sent;
      if (!send_query(query_)) return false;
    }
    return take_replies(std::chrono::milliseconds(0)) && check_overdue();
  }

  // What an answer tells about execution. ESC.B: the bytes written before the query, less what
  // its buffer still holds (its size less the free space), have left the buffer. Its size is the
  // profile's or the largest free space it ever reported, if larger (asked before the job, an
  // idle device reports all of it): a profile that understates the buffer must not make popcut
  // think more has been executed. ESC.O bit 3: everything written before it has been executed.
  void learn_executed(const Pending& asked) {
    if (asked.query == DrainQuery::esc_b) {
      if (last_answer_ < 0) return;
      const auto free_bytes = static_cast<std::size_t>(last_answer_);
      largest_free_ = std::max(largest_free_, free_bytes);
      const std::size_t held = device_buffer() - free_bytes;
      executed_ = std::max(executed_, asked.bytes_before - std::min(held, asked.bytes_before));
      // Time pacing: the device said where it was, later or sooner than the model: from here
      // the model goes on from there.
      if (time_paced()) model_s_ = model_time_at(asked.bytes_before - std::min(held, asked.bytes_before));
    } else if (asked.query == DrainQuery::esc_o && (last_answer_ & 8) != 0) {
      executed_ = std::max(executed_, asked.bytes_before);
      // Time pacing: the device is no later than the model says once it has read all that, so
      // a device faster than the margin assumes is not held back by it.
      if (time_paced()) model_s_ = std::max(model_s_, model_time_at(asked.bytes_before));
    }
  }

  // The last stroke the first `bytes` (taken out of the device's buffer) have certainly cut: its
  // commands and the one after it have left the buffer, so its last move has ended (a device
  // starts a command when the one before is done).
  std::size_t stroke_executed_by(std::size_t bytes) const {
    const std::size_t s = job_.last_stroke_within(bytes);
    if (s < job_.first_stroke) return s;
    const std::size_t next_end = job_.command_boundary_at_or_after(job_.stroke_end[s - job_.first_stroke] + 1);
    return next_end > bytes ? s - 1 : s;
  }

  // Reads what the device said within `wait`: XON/XOFF (the simulator) and answer lines, each of
  // which confirms the oldest query outstanding. False with r_.status set on a transport error or
  // an answer that is not a number.
  bool take_replies(std::chrono::milliseconds wait) {
    if (!t_.answers()) {
      // Nothing can come back (a file or printer node, USB without bulk IN): only let the time
      // pass. Such a transport's clock is the real one, and its read() refuses.
      if (wait.count() > 0) std::this_thread::sleep_for(wait);
      return true;
    }
    // Nothing expected: only let the time pass (on the transport's clock).
    const bool expect = flow_ == FlowControl::xon_xoff || !pending_.empty();
    std::uint8_t buf[64];
    const IoResult got = t_.read(std::span<std::uint8_t>(buf, expect ? sizeof buf : 0), wait);
    bytes_heard_ += got.bytes;
    for (std::size_t i = 0; i < got.bytes; ++i) {
      const std::uint8_t b = buf[i];
      if (b == kXoff && !paused_) {
        paused_ = true;
        ++xoffs_read_;
      } else if (b == kXon) {
        paused_ = false;
      } else if (b == '\r') {
        if (!answer_line()) return false;
      } else if (b != kXoff && b != '\n') {
        line_.push_back(static_cast<char>(b));
      }
    }
    if (!got.status.ok() && got.status.error != TransportError::timeout) {
      r_.status = got.status;
      return false;
    }
    return true;
  }

  bool answer_line() {
    const std::string text = std::exchange(line_, std::string());
    const bool number = !text.empty() && text.size() <= 12 && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (pending_.empty() || !number) {
      r_.status = {TransportError::io, 0,
                   "the device answered " + printable(text) + (pending_.empty() ? " unasked" : std::string(" to ") + query_name(pending_.front().query)) +
                       ", not a status number: " + check_line_hint()};
      return false;
    }
    const Pending asked = pending_.front();
    pending_.pop_front();
    confirmed_ = std::max(confirmed_, asked.bytes_before);
    last_answer_ = std::strtol(text.c_str(), nullptr, 10);
    ++answers_;
    learn_executed(asked);
    return true;
  }

  std::string check_line_hint() const {
    if (t_.describe().rfind("serial:", 0) != 0) return "check the cable and that the device is on and is the one the profile is for";
    return "check the cable, the port and the baud rate" +
           (o_.baud > 0 ? " (the profile says " + std::to_string(o_.baud) + " baud)" : std::string());
  }

  static std::string printable(const std::string& s) {
    std::string out = "'";
    for (char c : s) {
      const auto u = static_cast<unsigned char>(c);
      if (u >= 0x20 && u < 0x7f) out += c;
      else {
        static const char kHex[] = "0123456789abcdef";
        out += std::string("\\x") + kHex[u >> 4] + kHex[u & 15];
      }
    }
    return out + "'";
  }

  // One status round trip: sends the query and waits (up to the timeout, on the transport's
  // clock: real, or the simulator's) until it and every one before it are answered; the answer
  // in last_answer_. False with r_.status set.
  bool ask(DrainQuery q, const std::string& when) {
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

  // Waits up to the timeout until at most `keep` queries are unanswered. False with r_.status
  // set: a device that never answered is on the wrong port or baud; one that answered before
  // and falls silent has stopped.
  bool await_answers(std::size_t keep, DrainQuery q, const std::string& when) {
    const auto deadline = std::chrono::steady_clock::now() + o_.timeout;
    std::chrono::milliseconds left = o_.timeout;
    // In slices, so that a cancel before the first job byte (a device that does not answer
    // yet) is noticed at once rather than after the whole timeout. Silence is counted on the
    // transport's clock (the simulator's runs faster than real time), chatter on the real one.
    std::chrono::milliseconds silent{0}, held{0};
    auto until = deadline;
    while (pending_.size() > keep) {
      if (r_.bytes_sent == 0 && cancel_requested()) {
        r_.cancelled = true;
        return false;
      }
      if (cancel_requested() && !aborting_) {
        // A cancel while a device is slow to answer (or has stopped): stop waiting and go on to
        // the abort; the answer, should it come, is taken for this query later.
        answer_dropped_ = true;
        return true;
      }
      const std::size_t before = bytes_heard_;
      const auto slice = std::max(std::chrono::milliseconds(1), std::min(left, kSlice));
      if (!take_replies(slice)) return false;
      if (held < o_.hold_timeout && !cancel_requested() && t_.holding_line()) {
        // The query waits behind a line the device holds (it is cutting a full buffer): not
        // silence yet. Up to hold_timeout, as for any byte the device holds back; the silence
        // count starts again when the line moves. A cancel ends this grace (its own wait for
        // the held line, which a second interrupt may give up, follows).
        held += slice;
        silent = std::chrono::milliseconds(0);
        until = std::chrono::steady_clock::now() + o_.timeout;
        left = o_.timeout;
        continue;
      }
      silent = bytes_heard_ == before ? silent + slice : std::chrono::milliseconds(0);
      if (silent >= o_.timeout) break;  // silence for the whole timeout
      left = std::chrono::duration_cast<std::chrono::milliseconds>(until - std::chrono::steady_clock::now());
      if (left.count() <= 0) break;  // chatter, but no answer
    }
    if (pending_.size() <= keep) return true;
    const std::string waited = std::to_string(o_.timeout.count()) + " ms" +
                               (held.count() > 0 ? " after " + duration_text(held) + " behind a line it held" : "") +
                               (line_.empty() ? "" : " (it sent " + printable(line_) + ")");
    if (answers_ > 0) {
      r_.status = {TransportError::timeout, ETIMEDOUT,
                   "the device stopped answering: no answer to " + std::string(query_name(q)) + " " + when + " within " + waited +
                       ", though it answered the " + std::to_string(answers_) +
                       " queries before: it is paused, out of media or stuck, or it lost power"};
    } else {
      r_.status = {TransportError::timeout, ETIMEDOUT,
                   "the device did not answer " + std::string(query_name(q)) + " " + when + " within " + waited + ": " + check_line_hint()};
    }
    return false;
  }

  // A pipelined query followed by more job bytes than can still be on their way (the port's
  // queue and an adapter's FIFO, at least a status interval) has reached the device, which
  // answers device control on arrival: wait for its answer now, so that a device that stops
  // mid-job is noticed then and not only after the last byte.
  bool check_overdue() {
    if (pending_.empty()) return true;
    const std::size_t after = r_.bytes_sent - pending_.front().bytes_before;
    const std::size_t on_the_way = t_.writes_acknowledged() ? 0 : t_.in_flight();
    // Paced by time, nothing holds the line: an answer later than timeout_ms is a device that
    // stopped, and everything sent to it from here overruns its buffer and is lost. (Elsewhere
    // answers may wait behind bytes a held line or an adapter still holds.)
    const bool late = time_paced() && t_.now() - pending_.front().sent_at > o_.timeout;
    if (!late && after <= std::max(status_every_, on_the_way)) return true;
    return await_answers(pending_.size() - 1, pending_.front().query, "while sending");
  }

  bool ask_status(const std::string& when) { return ask(query_, when); }

  // Lets the device work for `wait` (the transport's clock: real, or the simulator's), taking
  // what it says; false on a transport error other than silence.
  bool idle(std::chrono::milliseconds wait) { return take_replies(wait); }

  // The longest the device may go without reading a byte: the longest command of the job by the
  // motion model, slowed by the margin (at least a few answers' worth where there is no model).
  std::chrono::milliseconds quiet_for() const {
    double longest_s = 0;
    for (std::size_t i = 1; i < o_.motion.size(); ++i) longest_s = std::max(longest_s, o_.motion[i].start_s - o_.motion[i - 1].start_s);
    return std::max(std::chrono::milliseconds(500), std::chrono::milliseconds(static_cast<long>(std::ceil(longest_s * slowdown() * 1000))));
  }

  // The first mark at which the model has read more than `bytes`, and when that is (the end of
  // the job's motion past the last mark).
  std::vector<MotionMark>::const_iterator first_mark_past(std::size_t bytes) const {
    return std::upper_bound(o_.motion.begin(), o_.motion.end(), bytes, [](std::size_t b, const MotionMark& m) { return b < m.bytes_read; });
  }
  double start_of(std::vector<MotionMark>::const_iterator mark) const {
    return mark == o_.motion.end() ? o_.motion.back().start_s : mark->start_s;
  }

  // When the model has read no more than `read_bytes`, at the latest: the start of the last
  // command within them.
  double model_time_at(std::size_t read_bytes) const {
    const auto after = first_mark_past(read_bytes);
    return after == o_.motion.begin() ? 0 : std::prev(after)->start_s;
  }

  // No handshake and a line that cannot hold popcut off: only the motion model tells the pace.
  bool time_paced() const { return flow_ == FlowControl::none && !t_.backpressure() && !o_.motion.empty(); }
  double slowdown() const { return 1 + o_.pace_margin_percent / 100.0; }

  // Moves the modelled device on by the transport's clock, at the model's pace slowed by the
  // margin, and returns the job bytes it has read out of its buffer. It cannot start a command
  // before it has all of it: waiting for bytes (a slow line, a late write) costs it time, so it
  // never runs ahead of the device, which could then be sent more than it has room for.
  std::size_t advance_model() {
    const auto now = t_.now();
    const double dt_s = std::chrono::duration<double>(now - model_at_).count() / slowdown();
    model_at_ = now;
    const std::size_t has_bytes = all_out_ ? r_.bytes_sent : r_.bytes_sent - std::min(r_.bytes_sent, t_.expected_in_flight());
    const auto waits_for = first_mark_past(has_bytes);
    const double limit_s = start_of(waits_for);
    model_s_ = std::min(model_s_ + std::max(0.0, dt_s), std::max(model_s_, limit_s));
    model_needs_ = waits_for != o_.motion.end() && model_s_ >= limit_s ? waits_for->bytes_read : 0;
    const auto started = std::upper_bound(o_.motion.begin(), o_.motion.end(), model_s_,
                                          [](double t, const MotionMark& m) { return t < m.start_s; });
    return started == o_.motion.begin() ? 0 : std::prev(started)->bytes_read;
  }

  // Waits until `n` bytes may go out; may shrink n (ESC.B credit). False with r_.status set.
  bool pace(std::size_t& n, std::size_t chunk) {
    if (flow_ == FlowControl::xon_xoff) {
      // Take what the device said so far; wait for XON while it holds us off.
      if (!take_replies(std::chrono::milliseconds(0))) return false;
      std::chrono::milliseconds held{0}, next_probe = o_.timeout;
      while (paused_) {
        if (at_boundary_and_cancelled()) return true;  // no need to wait for XON to stop
        // A device answers device control even while it holds us off (it bypasses the buffer):
        // asked every timeout_ms, silence means it has stopped, not that it is busy cutting.
        if (query_ != DrainQuery::none && held >= next_probe) {
          next_probe += o_.timeout;
          if (pending_.empty() && !send_query(query_)) return false;
          if (!pending_.empty() && !await_answers(0, pending_.back().query, "while it held popcut off (XOFF)")) return false;
          continue;
        }
        if (held >= o_.hold_timeout) {
          r_.status = {TransportError::timeout, 0, "the device held popcut off (XOFF) for " + duration_text(o_.hold_timeout) +
                                                       " (hold_timeout_ms): is it paused, out of media or stuck?"};
          return false;
        }
        if (!take_replies(kSlice)) return false;
        held += kSlice;
      }
    } else if (time_paced()) {
      // No handshake at all: keep at most half a buffer more than the modelled device has read.
      // Half: a device may free a command's bytes only when it ends it, not when it starts it.
      const std::size_t ahead_bytes = std::max<std::size_t>(1, o_.buffer_bytes / 2);
      const auto began = t_.now();
      for (;;) {
        const std::size_t read_bytes = advance_model();
        if (r_.bytes_sent + n <= read_bytes + ahead_bytes || cancel_requested()) break;
        // A single command longer than `ahead_bytes` that the device cannot start until it is all
        // there: it holds only what it waits for, so what it lacks goes.
        if (model_needs_ > r_.bytes_sent) {
          n = std::min(n, model_needs_ - r_.bytes_sent);
          break;
        }
        // A device that answers says where it is (learn_executed): ESC.O when it has caught up
        // (bit 3, buffer empty), ESC.B how much it still holds. Asked while held back, every kSlice.
        if (query_ != DrainQuery::none && pending_.empty() && t_.now() - asked_idle_at_ >= kSlice) {
          asked_idle_at_ = t_.now();
          if (!ask(query_, "while pacing")) return false;
          continue;
        }
        if (!check_overdue()) return false;
        // Answers that keep the model where it is show a device that does not move.
        if (query_ != DrainQuery::none && t_.now() - began > o_.hold_timeout) {
          r_.status = {TransportError::timeout, 0, "the device's answers to " + std::string(query_name(query_)) + " showed no progress for " +
                                                       duration_text(o_.hold_timeout) + " (hold_timeout_ms): is it paused, out of media or stuck?"};
          return false;
        }
        // When the model reads far enough, at its (slowed) pace.
        const std::size_t target_bytes = r_.bytes_sent + n - ahead_bytes;
        const double at_s = start_of(first_mark_past(target_bytes - 1));  // target_bytes > read_bytes >= 0
        const auto wait = std::chrono::milliseconds(1 + static_cast<long>(std::max(0.0, at_s - model_s_) * slowdown() * 1000));
        if (!idle(std::min(kSlice, wait))) return false;
      }
    } else if (flow_ == FlowControl::esc_b && credit_ < n) {
      // Ask for free space; poll again (letting the device work, backing off) while there is
      // too little. The answer is credit for the next chunks: the device only drains meanwhile.
      // Time without progress: an answer with more free space than any before in this wait
      // shows the device working, and restarts the count.
      long waited_ms = 0, most_free = -1;
      for (int polls = 0;; ++polls) {
        if (!ask(DrainQuery::esc_b, "while sending")) return false;
        // Cancelled while waiting for the answer: finish the command in flight without it (the
        // abort that follows discards what the device holds).
        if (query_skipped_ && cancel_requested()) {
          n = std::max<std::size_t>(1, job_.command_boundary_at_or_after(r_.bytes_sent) - r_.bytes_sent);
          return true;
        }
        ++r_.buffer_queries;
        credit_ = static_cast<std::size_t>(std::max(0L, last_answer_));
        if (credit_ >= n) break;
        if (last_answer_ > most_free) {
          most_free = last_answer_;
          waited_ms = 0;
        }
        // Enough to be worth a write: half a chunk, or half of the most the device ever said
        // was free when its buffer is smaller than the profile says (a 64-byte buffer holding
        // part of a long command never reports half of a 1024-byte profile's chunk).
        const std::size_t worth = std::max<std::size_t>(1, largest_free_ > 0 ? std::min(chunk, largest_free_) / 2 : chunk / 2);
        if (credit_ >= worth) {
          n = credit_;
          break;
        }
        if (at_boundary_and_cancelled()) return true;
        if (waited_ms > o_.hold_timeout.count()) {
          r_.status = {TransportError::timeout, 0, "the device's buffer stayed full for " + duration_text(o_.hold_timeout) +
                                                       " (hold_timeout_ms) without freeing a byte, by its answers to ESC.B: is it paused, out of media or stuck?"};
          return false;
        }
        const long wait_ms = std::min(200L, 20L << std::min(polls, 4));
        if (!idle(std::chrono::milliseconds(wait_ms))) return false;
        waited_ms += wait_ms;
      }
    }
    return true;
  }

  // The device's own word on the line (ESC.E, where the profile says it answers): bytes lost to
  // a framing error or a full buffer mean it cut something else than the job, which looked sent.
  bool check_device_errors() {
    if (!o_.error_query || !t_.answers()) return true;
    if (!ask(DrainQuery::esc_e, "after the job")) return false;
    // 10-14 are device-control complaints (a query or set-up it did not take): no HP-GL byte lost.
    if (query_skipped_ || (last_answer_ != 15 && last_answer_ != 16)) return true;
    const std::string code = std::to_string(last_answer_);
    r_.device_io_error = static_cast<int>(last_answer_);
    const std::string meaning =
        last_answer_ != 16 ? "framing, parity or overrun errors on the line: bytes were garbled; check the baud rate, data bits, parity and "
                             "stop bits of the profile against the device, and the cable"
        : time_paced()     ? "its input buffer overflowed: bytes were lost, so the cut is wrong; popcut paced the job by time (flow_control "
                             "\"none\"), and the device is slower than the profile's kinematics and tool speeds allow, with pace_margin_percent (" +
                                 std::to_string(o_.pace_margin_percent) + " %), or its buffer is smaller than buffer_bytes"
                           : "its input buffer overflowed: bytes were lost, so the cut is wrong; the device does not do the flow control the "
                             "profile says (flow_control, buffer_bytes)";
    r_.status = {TransportError::io, 0, "every byte went out, but the device reports I/O error " + code + " (ESC.E): " + meaning};
    return false;
  }

  // Every byte is out: wait until the device has executed them, by query or by estimate.
  void wait_until_drained() {
    if (!t_.answers() && o_.motion.empty()) {
      r_.drained_by = "none";
      return;
    }
    std::chrono::milliseconds waited{0};
    // The device can hold at most a buffer's worth: that share of the job's motion time.
    const double share = job_.bytes.empty() ? 0
                                            : std::min(1.0, static_cast<double>(device_buffer()) /
                                                                static_cast<double>(job_.bytes.size()));
    const double motion_s = o_.motion.empty() ? 0 : o_.motion.back().start_s;
    const auto buffered_time = std::chrono::milliseconds(static_cast<long>(motion_s * share * 1000));
    if (query_ == DrainQuery::none) {
      // Time-paced: until the modelled device ends the job's motion; else a full buffer's share.
      auto wait = buffered_time;
      if (time_paced()) {
        all_out_ = true;  // drained out of popcut's side: the device has every byte
        advance_model();
        wait = std::chrono::milliseconds(static_cast<long>(std::ceil((o_.motion.back().start_s - model_s_) * slowdown() * 1000)));
      }
      while (waited < wait) {
        if (cancel_requested()) {
          r_.cancelled = true;
          return;
        }
        const auto step = std::min(kSlice, wait - waited);
        if (!idle(step)) return;
        waited += step;
      }
      r_.drained_by = "estimate";
      return;
    }
    // A device that answers is working (or paused): it is given what its buffer should take to
    // cut, by the plan's estimate, plus hold_timeout; under ESC.B each answer with more free space
    // than before shows progress and restarts the hold_timeout.
    long most_free = -1;
    std::chrono::milliseconds stalled{0};
    const std::chrono::milliseconds quiet = quiet_for();
    for (int polls = 0;; ++polls) {
      if (cancel_requested()) {
        r_.cancelled = true;
        return;
      }
      if (!ask_status("after the last byte")) return;
      // ESC.B: as much free as the device ever said it had (asked idle before the job, that is
      // its whole buffer). The profile's size can be wrong either way: 1024 free of 65536 is not
      // empty, and a 256-byte device never reports 1024 free.
      if (query_ == DrainQuery::esc_o && (last_answer_ & 8) != 0) break;  // ESC.O bit 3: buffer empty
      if (query_ == DrainQuery::esc_b) {
        const auto free_now = static_cast<std::size_t>(std::max(0L, last_answer_));
        if (free_now >= device_buffer()) break;  // the whole buffer, by the profile or any answer
        if (last_answer_ > most_free) {
          most_free = last_answer_;
          stalled = std::chrono::milliseconds(0);
        }
        // As free as it ever said but less than the profile's size: a device smaller than the
        // profile says, now empty, or one that was busy when first asked and still holds what
        // it held then. Empty once it has read no byte for longer than any one command of the
        // job takes it (a device reads the next command when one ends).
        if (free_now >= largest_free_ && stalled >= quiet) break;
      }
      if (stalled >= o_.hold_timeout && waited >= buffered_time + o_.hold_timeout) {
        r_.status = {TransportError::timeout, 0,
                     "every byte reached the device, but its buffer is still not empty " + duration_text(waited) +
                         " after the last byte (" + (query_ == DrainQuery::esc_b ? "no progress by its ESC.B answers for " + duration_text(stalled) : std::string("ESC.O says busy")) +
                         "; the plan expected about " + duration_text(buffered_time) + " for a full buffer, plus hold_timeout_ms): it answers, so it is paused or stuck; check it — if it finishes, the card is complete"};
        return;
      }
      const auto step = std::chrono::milliseconds(std::min(200L, 20L << std::min(polls, 4)));
      if (!idle(step)) return;
      waited += step;
      stalled += step;
    }
    r_.drained_by = to_string(query_);
  }

  // Cancel: the profile's abort sequence and knife up, then how much the device may still hold.
  void send_abort() {
    aborting_ = true;  // from here a query's answer is waited for: it tells what the device holds
    // Under XON/XOFF in the OS the abort waits for XON like any byte, up to the hold timeout:
    // the device is cutting its buffer meanwhile, and the abort is what stops it. In slices, so
    // that the user is told and may give up (o_.give_up).
    const bool held_line = t_.backpressure();
    const auto slice = held_line ? std::min(o_.timeout, std::chrono::milliseconds(250)) : o_.timeout;
    const auto limit = held_line ? std::max(o_.timeout, o_.hold_timeout) : o_.timeout;
    const std::string_view abort = o_.abort_bytes;
    // Recorded before the abort goes out, so that a crash meanwhile leaves counts that never
    // skip what the device is about to drop.
    discarding_ = o_.abort_discards_buffer;
    if (discarding_) report_progress();
    std::size_t done = 0;
    std::chrono::milliseconds waited{0};
    for (;;) {
      // Bytes the port took may still wait in its queue for the device to let them out.
      TransportStatus st;
      if (done < abort.size()) {
        const IoResult w = t_.write(bytes_of(abort.substr(done)), slice);
        done += w.bytes;
        st = w.status;
      } else {
        st = t_.drain(slice);
      }
      if (st.ok() && done == abort.size()) break;
      if (st.ok()) continue;
      if (st.error != TransportError::timeout || !held_line) {
        r_.status = st;
        break;
      }
      waited += slice;
      if (given_up_while_held()) break;
      if (waited >= limit) {
        r_.status = {TransportError::timeout, st.os_error, "the device held the line for " + duration_text(limit) +
                                                               " (hold_timeout_ms) and did not take the abort sequence: " + st.message};
        break;
      }
    }
    r_.abort_sent = r_.status.ok() && done == abort.size();
    // Not through (given up, the line failed): the device keeps its buffer and goes on cutting.
    if (!r_.abort_sent) discarding_ = false;
    estimate_buffered();
    r_.buffer_discarded = discarding_;
  }

  // A cancel waiting on a device that holds the line: says so once (o_.waiting_to_cancel), and
  // true with r_.status set when the user has given up (o_.give_up: a second Ctrl-C). What the
  // port still holds for the device is dropped, so that no stale byte reaches it later.
  bool given_up_while_held() {
    if (!std::exchange(told_waiting_, true) && o_.waiting_to_cancel) o_.waiting_to_cancel();
    if (!o_.give_up || !o_.give_up->load()) return false;
    t_.discard_output();
    r_.status = {TransportError::timeout, 0,
                 "gave up waiting for the device to take the rest of the cancel: it held the line (XOFF or CTS), so neither "
                 "the abort sequence nor the knife-up reached it"};
    return true;
  }

  SendResult fail_tail() {
    estimate_buffered();
    return r_;
  }

  void estimate_buffered() {
    if (r_.status.ok()) take_replies(std::chrono::milliseconds(0));  // answers already on their way
    ended_badly_ = true;
    settle_counts();
    if (time_paced()) {
      // How long the device may go on cutting, at the paced rate: until the model would have
      // ended everything sent. A job sent to it again meanwhile would find its buffer part full.
      advance_model();
      const double done_s = start_of(first_mark_past(r_.bytes_sent));
      // From where it last said it was, if it answers: one that fell silent (paused) may
      // resume with all it held then.
      const bool fell_silent = query_ != DrainQuery::none && r_.status.error == TransportError::timeout;
      const double from_s = fell_silent ? std::min(model_s_, model_time_at(executed_)) : model_s_;
      r_.busy_for_s = std::max(0.0, done_s - from_s) * slowdown();
    }
    // What the device may still cut: its buffer plus what is on its way to it.
    // Paced by time, what it holds is never more than its buffer (it loses the rest), plus what
    // may still reach it: not all that is not certainly received.
    const std::size_t on_the_way = time_paced() ? std::min(r_.bytes_sent, t_.writes_acknowledged() ? 0 : t_.in_flight())
                                                : r_.bytes_sent - r_.bytes_received;
    r_.buffered_bytes = std::min(r_.bytes_sent, device_buffer() + on_the_way);
    r_.buffer_known = false;
    bool measured = false;
    if (t_.answers() && flow_ == FlowControl::esc_b && r_.status.ok()) {
      const TransportStatus keep = r_.status;
      if (ask(DrainQuery::esc_b, "after the cancel") && !query_skipped_) {
        // Exact when the device once said its whole buffer was free (so its size is known);
        // else an upper bound: a device smaller than the profile says holds less.
        const std::size_t free_now = static_cast<std::size_t>(std::max(0L, last_answer_));
        std::size_t held = device_buffer() - std::min(device_buffer(), free_now);
        // Asked after the abort: the knife-up sent with it is in the buffer too, and is no part
        // of the job (a device that honoured ESC.K holds only that).
        if (r_.abort_sent) held -= std::min(held, buffered_abort_bytes());
        r_.buffered_bytes = std::min(r_.bytes_sent, held);
        r_.buffer_known = largest_free_ >= device_buffer();
        measured = true;
      }
      r_.status = keep;
    }
    if (discarding_) {
      if (measured && r_.buffered_bytes > 0) {
        discarding_ = false;  // it still holds job bytes after the abort: it kept its buffer
        settle_counts();
      } else {
        r_.buffered_bytes = 0;  // it dropped what it held: it cuts nothing more
      }
    }
    r_.buffered_first_stroke = job_.last_stroke_within(r_.bytes_sent - r_.buffered_bytes) + 1;
    // Nothing after the last stroke known executed is known cut: the range starts no later.
    if (r_.last_stroke_executed) r_.buffered_first_stroke = std::min(r_.buffered_first_stroke, *r_.last_stroke_executed + 1);
    r_.buffered_last_stroke = stroke_touched_by(r_.bytes_sent);
    if (r_.buffered_bytes == 0) r_.buffered_first_stroke = r_.buffered_last_stroke + 1;
  }

  // Bytes of the abort that enter the device's buffer: all but its device-control sequences.
  std::size_t buffered_abort_bytes() const {
    std::size_t n = 0;
    std::string esc;
    for (const char c : o_.abort_bytes) {
      if (!esc.empty() || c == '\x1b') {
        esc += c;
        if (esc_complete(esc)) esc.clear();
      } else {
        ++n;
      }
    }
    return n;
  }

  // The last stroke the first `bytes` may cut: the last complete one, or the next one when its
  // knife went down (a cancel stops it at a command boundary).
  std::size_t stroke_touched_by(std::size_t bytes) const {
    const std::size_t done = job_.last_stroke_within(bytes);
    const std::size_t last = job_.first_stroke + job_.stroke_end.size() - 1;
    const std::size_t done_end = done >= job_.first_stroke ? job_.stroke_end[done - job_.first_stroke] : 0;
    // The next stroke is touched once its knife-down command went out: its travel and tool
    // set-up before that cut nothing. A job with no such record (raw bytes): from its end.
    const std::size_t next = done + 1 - job_.first_stroke;
    const std::size_t knife_down = next < job_.stroke_cut_start.size() ? job_.stroke_cut_start[next] : done_end;
    return done < last && bytes > knife_down ? done + 1 : done;
  }

  Transport& t_;
  const EncodedJob& job_;
  const SendOptions& o_;
  FlowControl flow_;
  DrainQuery query_;
  SendResult r_;
  bool paused_ = false;
  // Time pacing's model of the device: seconds of motion done, by the transport's clock at
  // model_at_; all_out_: every byte has left popcut.
  double model_s_ = 0;
  std::size_t model_needs_ = 0;  // starved: the bytes it must have to go on (0: it is not)
  std::chrono::steady_clock::time_point asked_idle_at_{};  // last ESC.O while held back
  std::chrono::steady_clock::time_point model_at_ = t_.now();
  bool all_out_ = false;
  bool ended_badly_ = false;  // a cancel or failure: counts are final and must assume the worst
  std::size_t credit_ = 0;  // ESC.B: bytes the device last said it could take, less those sent since
  std::size_t status_every_ = 0;
  std::size_t last_ping_ = 0;
  std::size_t confirmed_ = 0;  // job bytes written before the last answered query
  bool drained_ = false;       // the job went out whole and the device finished it
  std::deque<Pending> pending_;  // queries awaiting an answer
  int answers_ = 0;              // status answers heard: a device that answered once and goes silent has stopped
  std::size_t executed_ = 0;     // job bytes the device has been seen to take out of its buffer and start
  std::size_t largest_free_ = 0; // the most free space ESC.B ever reported
  // The device's buffer at its largest: the profile's size, or more if the device ever said it
  // had more free. What it holds is never less than this size less its free space, so what it
  // executed is never over-claimed (a profile overstating the buffer under-claims it).
  std::size_t device_buffer() const { return std::max(o_.buffer_bytes, largest_free_); }
  std::string line_;
  long last_answer_ = 0;
  std::size_t bytes_heard_ = 0;  // bytes read from the device so far
  int xoffs_read_ = 0;           // XOFFs popcut read itself (flow control not in the OS)
  int slice_holds_ = 0;          // holds seen as write slices that moved no byte
  bool told_waiting_ = false;    // o_.waiting_to_cancel was called
  bool query_skipped_ = false;
  bool answer_dropped_ = false;  // a cancel ended await_answers before the answer came
  bool aborting_ = false;        // the abort is under way: cancels no longer cut waits short
  bool discarding_ = false;      // an abort that makes the device drop its buffer is going out or went
};

}  // namespace

SendOptions send_options(const DeviceProfile& profile) {
  SendOptions o;
  o.flow = profile.transport.flow;
  o.buffer_bytes = profile.transport.buffer_bytes;
  o.timeout = std::chrono::milliseconds(profile.transport.timeout_ms);
  o.hold_timeout = std::chrono::milliseconds(profile.transport.hold_timeout_ms);
  o.drain_query = profile.transport.drain_query;
  o.error_query = profile.transport.error_query;
  o.baud = profile.transport.baud;
  o.pace_margin_percent = profile.transport.pace_margin_percent;
  const HpglDialect& d = profile.dialect;
  o.abort_bytes = profile.transport.abort + "PU" + d.terminator + (d.newline ? "\n" : "");
  o.abort_discards_buffer = profile.transport.abort_discards_buffer;
  return o;
}

SendResult send_job(Transport& t, const EncodedJob& job, const SendOptions& o) { return Sender(t, job, o).run(); }

SendResult send_job(Transport& t, std::string_view bytes, const SendOptions& o) {
  EncodedJob job;
  job.bytes = std::string(bytes);
  job.command_end = {job.bytes.size()};
  return send_job(t, job, o);
}

}  // namespace popcut::drivers
