// The exact (CGAL) face operations a FaceModel is built from: checked polygons, lobes, areas and eq. 5's overlay.
#pragma once

#include <CGAL/Polygon_set_2.h>
#include <CGAL/box_intersection_d.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "model/face_model_state.h"
#include "popcut/error.h"

namespace popcut::detail {

using PolygonSet = CGAL::Polygon_set_2<Kernel>;
using ExactFaces = std::vector<std::shared_ptr<const ExactFace>>;  // FaceModel::Drawn, FaceModelState::faces

// An invalid_input error naming the model file and the field.
[[noreturn]] void fail(const std::string& source, const std::string& where, const std::string& message);

// An exact, simple, counter-clockwise polygon from pattern points, or an error naming `where`.
// `exact` holds the same points exactly; when empty they are read from `ring` as decimals.
// `known_simple` skips the simplicity sweep for a ring that is simple by construction (a loop
// of a planar map, its vertices exact).
ExactPolygon exact_polygon(const Ring& ring, const std::string& source, const std::string& where,
                           std::vector<ExactPoint> exact = {}, bool known_simple = false);

// One face as given: its rings oriented and split at pinches, exact, on the sheet, holes inside;
// errors name `where` + `outer_field` or ".holes". A region of a subdivision on the nm grid
// (`of_subdivision`) has simple rings with its holes inside by construction; only the cheap checks
// run on it.
std::shared_ptr<const ExactFace> given_face(const OAFace& f, const FaceModelState& sheet, const std::string& source,
                                            const std::string& where, bool of_subdivision,
                                            const std::string& outer_field = ".outer");

// Every vertex lies on the sheet (its edge included).
bool inside_sheet(const ExactPolygon& poly, const FaceModelState& s);

// A Boolean result whose outer ring pinches at a vertex holds lobes that touch only at a point:
// separate pieces of paper, so separate faces (as the voxel path's 4-connected regions are).
// Clockwise loops split off the outer ring are holes touching it; each hole goes to its lobe.
std::vector<ExactPolygonWithHoles> split_lobes(const ExactPolygonWithHoles& pwh);

std::shared_ptr<const ExactFace> make_face(FaceKind kind, const FT& t, ExactPolygonWithHoles polygon,
                                           bool opening_paper = false, bool drops_out = false);
ExactPolygon rectangle(const FT& x0, const FT& v0, const FT& x1, const FT& v1);
FT polygon_area(const ExactPolygonWithHoles& p);

// The sheet of a new model, each size checked (0 exclusive to kMaxFaceCoordinateMm).
std::shared_ptr<FaceModelState> initial_state(double width_mm, double back_mm, double floor_mm);

// Runs CGAL work, turning any CGAL failure into an internal error: none may reach the user raw.
template <typename Body>
auto guarded(const std::string& source, const std::string& where, Body body) {
  try {
    return body();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(ErrorCode::internal, source, where, std::string("geometry kernel failure: ") + e.what());
  }
}

// Calls visit(i, j), i < j, for every pair of faces whose bounding boxes meet (CGAL's box sweep).
template <typename Visit>
void for_overlapping_boxes(const ExactFaces& faces, Visit visit) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 2, std::size_t>;
  std::vector<Box> boxes;
  boxes.reserve(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) boxes.emplace_back(faces[i]->bbox, i);
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    visit(std::min(a.info(), b.info()), std::max(a.info(), b.info()));
  });
}

// Eq. 5 for the whole history at once: face i is drawn polygon i minus the union of the
// polygons drawn after it that come near it (one aggregated union each). A polygon nothing
// covers is shared as it is; pieces that touch only at a corner become separate faces.
std::shared_ptr<const FaceModelState> work_out_faces(const FaceModelState& sheet, const ExactFaces& drawn,
                                                     std::size_t given);

// The same one edit later: the faces of the state before it, each minus the edit's polygons that
// come near it, then the edit's own. Its cost follows the faces the edit touches (each Boolean),
// not the history; the faces it leaves alone are shared.
std::shared_ptr<const FaceModelState> cover_faces(const FaceModelState& before, const ExactFaces& added);

}  // namespace popcut::detail
