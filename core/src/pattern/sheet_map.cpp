// The planar map of a drawn sheet: snapped ends, CGAL's exact arrangement, regions with holes and typed edges.
#include "popcut/pattern/sheet_map.h"

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "model/face_model_state.h"
#include "popcut/error.h"
#include "popcut/spatial_grid.h"
#include "popcut/text.h"

namespace popcut {
namespace {

using detail::ExactPoint;
using detail::to_point2;
using SegmentTraits = CGAL::Arr_segment_traits_2<detail::Kernel>;
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, int>;  // data: drawn line index
using Arrangement = CGAL::Arrangement_2<Traits>;

struct Piece {
  Point2 a, b;
  int drawn;
};

// Cells of the snapping grid, keyed by integer coordinates.
struct Grid {
  double cell;
  std::unordered_map<long long, std::vector<int>> cells;
  long long key(long long i, long long j) const { return i * 73856093LL ^ j * 19349663LL; }
  long long ci(double x) const { return static_cast<long long>(std::floor(x / cell)); }
};

// Ends closer than the tolerance become one point (the first drawn), so lines drawn to "the
// same" corner meet.
int snap_ends(std::vector<Piece>& pieces, double tol) {
  if (tol <= 0) return 0;
  int moved = 0;
  Grid grid{tol, {}};
  std::vector<Point2*> ends;
  for (Piece& p : pieces) {
    ends.push_back(&p.a);
    ends.push_back(&p.b);
  }
  std::vector<Point2> chosen;
  for (Point2* e : ends) {
    const long long i = grid.ci(e->x_mm), j = grid.ci(e->v_mm);
    int found = -1;
    for (long long di = -1; di <= 1 && found < 0; ++di)
      for (long long dj = -1; dj <= 1 && found < 0; ++dj)
        if (const auto it = grid.cells.find(grid.key(i + di, j + dj)); it != grid.cells.end())
          for (const int c : it->second)
            if (std::hypot(chosen[static_cast<std::size_t>(c)].x_mm - e->x_mm,
                           chosen[static_cast<std::size_t>(c)].v_mm - e->v_mm) <= tol) {
              found = c;
              break;
            }
    if (found >= 0) {
      const Point2 target = chosen[static_cast<std::size_t>(found)];
      moved += !(target == *e);
      *e = target;
    } else {
      grid.cells[grid.key(i, j)].push_back(static_cast<int>(chosen.size()));
      chosen.push_back(*e);
    }
  }
  return moved;
}

double distance_to(Point2 p, const Piece& s, double& u) {
  const double dx = s.b.x_mm - s.a.x_mm, dv = s.b.v_mm - s.a.v_mm, len2 = dx * dx + dv * dv;
  u = len2 > 0 ? ((p.x_mm - s.a.x_mm) * dx + (p.v_mm - s.a.v_mm) * dv) / len2 : 0;
  return std::hypot(p.x_mm - s.a.x_mm - u * dx, p.v_mm - s.a.v_mm - u * dv);
}

// An end within the tolerance of another line's inside (a T-junction drawn a hair short or
// long, or rounded in a file) splits that line there, so the two meet exactly.
int snap_ends_to_lines(std::vector<Piece>& pieces, double tol) {
  if (tol <= 0 || pieces.empty()) return 0;
  std::vector<Point2> ends;  // every distinct end, once
  ends.reserve(pieces.size() * 2);
  for (const Piece& p : pieces) {
    ends.push_back(p.a);
    ends.push_back(p.b);
  }
  std::sort(ends.begin(), ends.end(), lexicographic_less);
  ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
  // Each line in the cells within tol of it: the cell of an end then holds every line it may snap to.
  SpatialGrid grid(bounds(ends), pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i)
    grid.insert_segment(static_cast<int>(i), pieces[i].a, pieces[i].b, tol);
  std::vector<std::vector<std::pair<double, Point2>>> splits(pieces.size());
  int moved = 0;
  for (const Point2 p : ends) {
    int best = -1;
    double best_d = tol, best_u = 0;
    for (const int c : grid.at(p)) {
      const Piece& s = pieces[static_cast<std::size_t>(c)];
      if (s.a == p || s.b == p) continue;
      double u = 0;
      const double dist = distance_to(p, s, u);
      if (dist <= best_d && u > 0 && u < 1) {
        best = static_cast<int>(c);
        best_d = dist;
        best_u = u;
      }
    }
    if (best < 0) continue;
    splits[static_cast<std::size_t>(best)].push_back({best_u, p});
    moved += best_d > 0;  // an end exactly on the line needs no snap, only the split (1 nm grid)
  }
  const std::size_t n = pieces.size();
  for (std::size_t i = 0; i < n; ++i) {
    auto& at = splits[i];
    if (at.empty()) continue;
    std::sort(at.begin(), at.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    const Piece whole = pieces[i];
    Point2 from = whole.a;
    for (std::size_t k = 0; k < at.size(); ++k) {
      const Piece part{from, at[k].second, whole.drawn};
      if (k == 0)
        pieces[i] = part;
      else
        pieces.push_back(part);
      from = at[k].second;
    }
    pieces.push_back({from, whole.b, whole.drawn});
  }
  return moved;
}

std::vector<Piece> pieces_of(const LineDrawing& d, int& flat) {
  std::vector<Piece> out;
  for (std::size_t i = 0; i < d.lines.size(); ++i) {
    const DrawnLine& l = d.lines[i];
    if (l.kind == DrawnKind::flat) {
      ++flat;
      continue;
    }
    const std::size_t n = l.points.size();
    for (std::size_t k = 0; k + 1 < n + (l.closed ? 1 : 0); ++k)
      out.push_back({l.points[k], l.points[(k + 1) % n], static_cast<int>(i)});
  }
  return out;
}

void require_classified(const LineDrawing& d) {
  std::string list;
  int count = 0;
  const DrawnLine* first = nullptr;
  for (const DrawnLine& l : d.lines) {
    if (l.kind != DrawnKind::unknown) continue;
    if (!first) first = &l;
    if (++count <= 10) list += "\n  " + l.where + " at " + describe_place(l.points[0]) + ": " + l.why;
  }
  if (!first) return;
  throw Error(ErrorCode::invalid_input, d.source, first->where,
              std::to_string(count) +
                  " line(s) match no convention for cut, mountain, valley, score or outline; put "
                  "them on a layer named for their kind, or name their layer with --layer NAME=KIND:" +
                  list + (count > 10 ? "\n  …" : ""));
}

Arrangement arrange(const std::vector<Piece>& pieces) {
  std::vector<Traits::Curve_2> curves;
  curves.reserve(pieces.size());
  for (const Piece& p : pieces) {
    // On the 1 nm decimal grid, as faces are: ends a rounding apart meet, and decimal points that
    // are collinear (0.1, 0.2, 0.3) stay so, as they would not as doubles.
    const ExactPoint a = detail::exact_point_nm(p.a), b = detail::exact_point_nm(p.b);
    if (a != b) curves.emplace_back(SegmentTraits::Curve_2(a, b), p.drawn);
  }
  Arrangement arr;
  CGAL::insert(arr, curves.begin(), curves.end());
  return arr;
}

// The kind of an edge drawn by one or more lines; two different kinds over each other are an error.
DrawnKind edge_kind(const LineDrawing& d, Arrangement::Halfedge_const_handle h) {
  const auto& data = h->curve().data();
  DrawnKind kind = d.lines[static_cast<std::size_t>(data.front())].kind;
  for (const int i : data) {
    const DrawnLine& l = d.lines[static_cast<std::size_t>(i)];
    if (l.kind == kind || (l.kind == DrawnKind::cut && kind == DrawnKind::outline)) continue;
    if (l.kind == DrawnKind::outline && kind == DrawnKind::cut) {
      kind = DrawnKind::outline;
      continue;
    }
    const DrawnLine& other = d.lines[static_cast<std::size_t>(data.front())];
    throw Error(ErrorCode::invalid_input, d.source, l.where,
                std::string("drawn over ") + other.where + " at " + describe_place(to_point2(h->source()->point())) +
                    " as " + to_string(l.kind) + " where that line is " + to_string(other.kind) +
                    ": one line, one kind");
  }
  return kind;
}

// The ring of a CCB without its antennas (edges with the same face on both sides: slits).
Ring ring_of(Arrangement::Ccb_halfedge_const_circulator first) {
  Ring ring;
  auto h = first;
  do {
    if (h->face() != h->twin()->face()) ring.push_back(to_point2(h->source()->point()));
  } while (++h != first);
  return ring;
}

struct OutlineCheck {
  bool ok = true;
  std::string problem;
  int drawn = -1;
};

// Every edge of the unbounded face must be the sheet's edge, and the edge one closed loop. An
// outline left open is named first: every other complaint would follow from it.
OutlineCheck check_outline(const LineDrawing& d, const Arrangement& arr, bool have_outline) {
  const auto outside = arr.unbounded_face();
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e)
    if (e->face() == outside && e->twin()->face() == outside && edge_kind(d, e) == DrawnKind::outline)
      return {
          false,
          "the sheet's outline is not closed: it ends loose near " + describe_place(to_point2(e->source()->point())),
          e->curve().data().front()};
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
    const bool out1 = e->face() == outside, out2 = e->twin()->face() == outside;
    if (!out1 && !out2) continue;
    const DrawnKind k = edge_kind(d, e);
    const int drawn = e->curve().data().front();
    if (have_outline && k != DrawnKind::outline) return {false, "lies outside the sheet's outline", drawn};
    if (out1 && out2) return {false, "lies outside the sheet (it ends loose, enclosing nothing)", drawn};
    if (k != DrawnKind::outline && k != DrawnKind::cut)
      return {false, std::string("a ") + to_string(k) + " line on the sheet's edge: the edge must be cut", drawn};
  }
  if (outside->number_of_inner_ccbs() != 1)
    return {false, std::to_string(outside->number_of_inner_ccbs()) + " separate sheets are drawn; popcut imports one",
            -1};
  return {};
}

void fill_map(const LineDrawing& d, const Arrangement& arr, SheetMap& map) {
  for (auto v = arr.vertices_begin(); v != arr.vertices_end() && map.vertices_on_grid; ++v) {
    // Counts of nm are whole doubles exactly; a crossing between them has a wider interval.
    const auto& a = v->point().approx();
    map.vertices_on_grid = a.x().is_point() && a.y().is_point() && std::floor(a.x().inf()) == a.x().inf() &&
                           std::floor(a.y().inf()) == a.y().inf();
  }
  std::unordered_map<const void*, int> index;
  for (auto f = arr.faces_begin(); f != arr.faces_end(); ++f) {
    if (f->is_unbounded()) continue;
    SheetRegion r;
    r.outer = ring_of(f->outer_ccb());
    for (auto h = f->inner_ccbs_begin(); h != f->inner_ccbs_end(); ++h)
      if (Ring hole = ring_of(*h); hole.size() >= 3) r.holes.push_back(std::move(hole));
    r.area_mm2 = signed_area_mm2(r.outer);
    for (const Ring& h : r.holes) r.area_mm2 += signed_area_mm2(h);
    r.label = interior_point(r.outer, r.holes);
    index[&*f] = static_cast<int>(map.regions.size());
    map.regions.push_back(std::move(r));
  }
  const auto region = [&](Arrangement::Face_const_handle f) { return f->is_unbounded() ? -1 : index.at(&*f); };
  for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
    auto h = e->source()->point() < e->target()->point() ? Arrangement::Halfedge_const_handle(e) : e->twin();
    map.edges.push_back({edge_kind(d, h), to_point2(h->source()->point()), to_point2(h->target()->point()),
                         region(h->face()), region(h->twin()->face()), h->curve().data().front()});
    map.overlaps_merged += h->curve().data().size() > 1;
  }
  const auto outside = arr.unbounded_face();
  Ring outline;
  for (auto h = *outside->inner_ccbs_begin(); outline.empty() || h != *outside->inner_ccbs_begin(); ++h)
    outline.push_back(to_point2(h->twin()->target()->point()));
  std::reverse(outline.begin(), outline.end());  // the inner CCB of the outside runs clockwise
  map.outline = outline;
  map.bounds = bounds(outline);
}

}  // namespace

