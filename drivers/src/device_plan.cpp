// One planning path for every caller that sends to a device (popcut cut, popcutd's planners).
#include "popcut/drivers/device_plan.h"

#include <cstdio>

#include "popcut/drivers/language.h"
#include "popcut/error.h"

namespace popcut::drivers {
namespace {

std::string fixed_mm(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

}  // namespace

NestLayout copies_layout(const StrokePlan& card, const DeviceProfile& profile, double gap_mm) {
  // media_of keeps a blade offset clear on every side for a card's corner arcs; the card's extent
  // holds them already.
  const NamedMedia m = media_of(profile, profile.name);
  const double margin_mm = 2 * profile.plan.blade_offset_mm;
  return nest_layout(card.extent(), m.width_mm + margin_mm, m.height_mm + margin_mm, gap_mm);
}

DevicePlan plan_for_device(const Pattern& pattern, const DeviceProfile& profile, const std::string& profile_source,
                           const Copies& copies) {
  DevicePlan d;
  d.plan = plan_strokes(pattern, profile.plan);
  d.layout = copies_layout(d.plan, profile, copies.gap_mm);
  if (copies.count != 1) {
    if (copies.count < 1 || copies.count > d.layout.count()) {
      const Rect e = d.plan.extent();
      throw Error(ErrorCode::invalid_input, profile_source, "copies",
                  std::to_string(copies.count) + " copies of this " + fixed_mm(e.max.x_mm - e.min.x_mm) + " x " +
                      fixed_mm(e.max.v_mm - e.min.v_mm) + " mm card do not fit one sheet of " + profile.name +
                      ": it holds " + std::to_string(d.layout.count()) + " (" + std::to_string(d.layout.columns) +
                      " x " + std::to_string(d.layout.rows) + ", " + fixed_mm(copies.gap_mm) + " mm apart)");
    }
    d.plan = nest_plan(d.plan, d.layout, copies.count);
  }
  try {
    // Figures and the time estimate count only what is sent: strokes that round to one plotter
    // point are not.
    d.plan = drop_below_resolution(d.plan, profile.dialect);
    // Each stroke at its own speed: a kind's passes may differ.
    d.time = estimate_time(d.plan, profile.kinematics,
                           [&](const Stroke& s) { return tool_for_stroke(profile.tools, s).speed_cm_s * 10; });
    d.encoded = encode_for_device(d.plan, profile);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    throw Error(e.code(), profile_source, e.location(), e.message());
  }
  return d;
}

NamedMedia media_of(const DeviceProfile& profile, const std::string& name) {
  const HpglDialect& d = profile.dialect;
  const double margin_mm = 2 * profile.plan.blade_offset_mm;
  const double x_mm = static_cast<double>(d.area_max_x_pu - d.area_min_x_pu - 1) / d.units_per_mm_x - margin_mm;
  const double y_mm = static_cast<double>(d.area_max_y_pu - d.area_min_y_pu - 1) / d.units_per_mm_y - margin_mm;
  return d.swap_axes ? NamedMedia{name, y_mm, x_mm} : NamedMedia{name, x_mm, y_mm};
}

}  // namespace popcut::drivers
