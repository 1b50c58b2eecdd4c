// What a stopped job's device may still cut from its buffer, in the words popcut cut and popcutd both use.
#pragma once

#include <string>

#include "popcut/drivers/job_sender.h"

namespace popcut {

// "up to 1180 bytes (strokes 17..24)", exact ("212 bytes ...") when the device answered ESC.B, or
// "nothing more".
inline std::string still_buffered_text(const drivers::SendResult& sent) {
  if (sent.buffered_bytes == 0) return "nothing more";
  return (sent.buffer_known ? "" : "up to ") + std::to_string(sent.buffered_bytes) + " bytes (strokes " +
         std::to_string(sent.buffered_first_stroke) + ".." + std::to_string(sent.buffered_last_stroke) + ")";
}

}  // namespace popcut
