// Job streaming: chunks on command boundaries through the pacer, with status pings, cancel, drain and abort.
#include "popcut/drivers/job_sender.h"

#include "popcut/drivers/language.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "popcut/drivers/language.h"
#include "send/accounting.h"
#include "send/held_line.h"
#include "send/motion_tracker.h"
#include "send/pacer.h"
#include "send/session.h"
#include "send/status_channel.h"
#include "send/waits.h"

namespace popcut::drivers {
namespace {

using namespace send;

// One job's sending: the parts wired together, and the order of its phases (check the device,
// stream, drain, check its errors; or abort).
class Sender {
 public:
  Sender(Transport& transport, const EncodedJob& job, const SendOptions& options)
      : session_(transport, job, options),
        line_(session_),
        channel_(session_, line_, [this](const Answer& a) { heard(a); }),
        accounting_(session_),
        tracker_(options.motion, options.pace_margin_percent, transport.now()),
        pacer_(make_pacer({session_, channel_, accounting_, tracker_})) {
    line_.listen_with([this] { return channel_.take_replies(std::chrono::milliseconds(0)); });
  }

  SendResult run() {
    run_phases();
    if (session_.device_stop() != DeviceStop::none) stopped_by_device();
    return session_.result;
  }

 private:
  void run_phases() {
    SendResult& r = session_.result;
    if (!check_device_first()) {
      if (!r.cancelled) estimate_buffered();
      return;
    }
    if (!stream()) return estimate_buffered();
    if (!r.cancelled) {
      if (const TransportStatus st = session_.transport.drain(session_.options.timeout); !st.ok()) {
        r.status = st;
        return estimate_buffered();
      }
      wait_until_drained();
      if (!r.status.ok()) return estimate_buffered();
      if (!r.cancelled) {
        if (!check_device_errors()) return estimate_buffered();  // lost bytes: nothing is known executed
        accounting_.drained();  // the device said it has executed everything (or the estimate passed)
        settle_counts();
        return;
      }
    }
    send_abort();
  }

  // An answer: what it tells the accounting, and time pacing's model where the device is; a
  // device that says it cannot go on ends the job (DeviceStop).
  void heard(const Answer& answer) {
    const Whereabouts where = accounting_.learn(answer);
    if (session_.time_paced()) tracker_.heard(where);
    const StatusMeaning said = session_.host.meaning(answer.query, answer.value);
    if (said == StatusMeaning::tray_empty) session_.device_stopped(DeviceStop::tray_empty);
    if (said == StatusMeaning::paused) session_.device_stopped(DeviceStop::paused);
  }

  // The device stopped the job (its answer said so), which ended like a cancel: the result says
  // why instead, as a failure a resume finishes.
  void stopped_by_device() {
    SendResult& r = session_.result;
    const DeviceStop why = session_.device_stop();
    r.device_stop = why;
    r.cancelled = session_.user_cancelled();
    if (!r.status.ok() && r.bytes_sent > 0) return;  // the abort failed: that message says more
    const std::string said = session_.query_name(session_.query) + " answer";
    const std::string what = why == DeviceStop::tray_empty
                                 ? "no sheet loaded: the device reports its tray empty (" + said + ")"
                                 : "the device is paused (" + said + "): its pause key or a menu holds it";
    if (r.bytes_sent == 0) {
      r.status = {TransportError::io, 0,
                  what + ", before any byte of the job was sent: " +
                      (why == DeviceStop::tray_empty ? "load a sheet (or the mat)" : "let it go on, or reset it")};
      return;
    }
    r.status = {TransportError::io, 0,
                what + (why == DeviceStop::tray_empty ? " (the sheet or the roll ran out)" : "") + "; after " +
                    std::to_string(r.bytes_sent) + " of " + std::to_string(session_.job.bytes.size()) +
                    " job bytes popcut finished the command in flight and " +
                    (r.abort_sent ? "sent the knife-up (after the profile's abort sequence, if any)"
                                  : "could not send the abort sequence and the knife-up")};
  }

  void settle_counts() {
    session_.result.holds = channel_.xoffs_read() + session_.transport.holds().value_or(line_.slice_holds());
    accounting_.settle(channel_.answers());
  }

  void report_progress() {
    const SendOptions& o = session_.options;
    if (!o.progress) return;
    settle_counts();
    const SendResult& r = session_.result;
    const EncodedJob& job = session_.job;
    o.progress({r.bytes_sent, job.bytes.size(), r.last_stroke_sent, r.last_stroke_written, job.first_stroke,
                job.total_strokes});
  }

