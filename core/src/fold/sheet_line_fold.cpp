// Folding a flat-folded sheet along a new line through every layer it crosses (cut-and-fold paper §2.2.2).
#include <algorithm>
#include <cmath>

#include "popcut/error.h"
#include "popcut/fold/sheet_fold.h"
#include "popcut/spatial_grid.h"
#include "popcut/text.h"

namespace popcut {
namespace {

// Rounding the poses leave, far below any drawn feature.
constexpr double kFlatMm = 1e-6;

double cross(Point2 a, Point2 b, Point2 p) {
  return (b.x_mm - a.x_mm) * (p.v_mm - a.v_mm) - (b.v_mm - a.v_mm) * (p.x_mm - a.x_mm);
}

// The inverse of a flat pose (it maps the sheet's plane onto itself, perhaps turned over).
Point2 unapply(const Pose& pose, Point2 world) {
  const double x = world.x_mm - pose.t.x_mm, y = world.v_mm - pose.t.y_mm, z = -pose.t.z_mm;
  return {pose.r[0] * x + pose.r[3] * y + pose.r[6] * z, pose.r[1] * x + pose.r[4] * y + pose.r[7] * z};
}

Point2 world_of(const Pose& pose, Point2 p) {
  const Point3 q = apply(pose, p);
  return {q.x_mm, q.y_mm};
}

bool face_up(const Pose& pose) { return pose.r[8] > 0; }

void require_flat(const FoldableSheet& s, const SheetState& state) {
  for (std::size_t r = 0; r < s.map.regions.size(); ++r) {
    const Pose& p = state.poses[r];
    if (s.cut_out[r] || (std::abs(std::abs(p.r[8]) - 1) < 1e-12 && std::abs(p.t.z_mm) < kFlatMm)) continue;
    throw Error(ErrorCode::invalid_input, s.source, "--fold-line",
                "folding along a line needs the sheet folded flat (every crease at 0 or ±180°); region " +
                    std::to_string(r) + " (around " + describe_place(s.map.regions[r].label) +
                    ") stands out of the plane");
  }
}

// Where the infinite line a→b runs inside the region (outer ring minus holes): its pieces.
std::vector<std::pair<Point2, Point2>> clip(const SheetRegion& region, Point2 a, Point2 b) {
  std::vector<double> ts;
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm;
  const auto cut_ring = [&](const Ring& ring) {
    for (std::size_t i = 0; i < ring.size(); ++i) {
      const Point2 p = ring[i], q = ring[(i + 1) % ring.size()];
      const double sp = cross(a, b, p), sq = cross(a, b, q);
      if ((sp > 0) == (sq > 0) || sp == sq) continue;
      const double u = sp / (sp - sq);
      const Point2 x{p.x_mm + u * (q.x_mm - p.x_mm), p.v_mm + u * (q.v_mm - p.v_mm)};
      ts.push_back(((x.x_mm - a.x_mm) * dx + (x.v_mm - a.v_mm) * dv) / (dx * dx + dv * dv));
    }
  };
  cut_ring(region.outer);
  for (const Ring& h : region.holes) cut_ring(h);
  std::sort(ts.begin(), ts.end());
  std::vector<std::pair<Point2, Point2>> pieces;
  // Crossings alternate in and out along the line; pieces shorter than the hinge tolerance are grazes.
  for (std::size_t i = 0; i + 1 < ts.size(); i += 2) {
    const Point2 p{a.x_mm + ts[i] * dx, a.v_mm + ts[i] * dv}, q{a.x_mm + ts[i + 1] * dx, a.v_mm + ts[i + 1] * dv};
    if (std::hypot(q.x_mm - p.x_mm, q.v_mm - p.v_mm) > 1e-3) pieces.emplace_back(p, q);
  }
  return pieces;
}

// The region of a sheet holding a sheet point: candidates by their boxes, then the exact test.
class RegionFinder {
 public:
  explicit RegionFinder(const SheetMap& map) : map_(map), grid_(map.bounds, map.regions.size()) {
    for (std::size_t r = 0; r < map.regions.size(); ++r) {
      const Rect box = bounds(map.regions[r].outer);
      grid_.insert(static_cast<int>(r), box.min, box.max);
    }
  }
  int holding(Point2 p) const {  // -1 for none
    for (const int r : grid_.at(p)) {
      const SheetRegion& g = map_.regions[static_cast<std::size_t>(r)];
      if (!inside_ring(p, g.outer)) continue;
      if (std::none_of(g.holes.begin(), g.holes.end(), [&](const Ring& h) { return inside_ring(p, h); })) return r;
    }
    return -1;
  }

