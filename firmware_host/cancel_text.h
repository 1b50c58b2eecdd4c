// What a stopped job's device may still cut from its buffer, in the words popcut cut and popcutd both use.
#pragma once

#include <string>

#include "popcut/drivers/job_sender.h"

namespace popcut {

// ", for up to 12 s (let it stop before sending it anything more)": a device paced by time that
// may go on cutting; a job sent meanwhile would find its buffer part full and overrun it.
inline std::string busy_text(const drivers::SendResult& sent) {
  return ", for up to " + std::to_string(static_cast<long>(sent.busy_for_s + 0.999)) +
         " s by the profile's pace (let it stop before sending it anything more, a resume too)";
}

// "up to 1180 bytes (strokes 17..24)", exact ("212 bytes ...") when the device answered ESC.B, or
// "nothing more".
// A device paced by time adds how long that may take: "..., for up to 12 s (let it stop before
// sending it anything more)".
inline std::string still_buffered_text(const drivers::SendResult& sent) {
  if (sent.buffered_bytes == 0) return "nothing more";
  std::string text = (sent.buffer_known ? "" : "up to ") + std::to_string(sent.buffered_bytes) + " bytes (strokes " +
                     std::to_string(sent.buffered_first_stroke) + ".." + std::to_string(sent.buffered_last_stroke) + ")";
  if (sent.busy_for_s >= 0.5) text += busy_text(sent);
  return text;
}

// "the device discarded its buffer on the abort: resuming starts after stroke 53 (strokes 54..58
// may have been cut before it stopped and are then cut again)", or "" when it kept its buffer.
inline std::string discarded_text(const drivers::SendResult& sent) {
  if (!sent.buffer_discarded) return "";
  const std::size_t m = sent.last_stroke_sent, n = sent.last_stroke_written;
  std::string text = "the device discarded its buffer on the abort: resuming starts after stroke " + std::to_string(m) +
                     (sent.last_stroke_executed ? "" : " (what it executed is not known)");
  if (n > m) text += " (strokes " + std::to_string(m + 1) + ".." + std::to_string(n) + " may have been cut before it stopped and are then cut again)";
  return text;
}

}  // namespace popcut