  // Before the first byte: a device that should answer and does not is on the wrong port or
  // baud, or is off; nothing of the job has gone out yet. False: failed, or cancelled (a Ctrl-C
  // before the first byte: nothing went out, nothing to abort).
  bool check_device_first() {
    if (session_.query != DrainQuery::none && !channel_.ask(session_.query, "before sending")) return false;
    if (session_.device_stop() != DeviceStop::none) return false;  // no sheet, or paused: nothing goes out
    if (!wait_while_busy()) return false;
    // Reading ESC.E clears it: an error left from before this job must not fail it. A device
    // the profile says answers ESC.E and does not is found here, before any byte of the job.
    return !session_.options.error_query || !session_.transport.answers() ||
           channel_.ask(DrainQuery::esc_e, "before sending");
  }

  // A device still cutting an earlier job (a resume sent at once, another program's job) would
  // drop what it holds at this job's init where that resets it: ask until it is idle, up to
  // hold_timeout. False with the status set, or on a cancel or a device stop meanwhile.
  bool wait_while_busy() {
    if (session_.query == DrainQuery::none || !session_.host.init_resets_device()) return true;
    const auto busy = [&] {
      return session_.host.meaning(session_.query, channel_.last_answer()) == StatusMeaning::busy;
    };
    const auto start = session_.transport.now();
    while (busy()) {
      if (session_.user_cancelled() || session_.device_stop() != DeviceStop::none) return false;
      if (session_.transport.now() - start >= session_.options.hold_timeout) {
        session_.result.status = {
            TransportError::timeout, ETIMEDOUT,
            "the device was still busy (" + session_.query_name(session_.query) + " answers) after " +
                std::to_string(session_.options.hold_timeout.count() / 1000) +
                " s, cutting an earlier job: the job's init would reset it and drop what it holds, so nothing "
                "was sent; wait until it stops, or reset it"};
        return false;
      }
      if (!channel_.take_replies(std::chrono::milliseconds(250))) return false;  // a pause between questions
      if (!channel_.ask(session_.query, "while waiting for an earlier job to end")) return false;
    }
    return session_.device_stop() == DeviceStop::none;
  }

  // Every job byte, paced, or up to the command in flight at a cancel. False with the status set.
  bool stream() {
    SendResult& r = session_.result;
    const EncodedJob& job = session_.job;
    // Small chunks: under XON/XOFF the device says XOFF at 3/4 full, so one chunk in flight must
    // fit in the last quarter.
    const std::size_t chunk = std::max<std::size_t>(1, std::min<std::size_t>(256, session_.options.buffer_bytes / 8));
    std::size_t limit = job.bytes.size();
    while (r.bytes_sent < limit) {
      if (!r.cancelled && !r.paused && session_.pause_requested()) {
        // Finish the stroke in flight, then stop: nothing is dropped, so nothing is cut twice.
        r.paused = true;
        limit = stroke_boundary_at_or_after(r.bytes_sent);
        continue;
      }
      if (!r.cancelled && session_.cancel_requested()) {
        // Finish the command in flight (a half command would swallow the abort), then stop.
        r.cancelled = true;
        limit = job.command_boundary_at_or_after(r.bytes_sent);
        continue;
      }
      std::size_t n = std::min(chunk, limit - r.bytes_sent);
      if (!pacer_->pace(n, chunk)) return false;
      if (!r.cancelled && session_.cancel_requested()) continue;  // noticed while waiting: stop properly
      if (!r.paused && session_.pause_requested()) continue;
      n = on_boundary(n);
      if (!write_job_bytes(n)) return false;
      if ((r.cancelled || r.paused) && r.bytes_sent >= limit) break;
      if (!channel_.ping_if_due()) return false;
    }
    if (r.paused && !r.cancelled) return lift_for_pause();
    return true;
  }

  // Where a pause stops: the end of the stroke in flight (nothing sent yet: right here; past the
  // last stroke, in the finish: the end of the job).
  std::size_t stroke_boundary_at_or_after(std::size_t offset) const {
    const EncodedJob& job = session_.job;
    if (offset == 0) return 0;
    const auto it = std::lower_bound(job.stroke_end.begin(), job.stroke_end.end(), offset);
    if (it != job.stroke_end.end()) return *it;
    if (job.stroke_end.empty()) return job.command_boundary_at_or_after(offset);
    return job.bytes.size();
  }

