// Stroke planning: the pipeline from a pattern's lines to ordered strokes per tool (docs/architecture.md).
#include "popcut/plan/plan.h"

#include <algorithm>
#include <array>
#include <utility>

#include "plan/fold_clearance.h"
#include "plan/path_geometry.h"
#include "popcut/spatial_grid.h"

namespace popcut {

using plan_detail::kEps;
using plan_detail::lerp;

namespace {

// The sheet's four edges, anticlockwise from its min corner.
std::array<std::pair<Point2, Point2>, 4> sheet_edges(const Rect& s) {
  const Point2 c[4] = {s.min, {s.max.x_mm, s.min.v_mm}, s.max, {s.min.x_mm, s.max.v_mm}};
  return {{{c[0], c[1]}, {c[1], c[2]}, {c[2], c[3]}, {c[3], c[0]}}};
}

// A kind's paths, chained at the Euler bound and (perforate) cut into dashes, not yet ordered.
std::vector<std::vector<Point2>> kind_paths(const Pattern& pattern, PlanKind kind, const PlanOptions& options,
                                            KindStats& stats) {
  const KindPlan& kp = options.kinds[index_of(kind)];
  std::vector<std::pair<Point2, Point2>> segs;
  for (const Segment& s : kind_lines(pattern, kind, options.fold_gap_mm, &stats.folds_dropped))
    segs.emplace_back(s.a, s.b);
  segs = split_at_junctions(segs);
  stats.pen_lift_bound = euler_bound(segs);
  std::vector<std::vector<Point2>> paths = chain_edges(segs, options.max_turn_deg);
  if (kp.mode != ToolMode::perforate) return paths;
  std::vector<std::vector<Point2>> dashes;
  for (const auto& p : paths) {
    for (auto& d : perforate(p, kp.perforate_on_mm, kp.perforate_off_mm)) dashes.push_back(std::move(d));
  }
  return dashes;
}

// One pass's stroke (`tip`: the blade tip's path) after its precut if any.
void append_stroke(const std::vector<Point2>& tip, PlanKind kind, int pass, const PlanOptions& options,
                   StrokePlan& plan) {
  KindStats& stats = plan.kinds[index_of(kind)];
  if (const std::vector<Point2> pre = precut_path(tip, options.precut_mm); !pre.empty()) {
    // Turn the blade: cut the stroke's own first millimetres, lift, and start again there.
    Stroke ps{kind, blade_offset_path(pre, options.blade_offset_mm, options.swivel_step_deg), true, pass};
    stats.cut_mm += path_length_mm(ps.points);
    stats.travel_mm += path_length_mm(pre);  // back to the stroke's start, knife up
    ++stats.precuts;
    ++stats.pen_lifts;
    plan.strokes.push_back(std::move(ps));
  }
  Stroke s{kind, blade_offset_path(tip, options.blade_offset_mm, options.swivel_step_deg), false, pass};
  stats.cut_mm += path_length_mm(s.points);
  ++stats.strokes;
  ++stats.pen_lifts;
  plan.strokes.push_back(std::move(s));
}

// The ordered paths' strokes, one per path, or one per pass with separate passes; returns where
// the blade tip stops.
Point2 append_strokes(const std::vector<std::vector<Point2>>& paths, PlanKind kind, const PlanOptions& options,
                      Point2 at, StrokePlan& plan) {
  const KindPlan& kp = options.kinds[index_of(kind)];
  for (const auto& p : paths) {
    // Overcut closes a loop; the blade offset applies to every pass, turns included.
    const std::vector<Point2> closed = with_overcut(p, options.overcut_mm);
    if (!kp.separate_passes) {
      const std::vector<Point2> tip = with_passes(closed, kp.passes);
      append_stroke(tip, kind, 0, options, plan);
      at = tip.back();  // the next kind is ordered from where the blade tip stands
      continue;
    }
    const std::vector<std::vector<Point2>> passes = separate_passes(closed, kp.passes);
    for (std::size_t i = 0; i < passes.size(); ++i) append_stroke(passes[i], kind, static_cast<int>(i), options, plan);
    at = passes.back().back();
  }
  return at;
}

}  // namespace

const char* to_string(PlanKind kind) { return kPlanKindNames.name(kind).data(); }

std::size_t index_of(PlanKind kind) { return static_cast<std::size_t>(kind); }

const char* to_string(ToolMode mode) { return kToolModeNames.name(mode).data(); }

KindStats StrokePlan::total() const {
  KindStats t;
  for (const KindStats& k : kinds) {
    t.strokes += k.strokes;
    t.pen_lifts += k.pen_lifts;
    t.pen_lift_bound += k.pen_lift_bound;
    t.cut_mm += k.cut_mm;
    t.travel_mm += k.travel_mm;
    t.folds_dropped += k.folds_dropped;
    t.strokes_below_resolution += k.strokes_below_resolution;
    t.precuts += k.precuts;
  }
  return t;
}

Rect StrokePlan::extent() const {
  Rect r = sheet;
  for (const Stroke& s : strokes) {
    for (Point2 p : s.points) {
      r.min = {std::min(r.min.x_mm, p.x_mm), std::min(r.min.v_mm, p.v_mm)};
      r.max = {std::max(r.max.x_mm, p.x_mm), std::max(r.max.v_mm, p.v_mm)};
    }
  }
  return r;
}

std::vector<Segment> kind_lines(const Pattern& pattern, PlanKind kind, double fold_gap_mm, int* dropped) {
  std::vector<Segment> out;
  if (dropped) *dropped = 0;
  if (kind == PlanKind::outline) {
    for (const auto& [a, b] : sheet_edges(pattern.sheet)) out.push_back({LineKind::cut, a, b});
    return out;
  }
  const LineKind want =
      kind == PlanKind::cut ? LineKind::cut : (kind == PlanKind::valley ? LineKind::valley : LineKind::mountain);
  if (want == LineKind::cut || fold_gap_mm <= 0) {
    for (const Segment& l : pattern.lines) {
      if (l.kind == want) out.push_back(l);
    }
    return out;
  }
  // Cut lines and the outline's four edges in a grid, so each fold looks only at the cuts near it.
  std::vector<std::pair<Point2, Point2>> cuts;
  for (const Segment& l : pattern.lines) {
    if (l.kind == LineKind::cut) cuts.emplace_back(l.a, l.b);
  }
  for (const auto& edge : sheet_edges(pattern.sheet)) cuts.push_back(edge);
  SpatialGrid grid(pattern.sheet, cuts.size());
  for (std::size_t i = 0; i < cuts.size(); ++i)
    grid.insert_segment(static_cast<int>(i), cuts[i].first, cuts[i].second, kEps);
  std::vector<int> near_ids;
  std::vector<std::pair<Point2, Point2>> near;
  for (const Segment& l : pattern.lines) {
    if (l.kind != want) continue;
    // Every cut whose box comes within the gap of the fold's box.
    const double reach = fold_gap_mm + kEps;
    grid.ids_in_box({std::min(l.a.x_mm, l.b.x_mm) - reach, std::min(l.a.v_mm, l.b.v_mm) - reach},
                    {std::max(l.a.x_mm, l.b.x_mm) + reach, std::max(l.a.v_mm, l.b.v_mm) + reach}, near_ids);
    near.clear();
    for (int id : near_ids) near.push_back(cuts[static_cast<std::size_t>(id)]);
    // Euclidean clearance: a slanted cut takes gap / sin(angle) of the fold, not the gap.
    const auto pieces = plan_detail::clear_pieces(l.a, l.b, near, fold_gap_mm, kEps);
    if (pieces.empty() && dropped) ++*dropped;
    for (const auto& [t0, t1] : pieces) {
      out.push_back({l.kind, t0 == 0 ? l.a : lerp(l.a, l.b, t0), t1 == 1 ? l.b : lerp(l.a, l.b, t1)});
    }
  }
  return out;
}

StrokePlan plan_strokes(const Pattern& pattern, const PlanOptions& options) {
  StrokePlan plan;
  plan.sheet = pattern.sheet;
  plan.home = options.home.value_or(pattern.sheet.min);
  Point2 at = plan.home;
  for (PlanKind kind : options.order) {
    if (options.kinds[index_of(kind)].mode == ToolMode::skip) continue;
    KindStats& stats = plan.kinds[index_of(kind)];
    std::vector<std::vector<Point2>> paths =
        order_paths(kind_paths(pattern, kind, options, stats), at, options.optimise_work);
    for (auto& p : paths) p = without_straight_vertices(p);
    stats.travel_mm = travel_mm(paths, at);
    at = append_strokes(paths, kind, options, at, plan);
  }
  return plan;
}

}  // namespace popcut
