// One planning path for every caller that sends to a device (popcut cut, popcutd's planners).
#include "popcut/drivers/device_plan.h"

#include <algorithm>
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

namespace {

// `card`'s plan with `count` copies nested in `layout`, made ready to send: below-resolution strokes
// dropped, timed and encoded in the profile's language.
DevicePlan finished(const StrokePlan& card, const NestLayout& layout, int count, const DeviceProfile& profile,
                    const std::string& profile_source) {
  DevicePlan d;
  d.layout = layout;
  d.plan = count == 1 ? card : nest_plan(card, layout, count);
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

}  // namespace

DevicePlan plan_for_device(const Pattern& pattern, const DeviceProfile& profile, const std::string& profile_source,
                           const Copies& copies) {
  const StrokePlan card = plan_strokes(pattern, profile.plan);
  const NestLayout layout = copies_layout(card, profile, copies.gap_mm);
  if (copies.count != 1 && (copies.count < 1 || copies.count > layout.count())) {
    const Rect e = card.extent();
    throw Error(ErrorCode::invalid_input, profile_source, "copies",
                std::to_string(copies.count) + " copies of this " + fixed_mm(e.max.x_mm - e.min.x_mm) + " x " +
                    fixed_mm(e.max.v_mm - e.min.v_mm) + " mm card do not fit one sheet of " + profile.name +
                    ": it holds " + std::to_string(layout.count()) + " (" + std::to_string(layout.columns) + " x " +
                    std::to_string(layout.rows) + ", " + fixed_mm(copies.gap_mm) + " mm apart)");
  }
  return finished(card, layout, copies.count, profile, profile_source);
}

SheetPlans plan_sheets_for_device(const Pattern& pattern, const DeviceProfile& profile,
                                  const std::string& profile_source, const Copies& copies) {
  if (copies.count < 1) throw Error(ErrorCode::invalid_input, profile_source, "copies", "at least one copy");
  const StrokePlan card = plan_strokes(pattern, profile.plan);
  const NestLayout layout = copies_layout(card, profile, copies.gap_mm);
  SheetPlans s;
  // A card too big for the device nests none: planned alone, its encoding says why it does not fit.
  s.per_sheet = std::max(1, std::min(copies.count, layout.count()));
  s.sheets = (copies.count + s.per_sheet - 1) / s.per_sheet;
  s.full = finished(card, layout, s.per_sheet, profile, profile_source);
  const int last = copies.count - s.per_sheet * (s.sheets - 1);
  if (last != s.per_sheet) s.last = finished(card, layout, last, profile, profile_source);
  return s;
}

NamedMedia media_of(const DeviceProfile& profile, const std::string& name) {
  const HpglDialect& d = profile.dialect;
  const double margin_mm = 2 * profile.plan.blade_offset_mm;
  const double x_mm = static_cast<double>(d.area_max_x_pu - d.area_min_x_pu - 1) / d.units_per_mm_x - margin_mm;
  const double y_mm = static_cast<double>(d.area_max_y_pu - d.area_min_y_pu - 1) / d.units_per_mm_y - margin_mm;
  return d.swap_axes ? NamedMedia{name, y_mm, x_mm} : NamedMedia{name, x_mm, y_mm};
}

}  // namespace popcut::drivers
