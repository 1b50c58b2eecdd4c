// The stroke counts and resume points popcut cut gives after a cancel or a failure.
#include "resume_advice.h"

#include <optional>

#include "cancel_text.h"

namespace popcut {

std::string counts_text(const drivers::SendResult& sent) {
  // Honest numbers: E = the last stroke the device is known to have executed, M = the last it
  // certainly received, N = the last written (E <= M <= N). A device that keeps its buffer and
  // goes on cutting needs M + 1 (strokes M+1..N may be cut twice); one that was reset or lost
  // power cut nothing of its buffer, so E + 1 (strokes E+1..M may have been cut already).
  const std::size_t m = sent.last_stroke_sent, n = sent.last_stroke_written;
  const std::optional<std::size_t> e = sent.last_stroke_executed;
  return "last stroke known executed " + (e ? std::to_string(*e) : std::string(sent.received_counted_by == drivers::ReceivedCountedBy::status_answers ? "unknown (the device did not say)" : "unknown (the device cannot be asked)")) +
                      ", last stroke certainly received " + std::to_string(m) + " of " + std::to_string(sent.total_strokes) +
                      " (" + (sent.buffer_discarded ? "what it executed: it had received up to stroke " + std::to_string(sent.received_before_abort) +
                                                          " and discarded the rest on the abort"
                               : m < sent.first_stroke ? std::string("none confirmed")
                               : sent.received_counted_by == drivers::ReceivedCountedBy::status_answers ? std::string("confirmed by the device's answers")
                               : sent.received_counted_by == drivers::ReceivedCountedBy::os_queue ? std::string("sent, less what the port may still hold")
                               : sent.received_counted_by == drivers::ReceivedCountedBy::buffer_size
                                   ? std::string("what its buffer holds from the start: with no handshake and no answers, a device that stopped lost the rest")
                                                                       : std::string("taken by the device")) +
                      "), last stroke written " + std::to_string(n);
}

std::string resume_advice(const drivers::SendResult& sent) {
  const std::size_t m = sent.last_stroke_sent, n = sent.last_stroke_written;
  const std::optional<std::size_t> e = sent.last_stroke_executed;
  std::string resume;
  if (sent.bytes_sent == 0) {
    resume = "; nothing was sent: run the same command again";
  } else if (sent.device_io_error != 0) {
    resume = "; what it cut is not the job, and no --resume-from can repair that: fix the profile (or the line) and cut the "
             "whole job again on a fresh sheet";
  } else if (sent.buffer_discarded) {
    // The abort made the device drop its buffer: what it received and had not cut is gone, so
    // M is E and one resume point covers the card; should it have ignored the abort, the old M.
    const std::size_t before = sent.received_before_abort;
    if (m < sent.total_strokes) {
      resume = "; the abort makes the device discard its buffer, so finish with the same command and --resume-from " +
               std::to_string(m + 1) + (e ? "" : " (what it executed is not known)");
      if (n > m) {
        resume += " (strokes " + std::to_string(m + 1) + ".." + std::to_string(n) +
                  " may have been cut before it stopped and are then cut a second time)";
      }
    } else {
      resume = "; the device had executed the whole job before the abort";
    }
    if (before > m && before < sent.total_strokes) {
      resume += "; if it ignored the abort and goes on cutting its buffer (it had received up to stroke " + std::to_string(before) +
                "), use --resume-from " + std::to_string(before + 1) + " instead";
    } else if (before > m) {
      resume += "; if it ignored the abort and goes on cutting its buffer, it has the whole job";
    }
  } else {
    // Two cases, two resume points: the device keeps its buffer and cuts it (no abort reached
    // it, or the abort keeps the buffer), or it was reset or power-cycled and lost it.
    std::string kept;
    if (m < sent.total_strokes) {
      kept = "if the device still holds its buffer and goes on cutting, finish with the same command and --resume-from " + std::to_string(m + 1);
      if (n > m) {
        kept += " (strokes " + std::to_string(m + 1) + ".." + std::to_string(n) + " may have been cut already and are then cut a second time)";
      }
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
    resume = "; " + kept + (lost.empty() ? "" : "; " + lost);
    // A failure says nothing of the buffer otherwise (a cancel does, in still_buffered_text).
    if (!sent.cancelled && sent.busy_for_s >= 0.5) resume = "; the device may go on cutting" + busy_text(sent) + resume;
  }
  return resume;
}

}  // namespace popcut