 private:
  const SheetMap& map_;
  SpatialGrid grid_;
};

// Every crease of the drawing with the angle and stage its hinge turned by, so the new sheet keeps them.
std::vector<CreaseAngle> kept_turns(const LineDrawing& d, const FoldableSheet& s) {
  std::vector<CreaseAngle> out;
  std::vector<bool> seen(d.lines.size(), false);
  for (const SheetHinge& h : s.hinges)
    for (int e : h.edges) {
      const int drawn = s.map.edges[static_cast<std::size_t>(e)].drawn;
      if (drawn < 0 || drawn >= static_cast<int>(d.lines.size()) || seen[static_cast<std::size_t>(drawn)]) continue;
      seen[static_cast<std::size_t>(drawn)] = true;
      out.push_back({d.lines[static_cast<std::size_t>(drawn)].where, h.angle_deg, h.stage});
    }
  return out;
}

}  // namespace

SheetLineFold fold_along_line(const LineDrawing& d, const FoldableSheet& s, const LineFoldStep& step,
                              const SheetMapOptions& map_options) {
  const std::vector<int>& layers = s.layer;
  if (std::hypot(step.b.x_mm - step.a.x_mm, step.b.v_mm - step.a.v_mm) < 1e-3)
    throw Error(ErrorCode::invalid_input, s.source, "--fold-line", "the fold line's two points coincide");
  const SheetState state = fold_sheet(s, 1);
  require_flat(s, state);
  const int stage = stage_count(s) + (s.hinges.empty() ? 0 : 1);
  SheetLineFold out;
  out.drawing = d;
  SheetFoldOptions o;
  o.angles = kept_turns(d, s);
  // Every layer the line crosses gets a crease: valley where the layer faces up and the moving
  // side goes over the top, mountain where it lies turned over (and the reverse going under).
  int made = 0;
  for (std::size_t r = 0; r < s.map.regions.size(); ++r) {
    if (s.cut_out[r]) continue;
    const Pose& pose = state.poses[r];
    for (const auto& [p, q] : clip(s.map.regions[r], unapply(pose, step.a), unapply(pose, step.b))) {
      const bool valley = face_up(pose) != step.under;
      const std::string where =
          "fold line " + std::to_string(stage) + " through region " + std::to_string(r) + " #" + std::to_string(++made);
      out.drawing.lines.push_back({valley ? DrawnKind::valley : DrawnKind::mountain,
                                   {p, q},
                                   false,
                                   where,
                                   "folded along a line",
                                   valley ? 180.0 : -180.0});
      o.angles.push_back({where, valley ? 180.0 : -180.0, stage});
    }
  }
  if (made == 0)
    throw Error(ErrorCode::invalid_input, s.source, "--fold-line",
                "the line from " + describe_place(step.a) + " to " + describe_place(step.b) +
                    " crosses no layer of the folded sheet");
  // Each fold along a line can double the layers; past the limit the sheet is a stack no cutter
  // cuts and no simulation shows, so say so before the map grows without end.
  const std::size_t regions_after = s.map.regions.size() + static_cast<std::size_t>(made);
  if (regions_after > kMaxLineFoldRegions)
    throw Error(ErrorCode::invalid_input, s.source, "--fold-line",
                "folding along the line from " + describe_place(step.a) + " to " + describe_place(step.b) +
                    " would split the sheet into about " + std::to_string(regions_after) + " regions, more than the " +
                    std::to_string(kMaxLineFoldRegions) + " popcut folds");
  // Stay put on the side that does not move: the old fixed region where it lies there.
  SheetMap map = build_sheet_map(out.drawing, map_options);
  FoldableSheet probe = make_foldable_sheet(out.drawing, map, o);
  const RegionFinder old_regions(s.map);
  const auto old_of = [&](std::size_t r) { return old_regions.holding(probe.map.regions[r].label); };
  const auto moves = [&](std::size_t r) {
    const int old = old_of(r);
    return old >= 0 &&
           cross(step.a, step.b, world_of(state.poses[static_cast<std::size_t>(old)], probe.map.regions[r].label)) > 0;
  };
  for (std::size_t r = 0; r < probe.map.regions.size() && o.fixed_region < 0; ++r)
    if (!probe.cut_out[r] && !moves(r)) o.fixed_region = static_cast<int>(r);
  out.sheet = make_foldable_sheet(out.drawing, std::move(map), o);
  // Layers: the moving stack turns over onto (or under) the rest, its order reversed.
  const auto [lo, hi] = layers.empty() ? std::pair(0, 0)
                                       : std::pair(*std::min_element(layers.begin(), layers.end()),
                                                   *std::max_element(layers.begin(), layers.end()));
  for (std::size_t r = 0; r < out.sheet.map.regions.size(); ++r) {
    const int old = old_of(r);
    const int was =
        old >= 0 && static_cast<std::size_t>(old) < layers.size() ? layers[static_cast<std::size_t>(old)] : 0;
    out.sheet.layer.push_back(!moves(r) ? was : step.under ? lo - 1 - (was - lo) : hi + 1 + (hi - was));
  }
  return out;
}

}  // namespace popcut