  // Paused before the end: the knife goes up behind the last stroke sent, before the drain, so
  // it is not left down while the device empties its buffer. False with the status set.
  bool lift_for_pause() {
    SendResult& r = session_.result;
    // Nothing sent yet: the knife is where the last job left it; the finish went out: it lifted it.
    if (r.bytes_sent == 0 || r.bytes_sent >= session_.job.bytes.size()) return true;
    if (line_.write_abort(session_.options.pause_bytes)) return true;
    if (r.status.ok()) r.status = {TransportError::io, 0, "the knife-up of the pause did not reach the device"};
    return false;
  }

  // Writes the next n job bytes; a cancel while the device holds the line stops them at a command
  // boundary. False with the status set.
  bool write_job_bytes(std::size_t n) {
    SendResult& r = session_.result;
    const auto taken = [&](std::size_t k) {
      r.bytes_sent += k;
      pacer_->written(k);
      report_progress();
    };
    const auto may_stop = [&](std::size_t) { return session_.at_boundary_and_cancelled(); };
    return line_.write(std::string_view(session_.job.bytes).substr(r.bytes_sent, n), taken, may_stop) != Held::failed;
  }

  // Ends a chunk of up to n bytes on the last command boundary inside it, when there is one.
  std::size_t on_boundary(std::size_t n) const {
    const std::size_t sent = session_.result.bytes_sent;
    const std::size_t end = sent + n;
    if (end == session_.job.bytes.size()) return n;
    const auto& ends = session_.job.command_end;
    auto it = std::upper_bound(ends.begin(), ends.end(), end);
    if (it == ends.begin()) return n;
    --it;
    return *it > sent ? *it - sent : n;
  }

  // The device's own word on the line (ESC.E, where the profile says it answers): bytes lost to
  // a framing error or a full buffer mean it cut something else than the job, which looked sent.
  bool check_device_errors() {
    const SendOptions& o = session_.options;
    if (!o.error_query || !session_.transport.answers()) return true;
    if (!channel_.ask(DrainQuery::esc_e, "after the job")) return false;
    const long answer = channel_.last_answer();
    const StatusMeaning said = session_.host.meaning(DrainQuery::esc_e, answer);
    if (channel_.query_skipped() || (said != StatusMeaning::line_garbled && said != StatusMeaning::input_lost)) {
      return true;
    }
    const std::string code = std::to_string(answer);
    session_.result.device_io_error = static_cast<int>(answer);
    const std::string meaning =
        said == StatusMeaning::line_garbled ? "framing, parity or overrun errors on the line: bytes were garbled; "
                                              "check the baud rate, data bits, parity and "
                                              "stop bits of the profile against the device, and the cable"
        : session_.time_paced()
            ? "its input buffer overflowed: bytes were lost, so the cut is wrong; popcut paced "
              "the job by time (flow_control "
              "\"none\"), and the device is slower than the profile's kinematics and tool "
              "speeds allow with a pace margin of " +
                  std::to_string(o.pace_margin_percent) + " % (" + o.pace_margin_from +
                  "): raise it, or calibrate the device's pace; or its buffer is smaller than buffer_bytes"
            : "its input buffer overflowed: bytes were lost, so the cut is wrong; the device "
              "does not do the flow control the "
              "profile says (flow_control, buffer_bytes)";
    session_.result.status = {TransportError::io, 0,
                              "every byte went out, but the device reports I/O error " + code + " (" +
                                  session_.query_name(DrainQuery::esc_e) + "): " + meaning};
    return false;
  }

  // Every byte is out: wait until the device has executed them, by query or by estimate.
  void wait_until_drained() {
    const SendOptions& o = session_.options;
    const EncodedJob& job = session_.job;
    if (!session_.transport.answers() && o.motion.empty()) {
      session_.result.drained_by = DrainedBy::none;
      return;
    }
    // The device can hold at most a buffer's worth: that share of the job's motion time.
    const double share =
        job.bytes.empty()
            ? 0
            : std::min(1.0, static_cast<double>(accounting_.device_buffer()) / static_cast<double>(job.bytes.size()));
    const double motion_s = o.motion.empty() ? 0 : o.motion.back().start_s;
    const auto buffered_time = std::chrono::milliseconds(static_cast<long>(motion_s * share * 1000));
    if (session_.query == DrainQuery::none) {
      drain_by_estimate(buffered_time);
    } else {
      drain_by_answers(buffered_time);
    }
  }

