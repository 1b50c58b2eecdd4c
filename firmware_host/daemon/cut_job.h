// A planned job on disk (jobs/ID/plan.json): the stroke plan a device worker encodes with
// core's encode_job, from stroke 1 or, resumed, from the first stroke not fully sent.
#pragma once

#include <string>

#include "popcut/plan/plan.h"

namespace popcut::daemon {

// A plan as JSON and back; doubles round-trip exactly, so a resumed job re-encodes to the very
// same plotter coordinates as the first run.
std::string plan_to_json(const StrokePlan& plan);
StrokePlan plan_from_json(const std::string& text, const std::string& source);

}  // namespace popcut::daemon
