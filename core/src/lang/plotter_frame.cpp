// Plotter frame: rounds every pattern point once to absolute plotter units in the device's usable area.
#include "popcut/lang/plotter_frame.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
namespace {

// Local sheet coordinates (mm from the min corner) along the plotter's x and y axes.
std::array<double, 2> along_axes(Point2 p, const Rect& sheet, const PlotterFrame& f) {
  const double dx = p.x_mm - sheet.min.x_mm, dv = p.v_mm - sheet.min.v_mm;
  if (f.swap_axes) return {dv, dx};
  return {dx, dv};
}

// What the skew correction does to a point `a` mm along the plotter's x and `b` along its y, both
// counted from the sheet's corner in the direction the axes grow from it: the device's y axis
// leans toward its +x, so the point is commanded back by b·tan along +x (toward the origin corner
// or away from it, as the flips make those directions agree or not), and b stretched by 1/cos so
// the lean leaves the height right. Identity (bit for bit) without skew.
std::array<double, 2> deskewed(std::array<double, 2> ab, const PlotterFrame& f) {
  if (f.skew_deg == 0) return ab;
  const double rad = f.skew_deg * std::acos(-1.0) / 180;
  const double toward = f.flip_x == f.flip_y ? 1 : -1;
  return {ab[0] - toward * ab[1] * std::tan(rad), ab[1] / std::cos(rad)};
}

// The sheet's extent along the plotter's x once deskewed: its top edge shifts by height·tan.
std::array<double, 2> deskewed_x_range(const std::array<double, 2>& size, const PlotterFrame& f) {
  const double top_shift = deskewed({0, size[1]}, f)[0];
  return {std::min(0.0, top_shift), std::max(size[0], size[0] + top_shift)};
}

}  // namespace

PlotterPath stroke_in_plotter_units(const Stroke& s, const Rect& sheet, const Placement& placement,
                                    const PlotterFrame& f) {
  PlotterPath pts;
  for (Point2 p : s.points) {
    const auto q = to_plotter(p, sheet, placement, f);
    if (q[0] < f.area_min_x_pu || q[0] > f.area_max_x_pu || q[1] < f.area_min_y_pu || q[1] > f.area_max_y_pu ||
        (!f.allow_negative && (q[0] < 0 || q[1] < 0))) {
      throw Error(ErrorCode::internal, "", "hpgl",
                  "point (" + std::to_string(q[0]) + ", " + std::to_string(q[1]) +
                      ") plotter units lies outside the usable area; not sent");
    }
    if (pts.empty() || pts.back() != q) pts.push_back(q);
  }
  return pts;
}

std::vector<PlotterPath> plan_in_plotter_units(const StrokePlan& plan, const PlotterFrame& f) {
  // The frame placed is the sheet and everything the knife's axis visits (drag-knife arcs).
  const Rect frame = plan.extent();
  const Placement placement = place_sheet(frame, f);
  std::vector<PlotterPath> out;
  for (const Stroke& s : plan.strokes) {
    PlotterPath p = stroke_in_plotter_units(s, frame, placement, f);
    if (p.size() >= 2) out.push_back(std::move(p));
  }
  return out;
}

StrokePlan drop_below_resolution(const StrokePlan& plan, const PlotterFrame& f) {
  const Rect frame = plan.extent();
  const Placement placement = place_sheet(frame, f);
  StrokePlan out = plan;
  // The frame placed stays the same (a dropped stroke may have reached past the sheet), so every
  // kept point rounds exactly as it did.
  out.sheet = frame;
  out.strokes.clear();
  for (KindStats& k : out.kinds) k.strokes = k.pen_lifts = k.precuts = 0, k.cut_mm = k.travel_mm = 0;
  Point2 at = plan.home;
  for (const Stroke& s : plan.strokes) {
    KindStats& k = out.kinds[index_of(s.kind)];
    if (stroke_in_plotter_units(s, frame, placement, f).size() < 2) {
      ++k.strokes_below_resolution;
      continue;
    }
    // Travel to a kind's strokes counts for that kind, as in plan_strokes.
    k.travel_mm += travel_mm({s.points}, at);
    k.cut_mm += path_length_mm(s.points);
    ++(s.precut ? k.precuts : k.strokes);
    ++k.pen_lifts;
    at = s.points.back();
    out.strokes.push_back(s);
  }
  return out;
}

Placement place_sheet(const Rect& sheet, const PlotterFrame& f) {
  const std::array<double, 2> size = along_axes(sheet.max, sheet, f);
  const std::array<double, 2> x_range = deskewed_x_range(size, f);
  Placement p;
  // As to_plotter rounds the extreme points, so the fit check is exact.
  p.width_pu = std::llround(x_range[1] * f.units_per_mm_x) - std::llround(x_range[0] * f.units_per_mm_x);
  p.height_pu = std::llround(deskewed({0, size[1]}, f)[1] * f.units_per_mm_y);
  const std::int64_t avail_x = f.area_max_x_pu - f.area_min_x_pu, avail_y = f.area_max_y_pu - f.area_min_y_pu;
  if (p.width_pu > avail_x || p.height_pu > avail_y) {
    throw Error(ErrorCode::invalid_input, "", "usable area",
                "the sheet (" + format_fixed(size[0], 1) + " x " + format_fixed(size[1], 1) +
                    " mm on the plotter's axes) does not fit the "
                    "usable area (" +
                    format_fixed(static_cast<double>(avail_x) / f.units_per_mm_x, 1) + " x " +
                    format_fixed(static_cast<double>(avail_y) / f.units_per_mm_y, 1) + " mm)");
  }
  // The sheet sits in the corner the axes grow from: the usable area's min, or max when flipped.
  // With sheet_at_origin a flipped axis counts down from the sheet's far edge at the min corner.
  // A skewed top edge that shifts toward the origin corner moves the whole sheet in by as much.
  const auto origin = [&](bool flip, std::int64_t lo, std::int64_t hi, std::int64_t extent, std::int64_t lean) {
    if (!flip) return lo - lean;
    return (f.sheet_at_origin ? lo + extent : hi) + lean;
  };
  const std::int64_t lean_pu = std::llround(x_range[0] * f.units_per_mm_x);
  p.origin_x_pu = origin(f.flip_x, f.area_min_x_pu, f.area_max_x_pu, p.width_pu, lean_pu);
  p.origin_y_pu = origin(f.flip_y, f.area_min_y_pu, f.area_max_y_pu, p.height_pu, 0);
  return p;
}

std::array<std::int64_t, 2> to_plotter(Point2 pt, const Rect& sheet, const Placement& p, const PlotterFrame& f) {
  const std::array<double, 2> a = deskewed(along_axes(pt, sheet, f), f);
  const std::int64_t x = std::llround(a[0] * f.units_per_mm_x), y = std::llround(a[1] * f.units_per_mm_y);
  return {f.flip_x ? p.origin_x_pu - x : p.origin_x_pu + x, f.flip_y ? p.origin_y_pu - y : p.origin_y_pu + y};
}

}  // namespace popcut
