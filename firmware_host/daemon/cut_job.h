// What a device worker sends: a planned job encoded for its device, with per-stroke byte offsets
// so progress counts strokes fully sent and an interrupted job resumes at a stroke boundary.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/plan/plan.h"

namespace popcut::daemon {

// The plan reduced to the strokes the encoder sends, framed so a tail of it encodes to exactly the
// same coordinates as the whole (its sheet is the whole plan's frame).
StrokePlan sendable_plan(const StrokePlan& plan, const drivers::DeviceProfile& profile);

struct EncodedCut {
  std::string bytes;                     // init, tools, strokes first_stroke.., finish
  std::vector<std::size_t> stroke_ends;  // byte offset just past each stroke's last coordinate
  std::vector<PlotterPath> paths;        // what the device should cut, for the simulator's check
};

// Encodes strokes [first_stroke, end) of a sendable plan; throws popcut::Error(internal) if
// the bytes do not hold one pen-down path per stroke.
EncodedCut encode_from(const StrokePlan& sendable, const drivers::DeviceProfile& profile, std::size_t first_stroke);

// Strokes whose every byte is within the first `bytes_sent`.
std::size_t strokes_sent(const EncodedCut& cut, std::size_t bytes_sent);

// A plan as JSON (job files) and back; doubles round-trip exactly.
std::string plan_to_json(const StrokePlan& plan);
StrokePlan plan_from_json(const std::string& text, const std::string& source);

}  // namespace popcut::daemon
