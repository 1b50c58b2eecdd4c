// What popcut cut says after a job that did not get through whole: the stroke counts and where to resume from.
#pragma once

#include <string>

#include "popcut/drivers/job_sender.h"

namespace popcut {

// "last stroke known executed 15, last stroke certainly received 41 of 62 (confirmed by the
// device's answers), last stroke written 44": E, M and N, and how M was counted.
std::string counts_text(const drivers::SendResult& sent);
// "; if the device still holds its buffer and goes on cutting, finish with the same command and
// --resume-from 42 (...); if it was reset or power-cycled, ... --resume-from 16 (...)": the resume
// points that leave no stroke uncut, each with the case it is for ("" never: it starts with "; ").
std::string resume_advice(const drivers::SendResult& sent);

}  // namespace popcut
