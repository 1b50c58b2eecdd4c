// FaceModel::from_faces and from_subdivision: faces given as final, each checked, then together to partition the sheet.
#include <CGAL/Boolean_set_operations_2.h>

#include <algorithm>
#include <cmath>

#include "model/exact_faces.h"
#include "popcut/model/face_model.h"
#include "popcut/text.h"

namespace popcut {
using namespace detail;

namespace {

// True when some vertex of `ring` appears twice (exact comparison, O(n log n)).
bool has_repeated_vertex(const ExactPolygon& ring) {
  std::vector<ExactPoint> points(ring.vertices_begin(), ring.vertices_end());
  std::sort(points.begin(), points.end());
  return std::adjacent_find(points.begin(), points.end()) != points.end();
}

// CGAL's validity test for a polygon with holes, without its quadratic crossover test when the
// outer ring repeats no vertex: that test (naive point location per vertex) only finds a ring that
// passes through one vertex twice, which a relatively simple ring without repeats cannot do.
// Without holes there is nothing left to test: exact_polygon made the outer ring simple and
// counter-clockwise.
bool valid_polygon_with_holes(const ExactPolygonWithHoles& pwh) {
  if (pwh.number_of_holes() == 0) return true;
  const CGAL::Gps_segment_traits_2<Kernel> traits;
  if (has_repeated_vertex(pwh.outer_boundary())) return CGAL::is_valid_polygon_with_holes(pwh, traits);
  if (!CGAL::is_closed_polygon_with_holes(pwh, traits) || !CGAL::is_relatively_simple_polygon_with_holes(pwh, traits) ||
      !CGAL::has_valid_orientation_polygon_with_holes(pwh, traits))
    return false;
  auto mutable_traits = traits;
  return CGAL::are_holes_and_boundary_pairwise_disjoint(pwh, mutable_traits);
}

FT total_area(const ExactFaces& given) {
  FT area = 0;
  for (const auto& fp : given) area += polygon_area(fp->polygon);
  return area;
}

void check_cover(const FT& area, const FaceModelState& sheet, const std::string& source) {
  const FT sheet_area = (sheet.max_x - sheet.min_x) * (sheet.max_v - sheet.min_v);
  if (area != sheet_area) {
    fail(source, "faces",
         "cover " + format_decimal(CGAL::to_double(area) / (kNmPerMm * kNmPerMm), 2) + " mm² of a " +
             format_decimal(CGAL::to_double(sheet_area) / (kNmPerMm * kNmPerMm), 2) +
             " mm² sheet: faces must cover it exactly (eq. 4)");
  }
}

// Eq. 4: no two faces overlap, and together they cover the sheet exactly. One aggregated
// union (a sweep, O(n log n)) proves both: its area equals the sum of the faces' areas only
// when nothing overlaps. Only on failure are pairs searched, to name the two faces.
void check_partition(const ExactFaces& given, const FaceModelState& sheet, const std::string& source) {
  const FT area = total_area(given);
  std::vector<ExactPolygonWithHoles> polygons;
  for (const auto& fp : given) polygons.push_back(fp->polygon);
  PolygonSet all;
  all.join(polygons.begin(), polygons.end());
  std::vector<ExactPolygonWithHoles> united;
  all.polygons_with_holes(std::back_inserter(united));
  FT union_area = 0;
  for (const ExactPolygonWithHoles& u : united) union_area += polygon_area(u);
  if (union_area != area) {
    for_overlapping_boxes(given, [&](std::size_t i, std::size_t j) {
      if (CGAL::do_intersect(given[i]->polygon, given[j]->polygon)) {
        fail(source, "faces[" + std::to_string(i) + "]",
             "overlaps faces[" + std::to_string(j) + "]: faces must not overlap (eq. 4)");
      }
    });
    fail(source, "faces", "overlap: faces must not overlap (eq. 4)");
  }
  check_cover(area, sheet, source);
}

// True when every vertex is within a rounding of the 1 nm grid (the card's shift by its centre
// fold, in doubles, errs by an ulp of the sheet's size: at most about 2e-11 mm), so snapping
// moves every copy of a vertex back to the exact map vertex it came from.
bool on_nm_grid(const std::vector<OAFace>& faces) {
  const auto on = [](const Ring& ring) {
    return std::all_of(ring.begin(), ring.end(), [](Point2 p) {
      constexpr double kRoundingMm = 1e-10;
      return std::abs(nm_count(p.x_mm) / kNmPerMm - p.x_mm) <= kRoundingMm &&
             std::abs(nm_count(p.v_mm) / kNmPerMm - p.v_mm) <= kRoundingMm;
    });
  };
  return std::all_of(faces.begin(), faces.end(), [&](const OAFace& f) {
    return on(f.polygon.outer) && std::all_of(f.polygon.holes.begin(), f.polygon.holes.end(), on);
  });
}

}  // namespace

std::shared_ptr<const ExactFace> detail::given_face(const OAFace& f, const FaceModelState& sheet,
                                                    const std::string& source, const std::string& where,
                                                    bool of_subdivision, const std::string& outer_field) {
  if (!std::isfinite(f.t_mm) || f.t_mm < 0 || f.t_mm > kMaxFaceCoordinateMm)
    fail(source, where + ".t", "must be from 0 to 100000 mm");
  // A region may touch itself at a corner: its rings then split into one counter-clockwise
  // outer loop and clockwise holes that touch it there.
  // Rings written the other way round (outer clockwise) are read as the writer meant them.
  const bool flipped = signed_area_mm2(f.polygon.outer) < 0;
  const auto oriented = [&](const Ring& r) { return flipped ? Ring(r.rbegin(), r.rend()) : r; };
  std::vector<Ring> loops = split_at_repeated_vertices(oriented(f.polygon.outer));
  for (const Ring& h : f.polygon.holes) {
    for (Ring& loop : split_at_repeated_vertices(oriented(h))) loops.push_back(std::move(loop));
  }
  std::vector<ExactPolygon> outers, holes;
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const bool ccw = signed_area_mm2(loops[k]) > 0;
    ExactPolygon poly = exact_polygon(loops[k], source, where + (k == 0 ? outer_field : ".holes"), {}, of_subdivision);
    if (ccw)
      outers.push_back(std::move(poly));
    else
      holes.push_back(std::move(poly));
  }
  if (outers.size() != 1) {
    fail(source, where + outer_field,
         "must enclose one connected region: give the outer ring counter-clockwise and holes clockwise");
  }
  ExactPolygonWithHoles pwh(outers.front());
  if (!inside_sheet(pwh.outer_boundary(), sheet)) fail(source, where + outer_field, "leaves the sheet");
  for (ExactPolygon& hole : holes) {
    hole.reverse_orientation();  // holes run clockwise
    pwh.add_hole(std::move(hole));
  }
  if (!of_subdivision && !valid_polygon_with_holes(pwh)) {
    fail(source, where + ".holes", "holes must lie inside the outer ring without crossing it or each other");
  }
  return make_face(f.kind, exact_nm(f.t_mm), std::move(pwh), f.opening_paper, f.drops_out);
}

