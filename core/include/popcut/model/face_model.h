// Planar-face OA model (polygon paper §2–3): VFaces and HFaces partitioning the sheet, edited with exact Booleans.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "popcut/geometry.h"
#include "popcut/names.h"

namespace popcut {

// Documented limits: coordinates (100 m), faces in a model, points in one outline, edits.
inline constexpr double kMaxFaceCoordinateMm = 1e5;
inline constexpr std::size_t kMaxFaces = 100000;
inline constexpr std::size_t kMaxOutlinePoints = 10000;
inline constexpr std::size_t kMaxEdits = 100000;

// A polygon in pattern coordinates (x, v), mm: outer ring counter-clockwise, holes clockwise.
struct PolygonWithHoles {
  Ring outer;
  std::vector<Ring> holes;
  friend bool operator==(const PolygonWithHoles&, const PolygonWithHoles&) = default;
};

// One face: a connected region of the sheet and the plane it becomes (Fig. 5 of the paper).
struct OAFace {
  FaceKind kind = FaceKind::vertical;
  double t_mm = 0;  // VFace: depth y of its plane; HFace: height z of its plane
  PolygonWithHoles polygon;
  bool opening_paper = false;  // the paper inside an opening: drops out when nothing holds it
  bool drops_out = false;      // such paper cut all round, to fall out (FaceEdit::drop)
};

enum class EditOp { add_vface, add_hface, add_vhole, add_hhole };
inline constexpr auto kEditOpNames = enum_names<EditOp>({{EditOp::add_vface, "add_vface"},
                                                         {EditOp::add_hface, "add_hface"},
                                                         {EditOp::add_vhole, "add_vhole"},
                                                         {EditOp::add_hhole, "add_hhole"}});  // as in popcut.faces.v1
const char* to_string(EditOp op);

// A polygon drawn in one plane of the open card (polygon paper §3.1): for add_vface and
// add_vhole, points (x, z) in the plane y = t_mm; for add_hface and add_hhole, points (x, y) in
// the plane z = t_mm. A hole becomes the equivalent face of the other kind (eq. 6).
struct FaceEdit {
  EditOp op = EditOp::add_vface;
  double t_mm = 0;
  std::vector<std::array<double, 2>> outline;
  // add_vface and add_hface only: parts of the outline the face leaves out, in the same plane
  // coordinates. What was drawn there before shows through; nothing folds at their edges. A
  // card's faces read back as edits (a webOAcard card imported into a design) need them: a wall
  // seen through a window of the wall in front is a face with a hole.
  std::vector<std::vector<std::array<double, 2>>> holes{};
  // add_vhole and add_hhole only: the opening's paper is cut all round and falls out, instead of
  // folding down on a level bottom edge as a ledge (a plain square window; the space around
  // framed letters).
  bool drop = false;
  friend bool operator==(const FaceEdit&, const FaceEdit&) = default;
};

namespace detail {
struct FaceModelState;  // exact (CGAL) faces; defined in core/src only
struct ExactFace;
struct FaceCache;
}  // namespace detail

// The faces always partition the sheet (eq. 4): every edit subtracts its polygon from the
// faces already there (eq. 5) with exact regularized Booleans. Coordinates are exact inside;
// faces() rounds them to double for output.
//
// The subtraction is deferred: the model keeps the polygons in the order they were drawn, and
// face i is drawn polygon i minus the union of everything drawn after it. An edit is then local
// (a hole is checked against the polygons near it only), and the faces are worked out once, when
// first asked for, with one aggregated union per drawn polygon. Done eagerly, every edit would
// re-cut the back board and floor, whose outlines grow with every face: quadratic in the edits.
// A FaceModel may be read from several threads; editing needs exclusive access.
class FaceModel {
 public:
  // The initial card: the back board (VFace, t = 0) over v ≥ 0 and the floor (HFace, t = 0) over
  // v ≤ 0, on the sheet x in [0, width], v in [-floor, back] (mm).
  FaceModel(double width_mm, double back_mm, double floor_mm);
  // A model given by its final faces; throws popcut::Error naming faces[i] when a polygon is
  // malformed, leaves the sheet, or the faces overlap or leave a gap.
  static FaceModel from_faces(double width_mm, double back_mm, double floor_mm, const std::vector<OAFace>& faces,
                              const std::string& source = "");
  // The same for faces that are the regions of one planar subdivision. When the caller's exact
  // map put every vertex on the 1 nm grid (`vertices_on_grid`), and the rings given are within a
  // rounding of it, no face can cross another and the rings are that map's loops: only their
  // areas are summed to prove they cover the sheet, skipping the Boolean union that dominates
  // from_faces on large patterns, and the rings are not swept for self-crossings. Otherwise every
  // check of from_faces runs. Faces that are not such regions must go to from_faces.
  static FaceModel from_subdivision(double width_mm, double back_mm, double floor_mm, const std::vector<OAFace>& faces,
                                    const std::string& source = "", bool vertices_on_grid = false);

  // Applies an edit; on error (popcut::Error naming `where`, e.g. "edits[3]") nothing changes.
  void apply(const FaceEdit& edit, const std::string& source = "", const std::string& where = "edit");
  bool undo();  // false when there is nothing to undo
  bool redo();
  const std::vector<FaceEdit>& edits() const { return edits_; }  // the edits that made this state
  bool has_edit_history() const { return from_edits_; }          // false for a model read as faces

  Rect sheet() const;
  // The faces; the first call after an edit works them out (throws popcut::Error when the
  // model would exceed kMaxFaces).
  std::vector<OAFace> faces() const;
  std::size_t face_count() const;
  const detail::FaceModelState& state() const;

  // What drew the face at pattern point p: "edits[k]", "faces[i]" for a model read as faces,
  // or "the back board" / "the floor" of the blank card. For error messages.
  std::string drawn_by(Point2 p) const;
  // What drawn_by() says for each face read by from_faces or from_subdivision, in their order,
  // when they came from another file's faces (a webOAcard card: "faces[3] (a wall at t = 24 mm)").
  void name_given_faces(std::vector<std::string> names);

 private:
  using Drawn = std::vector<std::shared_ptr<const detail::ExactFace>>;
  static FaceModel from_given(double width_mm, double back_mm, double floor_mm, const std::vector<OAFace>& faces,
                              const std::string& source, bool may_overlap);
  FaceModel() = default;
  void changed();
  static void keep(std::vector<std::shared_ptr<detail::FaceCache>>& stack, std::shared_ptr<detail::FaceCache> cache);
  void restore(std::vector<std::shared_ptr<detail::FaceCache>>& stack);

  std::shared_ptr<const detail::FaceModelState> sheet_;  // the sheet's bounds; no faces
  Drawn drawn_;                        // bottom to top: each polygon covers those drawn before it (eq. 5)
  std::size_t given_ = 0;              // leading polygons read as final faces: disjoint, nothing to subtract
  std::vector<std::size_t> edit_end_;  // drawn_.size() after each edit in edits_
  std::vector<FaceEdit> edits_, undone_;
  std::vector<Drawn> redo_drawn_;                     // the polygons of each undone edit, for redo
  mutable std::shared_ptr<detail::FaceCache> cache_;  // the faces of this state, once worked out
  std::vector<std::shared_ptr<detail::FaceCache>> undo_cache_, redo_cache_;  // of the states nearest in history
  bool from_edits_ = true;
  std::shared_ptr<const std::vector<std::string>> given_names_;  // name_given_faces
};

}  // namespace popcut