  // No answers: time-paced, until the modelled device ends the job's motion; else a full buffer's share.
  void drain_by_estimate(std::chrono::milliseconds buffered_time) {
    SendResult& r = session_.result;
    auto wait = buffered_time;
    if (session_.time_paced()) {
      tracker_.all_out();  // drained out of popcut's side: the device has every byte
      advance_by_line(tracker_, session_.transport, r.bytes_sent);
      const double end_s = r.paused ? tracker_.time_past(r.bytes_sent) : tracker_.end_s();
      wait = std::chrono::milliseconds(
          static_cast<long>(std::ceil(std::max(0.0, end_s - tracker_.seconds()) * tracker_.slowdown() * 1000)));
    }
    std::chrono::milliseconds waited{0};
    while (waited < wait) {
      if (session_.cancel_requested()) {
        r.cancelled = true;
        return;
      }
      const auto step = std::min(kSlice, wait - waited);
      if (!channel_.take_replies(step)) return;
      waited += step;
    }
    r.drained_by = DrainedBy::estimate;
  }

  // A device that answers is working (or paused): it is given what its buffer should take to
  // cut, by the plan's estimate, plus hold_timeout; under ESC.B each answer with more free space
  // than before shows progress and restarts the hold_timeout.
  void drain_by_answers(std::chrono::milliseconds buffered_time) {
    SendResult& r = session_.result;
    const DrainQuery query = session_.query;
    std::chrono::milliseconds waited{0};
    StallClock stall;
    const std::chrono::milliseconds quiet = tracker_.quiet_for();
    for (int polls = 0;; ++polls) {
      if (session_.cancel_requested()) {
        r.cancelled = true;
        return;
      }
      if (!channel_.ask(query, "after the last byte")) return;
      // ESC.B: as much free as the device ever said it had (asked idle before the job, that is
      // its whole buffer). The profile's size can be wrong either way: 1024 free of 65536 is not
      // empty, and a 256-byte device never reports 1024 free.
      const long answer = channel_.last_answer();
      if (session_.host.meaning(query, answer) == StatusMeaning::idle) break;  // e.g. ESC.O bit 3: buffer empty
      if (query == DrainQuery::esc_b) {
        const auto free_now = static_cast<std::size_t>(std::max(0L, answer));
        if (free_now >= accounting_.device_buffer()) break;  // the whole buffer, by the profile or any answer
        stall.answered(answer);
        // As free as it ever said but less than the profile's size: a device smaller than the
        // profile says, now empty, or one that was busy when first asked and still holds what
        // it held then. Empty once it has read no byte for longer than any one command of the
        // job takes it (a device reads the next command when one ends).
        if (free_now >= accounting_.largest_free() && stall.stalled() >= quiet) break;
      }
      const auto hold_timeout = session_.options.hold_timeout;
      if (stall.stalled() >= hold_timeout && waited >= buffered_time + hold_timeout) {
        r.status = {
            TransportError::timeout, 0,
            "every byte reached the device, but its buffer is still not empty " + duration_text(waited) +
                " after the last byte (" +
                (query == DrainQuery::esc_b ? "no progress by its " + session_.query_name(query) + " answers for " +
                                                  duration_text(stall.stalled())
                                            : session_.query_name(query) + " says busy") +
                "; the plan expected about " + duration_text(buffered_time) +
                " for a full buffer, plus hold_timeout_ms): it answers, so it is paused or stuck; check it — if it "
                "finishes, the "
                "card is complete"};
        return;
      }
      const auto step = poll_backoff(polls);
      if (!channel_.take_replies(step)) return;
      waited += step;
      stall.waited(step);
    }
    r.drained_by = query == DrainQuery::esc_b     ? DrainedBy::esc_b
                   : query == DrainQuery::esc_enq ? DrainedBy::esc_enq
                                                  : DrainedBy::esc_o;
  }

  // Cancel: the profile's abort sequence and knife up, then how much the device may still hold.
  void send_abort() {
    SendResult& r = session_.result;
    channel_.aborting();  // from here a query's answer is waited for: it tells what the device holds
    // Recorded before the abort goes out, so that a crash meanwhile leaves counts that never
    // skip what the device is about to drop.
    accounting_.set_discarding(session_.options.abort_discards_buffer);
    if (accounting_.discarding()) report_progress();
    // Under XON/XOFF in the OS the abort waits for XON like any byte, up to the hold timeout:
    // the device is cutting its buffer meanwhile, and the abort is what stops it. In slices, so
    // that the user is told and may give up (options.give_up).
    r.abort_sent = line_.write_abort(session_.options.abort_bytes);
    // Not through (given up, the line failed): the device keeps its buffer and goes on cutting.
    if (!r.abort_sent) accounting_.set_discarding(false);
    estimate_buffered();
    r.buffer_discarded = accounting_.discarding();
  }