FaceModel FaceModel::from_faces(double width_mm, double back_mm, double floor_mm, const std::vector<OAFace>& faces,
                                const std::string& source) {
  return from_given(width_mm, back_mm, floor_mm, faces, source, true);
}

FaceModel FaceModel::from_subdivision(double width_mm, double back_mm, double floor_mm,
                                      const std::vector<OAFace>& faces, const std::string& source,
                                      bool vertices_on_grid) {
  return from_given(width_mm, back_mm, floor_mm, faces, source, !(vertices_on_grid && on_nm_grid(faces)));
}

FaceModel FaceModel::from_given(double width_mm, double back_mm, double floor_mm, const std::vector<OAFace>& faces,
                                const std::string& source, bool may_overlap) {
  auto s = initial_state(width_mm, back_mm, floor_mm);
  if (faces.size() > kMaxFaces)
    fail(source, "faces", "has " + std::to_string(faces.size()) + " faces; the limit is " + std::to_string(kMaxFaces));
  Drawn given;
  guarded(source, "faces", [&] {
    for (std::size_t i = 0; i < faces.size(); ++i)
      given.push_back(given_face(faces[i], *s, source, "faces[" + std::to_string(i) + "]", !may_overlap));
    if (may_overlap)
      check_partition(given, *s, source);
    else
      check_cover(total_area(given), *s, source);
    return 0;
  });

  FaceModel m;
  m.sheet_ = std::move(s);
  m.drawn_ = std::move(given);
  m.given_ = m.drawn_.size();
  m.from_edits_ = false;
  m.changed();
  return m;
}

}  // namespace popcut
