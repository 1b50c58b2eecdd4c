// What a send did, in the words popcut cut and popcutd both use (where it stopped, how to resume, what the
// device may still cut) and as the `sent` object of popcut.cut.v1.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/profile.h"

namespace popcut::drivers {

// ", for up to 12 s by the profile's pace (let it stop before sending it anything more, a resume
// too)": a device paced by time that may go on cutting; a job sent meanwhile would find its
// buffer part full and overrun it.
std::string busy_text(const SendResult& sent);

// "up to 1180 bytes (strokes 17..24)", exact ("212 bytes ...") when the device answered ESC.B, or
// "nothing more"; a device paced by time adds how long that may take (busy_text).
std::string still_buffered_text(const SendResult& sent);

// "the device discarded its buffer on the abort: resuming starts after stroke 53 (strokes 54..58
// may have been cut before it stopped and are then cut again)", or "" when it kept its buffer.
std::string discarded_text(const SendResult& sent);

// "last stroke known executed 15, last stroke certainly received 41 of 62 (confirmed by the
// device's answers), last stroke written 44": E, M and N, and how M was counted.
std::string counts_text(const SendResult& sent);
// The same three numbers without the how: "last stroke known executed unknown, last stroke
// certainly received 41 of 62, last written 44".
std::string counts_brief(const SendResult& sent);

// "; if the device still holds its buffer and goes on cutting, finish with the same command and
// --resume-from 42 (...); if it was reset or power-cycled, ... --resume-from 16 (...)": the resume
// points that leave no stroke uncut, each with the case it is for ("" never: it starts with "; ").
std::string resume_advice(const SendResult& sent);

// A cancel in a clause: "sent the abort sequence and lifted the knife; the device may still cut
// up to 212 bytes (strokes 5..9) from its buffer unless it honours the abort sequence", by what
// the profile's abort does.
std::string cancel_text(const SendResult& sent, const TransportDefaults& transport);

// The `sent` object of a popcut.cut.v1 report; `job_bytes`: the size of the job this run sends.
nlohmann::json send_result_json(const SendResult& sent, std::size_t job_bytes);

}  // namespace popcut::drivers
