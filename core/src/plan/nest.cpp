// Nesting copies of a card: a grid that fits the media, and the card's strokes replayed kind by kind over it.
#include "popcut/plan/nest.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "popcut/plan/order.h"

namespace popcut {
namespace {

// How many of `size` fit `room` with `gap` between neighbours (a tiny slack for rounding).
int fitting(double size, double room, double gap) {
  if (size <= 0 || room + 1e-9 < size) return 0;
  return 1 + static_cast<int>(std::floor((room - size) / (size + gap) + 1e-9));
}

// The card's strokes cut together: one kind, in the card's order, or every outline.
struct Run {
  std::size_t begin = 0, end = 0;
};

std::vector<Run> kind_runs(const StrokePlan& card) {
  std::vector<Run> runs;
  for (std::size_t i = 0; i < card.strokes.size(); ++i) {
    if (card.strokes[i].kind == PlanKind::outline) continue;
    if (runs.empty() || card.strokes[runs.back().end - 1].kind != card.strokes[i].kind || runs.back().end != i)
      runs.push_back({i, i + 1});
    else
      runs.back().end = i + 1;
  }
  return runs;
}

}  // namespace

NestLayout nest_layout(const Rect& card, double media_x_mm, double media_y_mm, double gap_mm) {
  if (!(gap_mm >= 0)) throw std::invalid_argument("nest_layout: gap_mm must be >= 0");
  NestLayout l;
  l.gap_mm = gap_mm;
  l.columns = fitting(card.max.x_mm - card.min.x_mm, media_x_mm, gap_mm);
  l.rows = fitting(card.max.v_mm - card.min.v_mm, media_y_mm, gap_mm);
  if (l.count() == 0) l.columns = l.rows = 0;
  return l;
}

StrokePlan nest_plan(const StrokePlan& card, const NestLayout& layout, int copies) {
  if (copies < 1 || copies > layout.count())
    throw std::invalid_argument("nest_plan: copies must be 1 .. the layout's count");
  const Rect extent = card.extent();
  const double step_x = extent.max.x_mm - extent.min.x_mm + layout.gap_mm;
  const double step_y = extent.max.v_mm - extent.min.v_mm + layout.gap_mm;
  // Serpentine: along the first row, back along the second, ...
  std::vector<Point2> offsets;
  for (int i = 0; i < copies; ++i) {
    const int row = i / layout.columns, k = i % layout.columns;
    const int col = row % 2 == 0 ? k : layout.columns - 1 - k;
    offsets.push_back({col * step_x, row * step_y});
  }
  const int used_rows = (copies + layout.columns - 1) / layout.columns;
  const int used_cols = std::min(copies, layout.columns);
  StrokePlan out;
  out.home = card.home;
  out.sheet = {card.sheet.min,
               {card.sheet.max.x_mm + (used_cols - 1) * step_x, card.sheet.max.v_mm + (used_rows - 1) * step_y}};
  std::vector<Run> runs = kind_runs(card);
  Run outlines;  // every outline stroke, in the card's order, after everything else
  for (std::size_t i = 0; i < card.strokes.size(); ++i) {
    if (card.strokes[i].kind != PlanKind::outline) continue;
    if (outlines.end == outlines.begin) outlines.begin = i;
    outlines.end = i + 1;
  }
  if (outlines.end > outlines.begin) runs.push_back(outlines);
  for (const Run& run : runs) {
    for (const Point2& off : offsets) {
      for (std::size_t i = run.begin; i < run.end; ++i) {
        const Stroke& s = card.strokes[i];
        if (run.begin == outlines.begin && run.end == outlines.end && s.kind != PlanKind::outline) continue;
        Stroke moved = s;
        for (Point2& p : moved.points) p = {p.x_mm + off.x_mm, p.v_mm + off.v_mm};
        out.strokes.push_back(std::move(moved));
      }
    }
  }
  Point2 at = out.home;
  for (std::size_t k = 0; k < out.kinds.size(); ++k) {
    const KindStats& c = card.kinds[k];
    const auto n = static_cast<int>(copies);
    out.kinds[k].pen_lift_bound = c.pen_lift_bound * n;
    out.kinds[k].folds_dropped = c.folds_dropped * n;
    out.kinds[k].strokes_below_resolution = c.strokes_below_resolution * n;
  }
  for (const Stroke& s : out.strokes) {
    KindStats& k = out.kinds[index_of(s.kind)];
    k.travel_mm += travel_mm({s.points}, at);
    k.cut_mm += path_length_mm(s.points);
    ++(s.precut ? k.precuts : k.strokes);
    ++k.pen_lifts;
    at = s.points.back();
  }
  return out;
}

}  // namespace popcut