  // After a cancel or failure: final counts, how long a time-paced device may go on cutting, and
  // what it may still hold.
  void estimate_buffered() {
    SendResult& r = session_.result;
    Transport& t = session_.transport;
    if (r.status.ok()) channel_.take_replies(std::chrono::milliseconds(0));  // answers already on their way
    accounting_.ended_badly();
    settle_counts();
    if (session_.time_paced()) {
      // How long the device may go on cutting, at the paced rate: until the model would have
      // ended everything sent. A job sent to it again meanwhile would find its buffer part full.
      advance_by_line(tracker_, t, r.bytes_sent);
      const double done_s = tracker_.time_past(r.bytes_sent);
      // From where it last said it was, if it answers: one that fell silent (paused) may
      // resume with all it held then.
      const bool fell_silent = session_.query != DrainQuery::none && r.status.error == TransportError::timeout;
      const double from_s =
          fell_silent ? std::min(tracker_.seconds(), tracker_.time_at(accounting_.executed())) : tracker_.seconds();
      r.busy_for_s = std::max(0.0, done_s - from_s) * tracker_.slowdown();
    }
    // What the device may still cut: its buffer plus what is on its way to it.
    // Paced by time, what it holds is never more than its buffer (it loses the rest), plus what
    // may still reach it: not all that is not certainly received.
    accounting_.bound_buffered(session_.time_paced()
                                   ? std::min(r.bytes_sent, t.writes_acknowledged() ? 0 : t.in_flight())
                                   : r.bytes_sent - r.bytes_received);
    bool measured = false;
    if (t.answers() && session_.flow == FlowControl::esc_b && r.status.ok()) {
      const TransportStatus keep = r.status;
      if (channel_.ask(DrainQuery::esc_b, "after the cancel") && !channel_.query_skipped()) {
        accounting_.measured_buffered(channel_.last_answer());
        measured = true;
      }
      r.status = keep;
    }
    if (accounting_.discarding()) {
      if (measured && r.buffered_bytes > 0) {
        accounting_.set_discarding(false);  // it still holds job bytes after the abort: it kept its buffer
        settle_counts();
      } else {
        r.buffered_bytes = 0;  // it dropped what it held: it cuts nothing more
      }
    }
    accounting_.buffered_strokes();
  }

  SendSession session_;
  HeldLine line_;
  StatusChannel channel_;
  SendAccounting accounting_;
  MotionTracker tracker_;
  std::unique_ptr<Pacer> pacer_;
};

}  // namespace

const char* to_string(ReceivedCountedBy how) { return kReceivedCountedByNames.name(how).data(); }
const char* to_string(DrainedBy how) { return kDrainedByNames.name(how).data(); }
const char* to_string(DeviceStop why) { return kDeviceStopNames.name(why).data(); }

std::string pace_margin_from(const DeviceProfile& profile) {
  const TransportDefaults& t = profile.transport;
  std::string from = std::string(t.pace_margin_key()) + " in " + profile.source;
  if (!t.pace_measured) return from + ": the pace is not calibrated";
  const std::string& measured_in = profile.calibration.overlay.empty() ? profile.source : profile.calibration.overlay;
  return from + ", since [kinematics] time_factor in " + measured_in + " measured the pace";
}

SendOptions send_options(const DeviceProfile& profile) {
  SendOptions o;
  o.flow = profile.transport.flow;
  o.buffer_bytes = profile.transport.buffer_bytes;
  o.timeout = std::chrono::milliseconds(profile.transport.timeout_ms);
  o.hold_timeout = std::chrono::milliseconds(profile.transport.hold_timeout_ms);
  o.drain_query = profile.transport.drain_query;
  o.error_query = profile.transport.error_query;
  o.baud = profile.transport.baud;
  o.pace_margin_percent = profile.transport.pace_margin_in_use();
  o.pace_margin_from = pace_margin_from(profile);
  o.language = profile.language;
  const LanguageUnit& language = language_unit(profile.language);
  o.abort_bytes = profile.transport.abort + language.knife_up(profile);
  // The next job's pacing takes the head to be where the finish leaves it.
  if (profile.starts_at == StartsAt::origin) o.abort_bytes += language.park(profile);
  o.abort_discards_buffer = profile.transport.abort_discards_buffer;
  o.pause_bytes = language.knife_up(profile);
  if (profile.starts_at == StartsAt::origin) o.pause_bytes += language.park(profile);
  return o;
}

SendResult send_job(Transport& transport, const EncodedJob& job, const SendOptions& options) {
  return Sender(transport, job, options).run();
}

SendResult send_job(Transport& transport, std::string_view bytes, const SendOptions& options) {
  EncodedJob job;
  job.bytes = std::string(bytes);
  job.command_end = {job.bytes.size()};
  return send_job(transport, job, options);
}

}  // namespace popcut::drivers
