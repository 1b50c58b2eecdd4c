// The words and the JSON of a SendResult, shared by popcut cut and popcutd.
#include "popcut/drivers/send_report.h"

#include <optional>

namespace popcut::drivers {

using nlohmann::json;

std::string busy_text(const SendResult& sent) {
  return ", for up to " + std::to_string(static_cast<long>(sent.busy_for_s + 0.999)) +
         " s by the profile's pace (let it stop before sending it anything more, a resume too)";
}

std::string still_buffered_text(const SendResult& sent) {
  if (sent.buffered_bytes == 0) return "nothing more";
  std::string text = (sent.buffer_known ? "" : "up to ") + std::to_string(sent.buffered_bytes) + " bytes (strokes " +
                     std::to_string(sent.buffered_first_stroke) + ".." + std::to_string(sent.buffered_last_stroke) +
                     ")";
  if (sent.busy_for_s >= 0.5) text += busy_text(sent);
  return text;
}

std::string discarded_text(const SendResult& sent) {
  if (!sent.buffer_discarded) return "";
  const std::size_t m = sent.last_stroke_sent, n = sent.last_stroke_written;
  std::string text = "the device discarded its buffer on the abort: resuming starts after stroke " + std::to_string(m) +
                     (sent.last_stroke_executed ? "" : " (what it executed is not known)");
  if (n > m)
    text += " (strokes " + std::to_string(m + 1) + ".." + std::to_string(n) +
            " may have been cut before it stopped and are then cut again)";
  return text;
}

namespace {

// How M was counted, for counts_text.
std::string received_how(const SendResult& sent) {
  if (sent.buffer_discarded) {
    return "what it executed: it had received up to stroke " + std::to_string(sent.received_before_abort) +
           " and discarded the rest on the abort";
  }
  if (sent.last_stroke_sent < sent.first_stroke) return "none confirmed";
  switch (sent.received_counted_by) {
    case ReceivedCountedBy::status_answers: return "confirmed by the device's answers";
    case ReceivedCountedBy::os_queue: return "sent, less what the port may still hold";
    case ReceivedCountedBy::buffer_size:
      return "what its buffer holds from the start: with no handshake and no answers, a device that stopped lost the "
             "rest";
    case ReceivedCountedBy::transport: break;
  }
  return "taken by the device";
}

// The abort made the device drop its buffer: what it received and had not cut is gone, so M is E
// and one resume point covers the card; should it have ignored the abort, the old M.
std::string discarded_resume(const SendResult& sent) {
  const std::size_t m = sent.last_stroke_sent, n = sent.last_stroke_written, before = sent.received_before_abort;
  std::string resume;
  if (m < sent.total_strokes) {
    resume = "; the abort makes the device discard its buffer, so finish with the same command and --resume-from " +
             std::to_string(m + 1) + (sent.last_stroke_executed ? "" : " (what it executed is not known)");
    if (n > m) {
      resume += " (strokes " + std::to_string(m + 1) + ".." + std::to_string(n) +
                " may have been cut before it stopped and are then cut a second time)";
    }
  } else {
    resume = "; the device had executed the whole job before the abort";
  }
  if (before > m && before < sent.total_strokes) {
    resume += "; if it ignored the abort and goes on cutting its buffer (it had received up to stroke " +
              std::to_string(before) + "), use --resume-from " + std::to_string(before + 1) + " instead";
  } else if (before > m) {
    resume += "; if it ignored the abort and goes on cutting its buffer, it has the whole job";
  }
  return resume;
}

// Two cases, two resume points: the device keeps its buffer and cuts it (no abort reached it, or
// the abort keeps the buffer), or it was reset or power-cycled and lost it.
std::string kept_or_lost_resume(const SendResult& sent) {
  const std::size_t m = sent.last_stroke_sent, n = sent.last_stroke_written;
  const std::optional<std::size_t> e = sent.last_stroke_executed;
  std::string kept;
  if (m < sent.total_strokes) {
    kept = "if the device still holds its buffer and goes on cutting, finish with the same command and --resume-from " +
           std::to_string(m + 1);
    if (n > m)
      kept += " (strokes " + std::to_string(m + 1) + ".." + std::to_string(n) +
              " may have been cut already and are then cut a second time)";
  } else {
    kept = "if the device still holds its buffer and goes on cutting, it has the whole job";
  }
  // After a reset or a power cycle the buffer is gone: only what it executed is cut.
  const std::size_t safe = e ? *e + 1 : sent.first_stroke;
  std::string lost;
  if (safe <= m) {
    lost = "if it was reset or power-cycled, or lost its buffer, use --resume-from " + std::to_string(safe) + " (" +
           (e ? "" : "what it executed is not known: ") + "strokes " + std::to_string(safe) + ".." + std::to_string(m) +
           " may have been cut already)";
  }
  std::string resume = "; " + kept + (lost.empty() ? "" : "; " + lost);
  // A failure says nothing of the buffer otherwise (a cancel does, in still_buffered_text).
  if (!sent.cancelled && sent.busy_for_s >= 0.5) resume = "; the device may go on cutting" + busy_text(sent) + resume;
  return resume;
}

}  // namespace

std::string counts_text(const SendResult& sent) {
  // Honest numbers: E = the last stroke the device is known to have executed, M = the last it
  // certainly received, N = the last written (E <= M <= N). A device that keeps its buffer and
  // goes on cutting needs M + 1 (strokes M+1..N may be cut twice); one that was reset or lost
  // power cut nothing of its buffer, so E + 1 (strokes E+1..M may have been cut already).
  const std::optional<std::size_t> e = sent.last_stroke_executed;
  const std::string executed = e ? std::to_string(*e)
                                 : std::string(sent.received_counted_by == ReceivedCountedBy::status_answers
                                                   ? "unknown (the device did not say)"
                                                   : "unknown (the device cannot be asked)");
  return "last stroke known executed " + executed + ", last stroke certainly received " +
         std::to_string(sent.last_stroke_sent) + " of " + std::to_string(sent.total_strokes) + " (" +
         received_how(sent) + "), last stroke written " + std::to_string(sent.last_stroke_written);
}

std::string counts_brief(const SendResult& sent) {
  return "last stroke known executed " +
         (sent.last_stroke_executed ? std::to_string(*sent.last_stroke_executed) : std::string("unknown")) +
         ", last stroke certainly received " + std::to_string(sent.last_stroke_sent) + " of " +
         std::to_string(sent.total_strokes) + ", last written " + std::to_string(sent.last_stroke_written);
}

std::string resume_advice(const SendResult& sent) {
  if (sent.bytes_sent == 0) return "; nothing was sent: run the same command again";
  if (sent.device_io_error != 0) {
    return "; what it cut is not the job, and no --resume-from can repair that: fix the profile (or the line) and cut "
           "the "
           "whole job again on a fresh sheet";
  }
  return sent.buffer_discarded ? discarded_resume(sent) : kept_or_lost_resume(sent);
}

std::string cancel_text(const SendResult& sent, const TransportDefaults& transport) {
  const std::string abort = sent.abort_sent
                                ? (transport.abort.empty() ? "lifted the knife (the profile names no abort sequence)"
                                                           : "sent the abort sequence and lifted the knife")
                                : "could NOT send the abort sequence: " + sent.status.message;
  const std::string left = sent.buffer_discarded
                               ? "; the device discarded its buffer on it and cuts nothing more"
                               : "; the device may still cut " + still_buffered_text(sent) + " from its buffer";
  // Known, or an abort that keeps the buffer: the figure stands.
  const bool unless = !sent.buffer_discarded && sent.buffered_bytes != 0 && sent.abort_sent && !sent.buffer_known &&
                      transport.abort_discards_buffer;
  return abort + left + (unless ? " unless it honours the abort sequence" : "");
}

json send_result_json(const SendResult& sent, std::size_t job_bytes) {
  return {
      {"bytes", sent.bytes_sent},
      {"bytes_total", job_bytes},
      {"complete", sent.complete()},
      {"cancelled", sent.cancelled},
      {"abort_sent", sent.abort_sent},
      {"buffer_discarded", sent.buffer_discarded},
      {"error", sent.status.ok() ? "" : std::string(to_string(sent.status.error))},
      {"message", sent.status.message},
      {"first_stroke", sent.first_stroke},
      {"bytes_received", sent.bytes_received},
      {"received_counted_by", to_string(sent.received_counted_by)},
      {"last_stroke_sent", sent.last_stroke_sent},
      {"last_stroke_written", sent.last_stroke_written},
      {"last_stroke_executed", sent.last_stroke_executed ? json(*sent.last_stroke_executed) : json(nullptr)},
      {"total_strokes", sent.total_strokes},
      {"buffered_bytes", sent.buffered_bytes},
      {"buffer_known", sent.buffer_known},
      {"buffered_strokes",
       sent.buffered_bytes == 0 ? json(nullptr) : json::array({sent.buffered_first_stroke, sent.buffered_last_stroke})},
      {"status_queries", sent.status_queries},
      {"drained_by", to_string(sent.drained_by)},
      {"holds", sent.holds},
      {"buffer_queries", sent.buffer_queries},
      {"device_io_error", sent.device_io_error == 0 ? json(nullptr) : json(sent.device_io_error)},
      {"device_stop", sent.device_stop == DeviceStop::none ? json(nullptr) : json(to_string(sent.device_stop))},
      {"busy_for_s", sent.busy_for_s}};
}

}  // namespace popcut::drivers
