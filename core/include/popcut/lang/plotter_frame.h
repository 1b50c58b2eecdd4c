// A device's coordinate frame, shared by every cutter language: plotter units, axes, usable area, placement.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "popcut/plan/plan.h"

namespace popcut {

// Where the device's axes run and what it can reach, filled from a profile's [device] section.
struct PlotterFrame {
  double units_per_mm_x = 40;  // calibratable: real devices differ by about 0.5 %
  double units_per_mm_y = 40;
  // Calibration: the device's y axis leans this far toward its +x (the angle between its axes is
  // 90° minus this), so every point is sheared back along x by y·tan and y stretched by 1/cos.
  double skew_deg = 0;
  bool swap_axes = false;  // plotter x runs along the pattern's v; alone a mirror, with one flip a quarter turn
  bool flip_x = false;     // plotter x grows the other way (after any swap)
  bool flip_y = false;
  // The sheet sits at the usable area's min corner on a flipped axis too (its far edge there),
  // instead of against the max edge: devices whose origin is the sheet's corner (GP-GL).
  bool sheet_at_origin = false;
  std::int64_t area_min_x_pu = 0, area_min_y_pu = 0;  // usable area, in plotter units
  std::int64_t area_max_x_pu = 0, area_max_y_pu = 0;
  bool allow_negative = false;
};

// Where the sheet's min corner lands, in absolute plotter units, and how pattern mm map there.
struct Placement {
  std::int64_t origin_x_pu = 0, origin_y_pu = 0;
  std::int64_t width_pu = 0, height_pu = 0;  // the sheet's extent on the plotter axes
};

// Puts `sheet` (encoders pass StrokePlan::extent(): the sheet and any drag-knife arcs past its
// edge) at the usable area's origin corner; throws popcut::Error (invalid_input) when it does not
// fit, naming both sizes in mm.
Placement place_sheet(const Rect& sheet, const PlotterFrame& frame);

// Absolute plotter coordinates of a pattern point, rounded once (every move derives from these).
std::array<std::int64_t, 2> to_plotter(Point2 p, const Rect& sheet, const Placement& placement,
                                       const PlotterFrame& frame);

using PlotterPath = std::vector<std::array<std::int64_t, 2>>;

// One stroke's points in absolute plotter units, consecutive repeats merged. Throws popcut::Error
// when a point would leave the usable area (never sent).
PlotterPath stroke_in_plotter_units(const Stroke& stroke, const Rect& sheet, const Placement& placement,
                                    const PlotterFrame& frame);

// Every stroke in absolute plotter units, consecutive repeats merged and strokes that round to a
// single point dropped: exactly the knife-down paths an encoder sends (and a device should cut).
// Throws popcut::Error when a point would leave the usable area (never sent).
std::vector<PlotterPath> plan_in_plotter_units(const StrokePlan& plan, const PlotterFrame& frame);

// The plan as the device will get it: strokes that round to a single plotter point (encoders
// never send them) are removed and counted in strokes_below_resolution; strokes, pen_lifts,
// cut_mm and travel_mm are recomputed from what is left. Throws like plan_in_plotter_units.
StrokePlan drop_below_resolution(const StrokePlan& plan, const PlotterFrame& frame);

}  // namespace popcut
