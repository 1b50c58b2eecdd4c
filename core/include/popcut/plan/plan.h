// Stroke planning: a pattern's lines as ordered, chained knife-down paths, per tool, in mm.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "popcut/pattern/pattern.h"
#include "popcut/plan/chaining.h"
#include "popcut/plan/order.h"
#include "popcut/plan/time_model.h"
#include "popcut/plan/tool_paths.h"

namespace popcut {

// What a tool does: planning knows line kinds and modes, never devices.
enum class PlanKind { valley, mountain, cut, outline };
inline constexpr std::array<PlanKind, 4> kAllPlanKinds = {PlanKind::valley, PlanKind::mountain, PlanKind::cut,
                                                          PlanKind::outline};
inline constexpr auto kPlanKindNames = enum_names<PlanKind>({{PlanKind::valley, "valley"},
                                                             {PlanKind::mountain, "mountain"},
                                                             {PlanKind::cut, "cut"},
                                                             {PlanKind::outline, "outline"}});
const char* to_string(PlanKind kind);
std::size_t index_of(PlanKind kind);

enum class ToolMode { cut, score, perforate, skip };
inline constexpr auto kToolModeNames = enum_names<ToolMode>(
    {{ToolMode::cut, "cut"}, {ToolMode::score, "score"}, {ToolMode::perforate, "perforate"}, {ToolMode::skip, "skip"}});
const char* to_string(ToolMode mode);

// How one line kind is drawn. Score differs from cut only in force (the encoder's business).
struct KindPlan {
  ToolMode mode = ToolMode::cut;
  int passes = 1;                 // more than one: back and forth along the stroke, knife down
  double perforate_on_mm = 1.0;   // perforate: cut this long...
  double perforate_off_mm = 1.0;  // ...then leave this much uncut; dashes start and end uncut
  // Each pass a stroke of its own (Stroke::pass), alternating direction, so each pass can be
  // cut with its own force and speed (a light first pass, a full second one); the knife lifts
  // between passes. Off: one stroke carries every pass.
  bool separate_passes = false;
};

struct PlanOptions {
  double fold_gap_mm = 0.5;            // no scored fold point is nearer than this to a cut line or the outline
  std::optional<double> max_turn_deg;  // lift the knife where a stroke turns more sharply
  std::vector<PlanKind> order = {PlanKind::valley, PlanKind::mountain, PlanKind::cut, PlanKind::outline};
  std::array<KindPlan, 4> kinds{};  // indexed by index_of(PlanKind)
  // Work for 2-opt and Or-opt per kind after the greedy order, in counted steps (move
  // evaluations and elements moved), not time: the same input always gives the same plan.
  // 0 = greedy only.
  std::uint64_t optimise_work = kDefaultOptimiseWork;
  std::optional<Point2> home;  // where the knife starts; default the sheet's min corner
  // Drag knife: the blade tip trails the tool axis by this much; the axis path is offset ahead
  // along each segment with swivel arcs at the corners. 0: a tangential knife (or a pen).
  double blade_offset_mm = 0;
  double swivel_step_deg = 15;  // chord step of the swivel arcs
  double overcut_mm = 0;        // closed loops: cut on past the start so they close cleanly
  // Drag knife: before each stroke, cut its first precut_mm (along its own first segment, never
  // past it), lift and start the stroke there, so the blade already points the right way. 0: off.
  double precut_mm = 0;
};

// One knife-down path: the knife lowers at points.front() and lifts at points.back().
struct Stroke {
  PlanKind kind = PlanKind::cut;
  std::vector<Point2> points;
  bool precut = false;  // a blade-turning cut along the next stroke's start (PlanOptions::precut_mm)
  int pass = 0;         // which of its kind's passes, from 0 (KindPlan::separate_passes; else 0)
  friend bool operator==(const Stroke&, const Stroke&) = default;
};

struct KindStats {
  int strokes = 0;
  int pen_lifts = 0;                 // strokes + precuts: every knife-down path ends with a lift
  int precuts = 0;                   // blade-turning cuts before strokes (not counted in strokes)
  int pen_lift_bound = 0;            // Euler bound of the kind's line graph (before perforation)
  double cut_mm = 0;                 // knife-down length, all passes and precuts
  double travel_mm = 0;              // knife-up length travelled to reach this kind's strokes
  int folds_dropped = 0;             // folds with nothing left to score once the gap is kept from every cut
  int strokes_below_resolution = 0;  // round to one plotter point: not sent, not counted above
};

struct StrokePlan {
  Rect sheet;
  Point2 home;
  std::vector<Stroke> strokes;  // in cutting order
  std::array<KindStats, 4> kinds{};
  KindStats total() const;
  // The sheet and every stroke point: a drag knife's axis path may pass the sheet's edge.
  Rect extent() const;
};

// The whole plan: fold gaps, chaining, perforation, ordering, passes and tool paths. Deterministic.
StrokePlan plan_strokes(const Pattern& pattern, const PlanOptions& options = {});

// Parts, exposed for tests and benchmarks; the pipeline's other steps have their own headers
// (chaining.h, order.h, tool_paths.h, time_model.h), included above.

// Lines of one kind after the fold gap (for folds: the pieces at least fold_gap_mm, in the plane,
// from every cut and the sheet's edge); the outline kind yields the sheet's edges.
std::vector<Segment> kind_lines(const Pattern& pattern, PlanKind kind, double fold_gap_mm, int* dropped = nullptr);

}  // namespace popcut
