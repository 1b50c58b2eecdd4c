// A planned job on disk (jobs/ID/plan.json, and plan-last.json for a last sheet that holds fewer
// copies): the stroke plan a device worker encodes, from stroke 1 or, resumed, from the first stroke not fully sent.
#pragma once

#include <cstdint>
#include <string>

#include "job.h"
#include "popcut/plan/plan.h"

namespace popcut::daemon {

// A plan as JSON and back; doubles round-trip exactly, so a resumed job re-encodes to the very
// same plotter coordinates as the first run.
std::string plan_to_json(const StrokePlan& plan);
StrokePlan plan_from_json(const std::string& text, const std::string& source);

// The sheet a run of `job` cuts once `done_before` of its strokes are done: that sheet's plan, read
// from `dir` (the job's directory), and the job's stroke numbers before it (a run never leaves its
// sheet: its stroke s is the job's offset + s).
struct SheetRun {
  StrokePlan plan;
  int sheet = 0;            // from 0
  std::int64_t offset = 0;  // strokes of the sheets before it
};
SheetRun sheet_run(const std::string& dir, const Job& job, std::int64_t done_before);

}  // namespace popcut::daemon
