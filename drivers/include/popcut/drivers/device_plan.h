// A pattern planned for one device profile exactly as it will be sent: the figures `popcut cut` and popcutd report.
#pragma once

#include <optional>
#include <string>

#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/mesh/import_request.h"
#include "popcut/pattern/pattern.h"
#include "popcut/plan/nest.h"
#include "popcut/plan/plan.h"

namespace popcut::drivers {

// Several copies of the card on one sheet of the device's media (popcut/plan/nest.h).
struct Copies {
  int count = 1;        // 1 .. 1000
  double gap_mm = 5.0;  // between neighbouring cards' extents (a drag knife's corners included)
};

struct DevicePlan {
  StrokePlan plan;     // strokes below the plotter's resolution dropped: what is sent
  NestLayout layout;   // the grid of cards the device's media holds (copies fill it row by row)
  TimeEstimate time;   // of `plan`, with the profile's kinematics and speeds
  EncodedJob encoded;  // the whole job, from stroke 1
};

// plan_strokes -> drop_below_resolution -> estimate_time -> encode_for_device (in the profile's
// language). A sheet that does not fit the device's usable area throws popcut::Error(invalid_input)
// naming `profile_source`: the pattern is fine, it is this device that is too small.
// With copies.count > 1 the card is planned once and nested (nest_plan) in the grid the device's
// usable area holds; more copies than fit throws Error(invalid_input) at "copies", saying how
// many fit.
DevicePlan plan_for_device(const Pattern& pattern, const DeviceProfile& profile, const std::string& profile_source,
                           const Copies& copies = {});
// Copies over as many sheets as they take: every sheet holds per_sheet cards but the last, which
// holds the rest (`last`, when fewer). Stroke numbers run on across sheets: sheet k (from 0)
// starts after k * full's strokes.
struct SheetPlans {
  DevicePlan full;
  std::optional<DevicePlan> last;
  int per_sheet = 1;
  int sheets = 1;
  const DevicePlan& sheet(int k) const { return k + 1 == sheets && last ? *last : full; }
  std::size_t total_strokes() const {
    return static_cast<std::size_t>(sheets - 1) * full.encoded.total_strokes + sheet(sheets - 1).encoded.total_strokes;
  }
  double total_time_s() const { return (sheets - 1) * full.time.total_s + sheet(sheets - 1).time.total_s; }
};
// As plan_for_device, with no limit on copies: as many sheets as they need.
SheetPlans plan_sheets_for_device(const Pattern& pattern, const DeviceProfile& profile,
                                  const std::string& profile_source, const Copies& copies);

// The grid of `card` (a card's plan) that the device's usable area holds.
NestLayout copies_layout(const StrokePlan& card, const DeviceProfile& profile, double gap_mm);

// The largest sheet the device takes, as plan_for_device places it: the usable area with the
// sheet's x along the plotter's x (its y with swap_axes), less the blade offset on every side
// (a drag knife's corner arcs reach that far past the sheet's edge) and one plotter unit for rounding.
NamedMedia media_of(const DeviceProfile& profile, const std::string& name);

}  // namespace popcut::drivers