std::string describe_place(Point2 p) {
  return "(" + format_decimal(p.x_mm, 3) + ", " + format_decimal(p.v_mm, 3) + ") mm";
}

SheetMap build_sheet_map(const LineDrawing& d, const SheetMapOptions& options) {
  require_classified(d);
  SheetMap map;
  int flat = 0;
  std::vector<Piece> pieces = pieces_of(d, flat);
  if (pieces.empty()) throw Error(ErrorCode::invalid_input, d.source, "", "the drawing has no lines");
  map.snapped_ends = snap_ends(pieces, options.snap_tolerance_mm);
  map.snapped_ends += snap_ends_to_lines(pieces, options.snap_tolerance_mm);
  const bool have_outline =
      std::any_of(d.lines.begin(), d.lines.end(), [](const DrawnLine& l) { return l.kind == DrawnKind::outline; });
  Arrangement arr = arrange(pieces);
  OutlineCheck check = check_outline(d, arr, have_outline);
  LineDrawing with_page;
  const LineDrawing* used = &d;
  if (!check.ok && !have_outline && d.page) {
    // No edge was drawn; the page is the sheet, as the designer laid it out.
    with_page = d;
    const Rect p = *d.page;
    with_page.lines.push_back({DrawnKind::outline,
                               {p.min, {p.max.x_mm, p.min.v_mm}, p.max, {p.min.x_mm, p.max.v_mm}},
                               true,
                               "the page",
                               "the SVG page",
                               {}});
    const int page = static_cast<int>(with_page.lines.size()) - 1;
    for (int k = 0; k < 4; ++k) {
      const auto& pts = with_page.lines.back().points;
      pieces.push_back({pts[static_cast<std::size_t>(k)], pts[static_cast<std::size_t>((k + 1) % 4)], page});
    }
    arr = arrange(pieces);
    used = &with_page;
    check = check_outline(with_page, arr, true);
    map.notes.push_back("no sheet edge is drawn: the SVG page (" + format_decimal(p.max.x_mm, 2) + " × " +
                        format_decimal(p.max.v_mm, 2) + " mm) is the sheet");
  }
  if (!check.ok) {
    const DrawnLine* l = check.drawn >= 0 ? &used->lines[static_cast<std::size_t>(check.drawn)] : nullptr;
    throw Error(ErrorCode::invalid_input, d.source, l ? l->where : "", check.problem);
  }
  fill_map(*used, arr, map);
  if (flat) map.notes.push_back(std::to_string(flat) + " flat crease(s) (FOLD \"F\"/\"J\") left out: they do not fold");
  if (map.snapped_ends)
    map.notes.push_back(std::to_string(map.snapped_ends) + " line end(s) snapped to a neighbour within " +
                        format_decimal(options.snap_tolerance_mm, 4) + " mm");
  return map;
}

}  // namespace popcut
