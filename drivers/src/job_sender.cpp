// Job streaming: chunks on command boundaries, paced by XON/XOFF or ESC.B, with cancel and drain.
#include "popcut/drivers/job_sender.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>

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
    flow_ = t.answers() ? o.flow : FlowControl::none;
    query_ = t.answers() ? o.drain_query : DrainQuery::none;
    r_.first_stroke = job.first_stroke;
    r_.last_stroke_sent = job.first_stroke - 1;
    r_.total_strokes = job.total_strokes;
  }

  SendResult run() {
    // Small chunks under XON/XOFF: the device says XOFF at 3/4 full, so one chunk in flight must
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
      const IoResult w = t_.write(bytes_of(std::string_view(job_.bytes).substr(r_.bytes_sent, n)), o_.timeout);
      r_.bytes_sent += w.bytes;
      credit_ -= std::min(credit_, w.bytes);
      r_.last_stroke_sent = job_.last_stroke_within(r_.bytes_sent);
      report_progress();
      if (!w.status.ok()) {
        r_.status = w.status;
        return fail_tail();
      }
    }
    if (!r_.cancelled) {
      if (const TransportStatus st = t_.drain(o_.timeout); !st.ok()) {
        r_.status = st;
        return fail_tail();
      }
      wait_until_drained();
      if (!r_.status.ok()) return fail_tail();
      if (!r_.cancelled) return r_;
    }
    send_abort();
    return r_;
  }

 private:
  bool cancel_requested() const { return o_.cancel && o_.cancel->load(); }
  // A cancel while the device holds us off: stop waiting unless a command is half sent.
  bool at_boundary_and_cancelled() const {
    return cancel_requested() && job_.command_boundary_at_or_after(r_.bytes_sent) == r_.bytes_sent;
  }

  void report_progress() {
    if (!o_.progress) return;
    o_.progress({r_.bytes_sent, job_.bytes.size(), r_.last_stroke_sent, job_.first_stroke, job_.total_strokes});
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

  // One ESC.B round trip: the device's free buffer bytes, or nullopt with r_.status set.
  std::optional<std::size_t> query_free() {
    const IoResult w = t_.write(bytes_of("\x1b.B"), o_.timeout);
    if (!w.status.ok()) {
      r_.status = w.status;
      return std::nullopt;
    }
    ++r_.buffer_queries;
    const std::optional<std::string> answer = read_answer("ESC.B");
    if (!answer) return std::nullopt;
    return static_cast<std::size_t>(std::max(0L, std::strtol(answer->c_str(), nullptr, 10)));
  }

  // One reply line ending in CR. XON/XOFF bytes in between are flow control, not the answer.
  std::optional<std::string> read_answer(const char* what) {
    std::string answer;
    std::uint8_t b = 0;
    while (answer.find('\r') == std::string::npos) {
      const IoResult got = t_.read(std::span<std::uint8_t>(&b, 1), o_.timeout);
      if (!got.status.ok()) {
        r_.status = {got.status.error, got.status.os_error,
                     std::string("no answer to ") + what + " (is the baud rate right?): " + got.status.message};
        return std::nullopt;
      }
      if (got.bytes == 1 && b != kXon && b != kXoff) answer.push_back(static_cast<char>(b));
    }
    return answer;
  }

  // Lets the device work for `wait` (the transport's clock: real, or the simulator's), noting
  // XON/XOFF; false on a transport error other than silence.
  bool idle(std::chrono::milliseconds wait) {
    std::uint8_t buf[64];
    const IoResult got = t_.read(std::span<std::uint8_t>(buf, flow_ == FlowControl::xon_xoff ? sizeof buf : 0), wait);
    note_flow(buf, got.bytes);
    if (!got.status.ok() && got.status.error != TransportError::timeout) {
      r_.status = got.status;
      return false;
    }
    return true;
  }

  void note_flow(const std::uint8_t* buf, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      if (buf[i] == kXoff && !paused_) {
        paused_ = true;
        ++r_.xoff_pauses;
      } else if (buf[i] == kXon) {
        paused_ = false;
      }
    }
  }

  // Waits until `n` bytes may go out; may shrink n (ESC.B credit). False with r_.status set.
  bool pace(std::size_t& n, std::size_t chunk) {
    if (flow_ == FlowControl::xon_xoff) {
      // Take what the device said so far; wait for XON while it holds us off.
      std::uint8_t buf[64];
      const IoResult got = t_.read(buf, std::chrono::milliseconds(0));
      note_flow(buf, got.bytes);
      if (!got.status.ok() && got.status.error != TransportError::timeout) {
        r_.status = got.status;
        return false;
      }
      std::chrono::milliseconds held{0};
      while (paused_) {
        if (at_boundary_and_cancelled()) return true;  // no need to wait for XON to stop
        if (held >= o_.hold_timeout) {
          r_.status = {TransportError::timeout, 0, "device held the line (XOFF) for longer than " +
                                                       std::to_string(o_.hold_timeout.count()) + " ms"};
          return false;
        }
        const IoResult more = t_.read(buf, kSlice);
        note_flow(buf, more.bytes);
        if (!more.status.ok() && more.status.error != TransportError::timeout) {
          r_.status = more.status;
          return false;
        }
        if (more.bytes == 0) held += kSlice;
      }
    } else if (flow_ == FlowControl::none && !t_.backpressure() && o_.job_motion_estimate.count() > 0) {
      // No handshake at all: keep at most half a buffer ahead of where the device should be,
      // assuming it works through the job's bytes at the pace of its estimated motion.
      const double rate_bytes_s = static_cast<double>(job_.bytes.size()) /
                                  (static_cast<double>(o_.job_motion_estimate.count()) / 1000.0);
      for (;;) {
        const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        const double allowed = rate_bytes_s * elapsed_s + static_cast<double>(o_.buffer_bytes) / 2;
        if (static_cast<double>(r_.bytes_sent + n) <= allowed || cancel_requested()) break;
        const auto wait = std::chrono::milliseconds(
            1 + static_cast<long>((static_cast<double>(r_.bytes_sent + n) - allowed) / rate_bytes_s * 1000));
        if (!idle(std::min(kSlice, wait))) return false;
      }
    } else if (flow_ == FlowControl::esc_b && credit_ < n) {
      // Ask for free space; poll again (letting the device work, backing off) while there is
      // too little. The answer is credit for the next chunks: the device only drains meanwhile.
      long waited_ms = 0;
      for (int polls = 0;; ++polls) {
        const std::optional<std::size_t> free_bytes = query_free();
        if (!free_bytes) return false;
        credit_ = *free_bytes;
        if (credit_ >= n) break;
        if (credit_ >= chunk / 2) {
          n = credit_;
          break;
        }
        if (at_boundary_and_cancelled()) return true;
        if (waited_ms > o_.hold_timeout.count()) {
          r_.status = {TransportError::timeout, 0, "device buffer stayed full for longer than " +
                                                       std::to_string(o_.hold_timeout.count()) + " ms"};
          return false;
        }
        const long wait_ms = std::min(200L, 20L << std::min(polls, 4));
        if (!idle(std::chrono::milliseconds(wait_ms))) return false;
        waited_ms += wait_ms;
      }
    }
    return true;
  }

  // Every byte is out: wait until the device has executed them, by query or by estimate.
  void wait_until_drained() {
    if (!t_.answers() && o_.job_motion_estimate.count() == 0) {
      r_.drained_by = "none";
      return;
    }
    std::chrono::milliseconds waited{0};
    if (query_ == DrainQuery::none) {
      // The device can hold at most a buffer's worth: that share of the job's motion time.
      const double share = job_.bytes.empty() ? 0
                                              : std::min(1.0, static_cast<double>(o_.buffer_bytes) /
                                                                  static_cast<double>(job_.bytes.size()));
      const auto wait = std::chrono::milliseconds(static_cast<long>(static_cast<double>(o_.job_motion_estimate.count()) * share));
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
    for (int polls = 0;; ++polls) {
      if (cancel_requested()) {
        r_.cancelled = true;
        return;
      }
      if (query_ == DrainQuery::esc_b) {
        const std::optional<std::size_t> free_bytes = query_free();
        if (!free_bytes) return;
        if (*free_bytes >= o_.buffer_bytes) break;
      } else {
        const IoResult w = t_.write(bytes_of("\x1b.O"), o_.timeout);
        if (!w.status.ok()) {
          r_.status = w.status;
          return;
        }
        const std::optional<std::string> answer = read_answer("ESC.O");
        if (!answer) return;
        if (std::strtol(answer->c_str(), nullptr, 10) & 8) break;  // bit 3: buffer empty
      }
      if (waited >= o_.hold_timeout) {
        r_.status = {TransportError::timeout, 0, "device still busy " + std::to_string(o_.hold_timeout.count()) +
                                                     " ms after the last byte"};
        return;
      }
      const auto step = std::chrono::milliseconds(std::min(200L, 20L << std::min(polls, 4)));
      if (!idle(step)) return;
      waited += step;
    }
    r_.drained_by = to_string(query_);
  }

  // Cancel: the profile's abort sequence and knife up, then how much the device may still hold.
  void send_abort() {
    // The abort goes out even under XOFF: a few bytes fit the quarter the device keeps free.
    const IoResult w = t_.write(bytes_of(o_.abort_bytes), o_.timeout);
    r_.abort_sent = w.status.ok() && w.bytes == o_.abort_bytes.size();
    if (!w.status.ok()) r_.status = w.status;
    estimate_buffered();
  }

  SendResult fail_tail() {
    estimate_buffered();
    return r_;
  }

  void estimate_buffered() {
    r_.buffered_bytes = std::min(o_.buffer_bytes, r_.bytes_sent);
    r_.buffer_known = false;
    if (!t_.answers() || flow_ != FlowControl::esc_b || !r_.status.ok()) return;
    const TransportStatus keep = r_.status;
    if (const std::optional<std::size_t> free_bytes = query_free()) {
      r_.buffered_bytes = o_.buffer_bytes - std::min(o_.buffer_bytes, *free_bytes);
      r_.buffer_known = true;
    }
    r_.status = keep;
  }

  Transport& t_;
  const EncodedJob& job_;
  const SendOptions& o_;
  FlowControl flow_;
  DrainQuery query_;
  SendResult r_;
  bool paused_ = false;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::size_t credit_ = 0;  // ESC.B: bytes the device last said it could take, less those sent since
};

}  // namespace

SendOptions send_options(const DeviceProfile& profile) {
  SendOptions o;
  o.flow = profile.transport.flow;
  o.buffer_bytes = profile.transport.buffer_bytes;
  o.timeout = std::chrono::milliseconds(profile.transport.timeout_ms);
  o.hold_timeout = std::chrono::milliseconds(profile.transport.hold_timeout_ms);
  o.drain_query = profile.transport.drain_query;
  const HpglDialect& d = profile.dialect;
  o.abort_bytes = profile.transport.abort + "PU" + d.terminator + (d.newline ? "\n" : "");
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
