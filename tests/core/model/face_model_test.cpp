// Face model edits (polygon paper eq. 4–6): subtraction keeps the sheet partitioned, holes become faces.
#include "popcut/model/face_model.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "pattern_oracle.h"
#include "popcut/error.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"

namespace popcut {
namespace {

FaceEdit edit(EditOp op, double t, std::vector<std::array<double, 2>> outline) { return {op, t, std::move(outline)}; }

// The simplest card: a box 40 wide, 20 deep, 30 high (paper Fig. 8 (a)–(c): place a VFace, then an HFace).
FaceModel box_card() {
  FaceModel m(60, 50, 50);
  m.apply(edit(EditOp::add_vface, 20, {{10, 0}, {50, 0}, {50, 30}, {10, 30}}));
  m.apply(edit(EditOp::add_hface, 30, {{10, 0}, {50, 0}, {50, 20}, {10, 20}}));
  return m;
}

bool has_line(const Pattern& p, LineKind kind, Point2 a, Point2 b) {
  return std::any_of(p.lines.begin(), p.lines.end(), [&](const Segment& s) {
    return s.kind == kind && ((s.a == a && s.b == b) || (s.a == b && s.b == a));
  });
}

TEST(FaceModel, StartsAsBackBoardAndFloor) {
  const FaceModel m(60, 50, 40);
  ASSERT_EQ(m.face_count(), 2u) << "back board and floor";
  const Pattern p = make_pattern(m);
  EXPECT_EQ(p.sheet, (Rect{{0, -40}, {60, 50}})) << "sheet from width, back, floor";
  ASSERT_EQ(p.lines.size(), 1u) << "only the centre fold";
  EXPECT_EQ(p.lines[0].kind, LineKind::valley) << "the centre fold is a valley";
  EXPECT_TRUE(check_popup(p).pops_up()) << "a blank card is valid";
}

TEST(FaceModel, BoxFromTwoFaces) {
  const Pattern p = make_pattern(box_card());
  EXPECT_EQ(p.faces.size(), 4u) << "back board, floor, front VFace, top HFace";
  EXPECT_TRUE(has_line(p, LineKind::valley, {10, 30}, {50, 30})) << "top meets the back wall: valley";
  EXPECT_TRUE(has_line(p, LineKind::mountain, {10, 10}, {50, 10}))
      << "top meets the front (t_h - t_v = 10 = v): mountain";
  EXPECT_TRUE(has_line(p, LineKind::valley, {10, -20}, {50, -20})) << "front meets the floor: valley";
  EXPECT_TRUE(has_line(p, LineKind::cut, {10, -20}, {10, 30})) << "left side: one maximal cut across three faces";
  EXPECT_TRUE(has_line(p, LineKind::valley, {0, 0}, {10, 0})) << "centre fold left of the box";
  EXPECT_EQ(p.lines.size(), 7u) << "no other lines";
  EXPECT_TRUE(check_popup(p).pops_up()) << "the box pops up";
  EXPECT_TRUE(testing::check_tiling(p, 10).empty()) << "faces tile the sheet";
}

TEST(FaceModel, SlantedEdgesAreCuts) {
  FaceModel m(60, 50, 50);
  m.apply(edit(EditOp::add_vface, 20, {{10, 0}, {50, 0}, {45, 30}, {15, 30}}));  // a trapezoid front
  m.apply(edit(EditOp::add_hface, 30, {{15, 0}, {45, 0}, {45, 20}, {15, 20}}));
  const Pattern p = make_pattern(m);
  EXPECT_TRUE(has_line(p, LineKind::cut, {10, -20}, {15, 10})) << "the slanted left side is a cut";
  EXPECT_TRUE(has_line(p, LineKind::cut, {45, 10}, {50, -20})) << "the slanted right side is a cut";
  for (const Segment& s : p.lines) {
    if (s.kind != LineKind::cut) {
      EXPECT_EQ(s.a.v_mm, s.b.v_mm) << "every fold is x-parallel";
    }
  }
  EXPECT_TRUE(check_popup(p).pops_up()) << "a trapezoid front under a roof pops up";
}

TEST(FaceModel, HoleInAVFaceBecomesAnHFace) {
  FaceModel m = box_card();
  // A window 10 wide, z from 10 to 20, in the front face (y = 20): eq. 6 turns it into an HFace
  // at the hole's lowest z, with the same pattern polygon.
  m.apply(edit(EditOp::add_vhole, 20, {{25, 10}, {35, 10}, {35, 20}, {25, 20}}));
  const Pattern p = make_pattern(m);
  const auto ledge = std::find_if(p.faces.begin(), p.faces.end(),
                                  [](const PatternFace& f) { return f.kind == FaceKind::horizontal && f.t_mm == 10; });
  ASSERT_NE(ledge, p.faces.end()) << "an HFace at z = 10 (the hole's lowest z)";
  EXPECT_EQ(bounds(ledge->outer), (Rect{{25, -10}, {35, 0}})) << "same pattern polygon as the hole";
  const auto front = std::find_if(p.faces.begin(), p.faces.end(),
                                  [](const PatternFace& f) { return f.kind == FaceKind::vertical && f.t_mm == 20; });
  ASSERT_NE(front, p.faces.end());
  EXPECT_EQ(front->holes.size(), 1u) << "the front face has the window as a hole";
  EXPECT_TRUE(has_line(p, LineKind::mountain, {25, -10}, {35, -10})) << "ledge folds into the sill";
  EXPECT_TRUE(check_popup(p).pops_up()) << "the window pops up";
}

TEST(FaceModel, HoleInAnHFaceBecomesAVFace) {
  FaceModel m = box_card();
  // A skylight in the top (z = 30), y from 5 to 15: eq. 6 turns it into a VFace at y = 5.
  m.apply(edit(EditOp::add_hhole, 30, {{20, 5}, {30, 5}, {30, 15}, {20, 15}}));
  const Pattern p = make_pattern(m);
  const auto wall = std::find_if(p.faces.begin(), p.faces.end(),
                                 [](const PatternFace& f) { return f.kind == FaceKind::vertical && f.t_mm == 5; });
  ASSERT_NE(wall, p.faces.end()) << "a VFace at y = 5 (the hole's nearest y)";
  EXPECT_EQ(bounds(wall->outer), (Rect{{20, 15}, {30, 25}})) << "pattern v = 30 - y for y in [5, 15]";
}

TEST(FaceModel, TallWindowContinuesOnTheBackWall) {
  // A window in a 20-deep front from z = 5 to z = 30: its ledge (HFace at z = 5) would need
  // 25 mm of depth; the last 5 mm lie on the back wall instead, as windows do in the voxel paper.
  FaceModel m(60, 50, 50);
  m.apply(edit(EditOp::add_vface, 20, {{10, 0}, {50, 0}, {50, 40}, {10, 40}}));
  m.apply(edit(EditOp::add_hface, 40, {{10, 0}, {50, 0}, {50, 20}, {10, 20}}));
  m.apply(edit(EditOp::add_vhole, 20, {{25, 5}, {35, 5}, {35, 30}, {25, 30}}));
  const Pattern p = make_pattern(m);
  for (const PatternFace& f : p.faces) {
    for (const Point2& q : f.outer) {
      const Point3 c = to_card(f.kind, f.t_mm, q);
      EXPECT_GE(c.y_mm, -1e-9) << "no paper behind the back wall";
      EXPECT_GE(c.z_mm, -1e-9) << "no paper below the floor";
    }
  }
  const auto ledge = std::find_if(p.faces.begin(), p.faces.end(),
                                  [](const PatternFace& f) { return f.kind == FaceKind::horizontal && f.t_mm == 5; });
  ASSERT_NE(ledge, p.faces.end()) << "the ledge at z = 5";
  EXPECT_EQ(bounds(ledge->outer), (Rect{{25, -15}, {35, 5}})) << "20 mm deep, from the front to the back wall";
  EXPECT_TRUE(has_line(p, LineKind::valley, {25, 5}, {35, 5})) << "the ledge folds up onto the back wall";
}

TEST(FaceModel, SubtractionSplitsFacesIntoPieces) {
  FaceModel m(60, 50, 50);
  // A wall from the floor to past the sheet top cuts the back board into a left and a right piece.
  m.apply(edit(EditOp::add_vface, 10, {{20, 0}, {40, 0}, {40, 60}, {20, 60}}));
  const auto faces = m.faces();
  const auto boards = std::count_if(faces.begin(), faces.end(),
                                    [](const OAFace& f) { return f.kind == FaceKind::vertical && f.t_mm == 0; });
  EXPECT_EQ(boards, 2) << "the back board is now two pieces";
  const Pattern p = make_pattern(m);
  const auto problems = testing::check_tiling(p, 10);
  EXPECT_TRUE(problems.empty()) << "the pieces and the wall still tile the sheet: "
                                << (problems.empty() ? "" : problems[0]);
}

TEST(FaceModel, CoveredFacesDisappear) {
  FaceModel m(60, 50, 50);
  m.apply(edit(EditOp::add_vface, 20, {{20, 0}, {30, 0}, {30, 10}, {20, 10}}));
  ASSERT_EQ(m.face_count(), 3u) << "board, floor, the small face";
  // A larger face in another plane covering the first one's whole pattern polygon replaces it.
  m.apply(edit(EditOp::add_vface, 25, {{10, 0}, {40, 0}, {40, 20}, {10, 20}}));
  const auto faces = m.faces();
  EXPECT_EQ(faces.size(), 3u) << "the covered face is gone, not left empty";
  EXPECT_TRUE(std::none_of(faces.begin(), faces.end(), [](const OAFace& f) { return f.t_mm == 20; }))
      << "no face at depth 20";
}

TEST(FaceModel, DecimalCoordinatesAreExact) {
  // t_h - t_v = 1.1 - 0.1 must equal v = 1 exactly, or the fold would be typed as a cut.
  FaceModel m(10, 5, 5);
  m.apply(edit(EditOp::add_vface, 0.1, {{2, 0}, {8, 0}, {8, 1.1}, {2, 1.1}}));
  m.apply(edit(EditOp::add_hface, 1.1, {{2, 0}, {8, 0}, {8, 0.1}, {2, 0.1}}));
  const Pattern p = make_pattern(m);
  EXPECT_TRUE(has_line(p, LineKind::mountain, {2, 1}, {8, 1})) << "the roof folds into the front at v = 1";
  EXPECT_TRUE(check_popup(p).pops_up()) << "the decimal box pops up";
}

TEST(FaceModel, PatternFacesReadBackAsFaces) {
  // A notch whose tip touches the back board's edge pinches it; the ring keeps that vertex, so
  // the pattern's faces are simple and load again as a faces model.
  FaceModel m(10, 5, 5);
  m.apply(edit(EditOp::add_vface, 1, {{2, 1}, {4, 1}, {4.5, 2}, {5, 1}, {5, 4}, {2, 4}}));
  const Pattern p = make_pattern(m);
  std::vector<OAFace> faces;
  for (const PatternFace& f : p.faces) faces.push_back({f.kind, f.t_mm, {f.outer, f.holes}});
  EXPECT_NO_THROW(FaceModel::from_faces(10, 5, 5, faces, "again.json")) << "every ring of the pattern is simple";
}

TEST(FaceModel, BoardsComeFromTheGeometry) {
  FaceModel roof_only(10, 10, 10);
  roof_only.apply(edit(EditOp::add_hface, 10, {{0, 0}, {10, 0}, {10, 20}, {0, 20}}));
  const PopupReport r = check_popup(make_pattern(roof_only));
  EXPECT_TRUE(r.no_back_board) << "one HFace over the whole sheet leaves no back board";
  EXPECT_FALSE(r.pops_up()) << "so it is no card";
  FaceModel split(60, 50, 50);
  split.apply(edit(EditOp::add_vface, 10, {{20, 0}, {40, 0}, {40, 60}, {20, 60}}));
  const Pattern p = make_pattern(split);
  for (const FaceProblem& f : check_popup(p).not_standing) {
    const PatternFace& face = p.faces[static_cast<std::size_t>(f.face)];
    EXPECT_FALSE(face.kind == FaceKind::vertical && face.t_mm == 0)
        << "a piece of the back board is never 'not standing'";
  }
}

TEST(FaceModel, UndoRedo) {
  FaceModel m = box_card();
  const Pattern before = make_pattern(m);
  m.apply(edit(EditOp::add_vhole, 20, {{25, 10}, {35, 10}, {35, 20}, {25, 20}}));
  const Pattern with_hole = make_pattern(m);
  ASSERT_TRUE(m.undo()) << "one edit to undo";
  EXPECT_EQ(make_pattern(m), before) << "undo restores the pattern exactly";
  EXPECT_EQ(m.edits().size(), 2u) << "and the edit list";
  ASSERT_TRUE(m.redo()) << "one edit to redo";
  EXPECT_EQ(make_pattern(m), with_hole) << "redo brings the hole back";
  ASSERT_TRUE(m.undo());
  m.apply(edit(EditOp::add_hface, 10, {{0, 0}, {5, 0}, {5, 5}, {0, 5}}));
  EXPECT_FALSE(m.redo()) << "a new edit clears the redo list";
  EXPECT_TRUE(m.undo() && m.undo() && m.undo()) << "three edits to undo";
  EXPECT_FALSE(m.undo()) << "nothing before the blank card";
  EXPECT_EQ(m.face_count(), 2u) << "back to the blank card";
}

TEST(FaceModel, JsonRoundTrip) {
  FaceModel m = box_card();
  m.apply(edit(EditOp::add_vhole, 20, {{25, 10}, {35, 10}, {35, 20}, {25, 20}}));
  const FaceModel from_edits = parse_face_model(to_face_json(m), "rt.json");
  EXPECT_EQ(from_edits.edits(), m.edits()) << "the edit list survives";
  EXPECT_EQ(make_pattern(from_edits), make_pattern(m)) << "and replays to the same pattern";
  const FaceModel as_faces = FaceModel::from_faces(60, 50, 50, m.faces(), "faces.json");
  const FaceModel from_faces = parse_face_model(to_face_json(as_faces), "rt2.json");
  EXPECT_EQ(make_pattern(from_faces), make_pattern(m)) << "a model given by its faces gives the same pattern";
}

TEST(FaceModel, EditOpsAreReadByTheirFileNames) {
  for (EditOp op : {EditOp::add_vface, EditOp::add_hface, EditOp::add_vhole, EditOp::add_hhole}) {
    EXPECT_EQ(kEditOpNames.find(to_string(op)), op) << to_string(op);
  }
  std::string text = to_face_json(box_card());
  const std::string first = "\"op\": \"add_vface\"";
  ASSERT_NE(text.find(first), std::string::npos) << text;
  text.replace(text.find(first), first.size(), "\"op\": \"add_window\"");
  try {
    parse_face_model(text, "card.json");
    FAIL() << "an unknown op is rejected";
  } catch (const Error& e) {
    EXPECT_EQ(e.location(), "edits[0].op") << e.what();
    EXPECT_EQ(e.message(), "expected \"add_vface\", \"add_hface\", \"add_vhole\" or \"add_hhole\", got \"add_window\"");
  }
}

struct BadEdit {
  const char* name;
  FaceEdit edit;
  const char* location;
  const char* fragment;
};

class BadFaceEdit : public ::testing::TestWithParam<BadEdit> {};

void PrintTo(const BadEdit& b, std::ostream* os) { *os << b.name; }

TEST_P(BadFaceEdit, IsRejectedAndChangesNothing) {
  FaceModel m = box_card();
  const Pattern before = make_pattern(m);
  try {
    m.apply(GetParam().edit, "card.json", "edits[2]");
    FAIL() << GetParam().name << ": should be rejected";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input) << e.what();
    EXPECT_EQ(e.location(), GetParam().location) << GetParam().name << ": " << e.what();
    EXPECT_NE(e.message().find(GetParam().fragment), std::string::npos) << GetParam().name << ": " << e.what();
  }
  EXPECT_EQ(make_pattern(m), before) << GetParam().name << ": a rejected edit leaves the model as it was";
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();
INSTANTIATE_TEST_SUITE_P(
    Cases, BadFaceEdit,
    ::testing::Values(
        BadEdit{"bowtie", {EditOp::add_vface, 5, {{0, 0}, {10, 10}, {10, 0}, {0, 10}}}, "edits[2].outline", "crosses"},
        BadEdit{
            "two points", {EditOp::add_vface, 5, {{0, 0}, {10, 10}, {0, 0}}}, "edits[2].outline", "3 distinct points"},
        BadEdit{"collinear", {EditOp::add_vface, 5, {{0, 0}, {5, 0}, {10, 0}}}, "edits[2].outline", ""},
        BadEdit{"outside sheet",
                {EditOp::add_vface, 5, {{50, 0}, {70, 0}, {70, 10}, {50, 10}}},
                "edits[2].outline",
                "leaves the sheet"},
        BadEdit{"nan", {EditOp::add_hface, 5, {{0, 0}, {kNaN, 0}, {10, 10}}}, "edits[2].outline", "finite"},
        BadEdit{"huge", {EditOp::add_hface, 5, {{0, 0}, {1e9, 0}, {10, 10}}}, "edits[2].outline", "100000"},
        BadEdit{"below floor",
                {EditOp::add_vface, 5, {{0, -1}, {10, 0}, {10, 10}}},
                "edits[2].outline[0]",
                "below the floor"},
        BadEdit{"negative t", {EditOp::add_vface, -5, {{0, 0}, {10, 0}, {10, 10}}}, "edits[2].t", "from 0"},
        BadEdit{"hole outside face",
                {EditOp::add_vhole, 20, {{5, 10}, {15, 10}, {15, 20}, {5, 20}}},
                "edits[2].outline",
                "not inside a VFace at depth"},
        BadEdit{"hole in no face",
                {EditOp::add_hhole, 7, {{20, 5}, {30, 5}, {30, 15}}},
                "edits[2].outline",
                "not inside an HFace"}),
    [](const ::testing::TestParamInfo<BadEdit>& param) {
      std::string n = param.param.name;
      for (char& ch : n) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
      return n;
    });

TEST(FaceModel, FacesThatDoNotTileAreRejected) {
  const auto rect = [](double x0, double v0, double x1, double v1) {
    return Ring{{x0, v0}, {x1, v0}, {x1, v1}, {x0, v1}};
  };
  const std::vector<OAFace> overlap = {{FaceKind::vertical, 0, {rect(0, 0, 10, 10), {}}},
                                       {FaceKind::horizontal, 0, {rect(0, -10, 10, 5), {}}}};
  try {
    FaceModel::from_faces(10, 10, 10, overlap, "o.json");
    FAIL() << "overlapping faces break eq. 4";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("overlaps faces[1]"), std::string::npos) << e.what();
  }
  const std::vector<OAFace> gap = {{FaceKind::vertical, 0, {rect(0, 0, 10, 10), {}}},
                                   {FaceKind::horizontal, 0, {rect(0, -10, 10, -1), {}}}};
  try {
    FaceModel::from_faces(10, 10, 10, gap, "g.json");
    FAIL() << "a gap breaks eq. 4";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("cover it exactly"), std::string::npos) << e.what();
  }
  const std::vector<OAFace> hole_out = {{FaceKind::vertical, 0, {rect(0, 0, 10, 10), {rect(5, 5, 20, 6)}}}};
  EXPECT_THROW(FaceModel::from_faces(10, 10, 10, hole_out, "h.json"), Error) << "a hole outside its face";
  // Regions of a subdivision on the grid are only summed: a gap is still refused. Without the
  // caller's word that they are its loops, a bowtie or a clockwise hole leaving its face is too.
  EXPECT_THROW(FaceModel::from_subdivision(10, 10, 10, gap, "g.json", true), Error) << "a gap";
  EXPECT_THROW(FaceModel::from_subdivision(10, 10, 10, hole_out, "h.json"), Error) << "a hole outside its face";
  const std::vector<OAFace> hole_out_cw = {
      {FaceKind::vertical, 0, {rect(0, 0, 10, 10), {{{5, 5}, {5, 6}, {20, 6}, {20, 5}}}}},
      {FaceKind::horizontal, 0, {rect(0, -10, 10, 0), {}}}};
  EXPECT_THROW(FaceModel::from_subdivision(10, 10, 10, hole_out_cw, "h.json"), Error) << "a clockwise hole outside";
  const std::vector<OAFace> bowtie = {{FaceKind::vertical, 0, {{{0, 0}, {10, 10}, {10, 0}, {0, 10}}, {}}},
                                      {FaceKind::horizontal, 0, {rect(0, -10, 10, 0), {}}}};
  EXPECT_THROW(FaceModel::from_subdivision(10, 10, 10, bowtie, "b.json"), Error) << "a self-crossing outline";
}

TEST(FaceModel, ASubdivisionBuildsTheSameModelAsGivenFaces) {
  // A wall, a floor with a hole and the face filling it; then a slanted edge, off the 1 nm grid,
  // which takes the full overlap check.
  const std::vector<OAFace> faces = {
      {FaceKind::vertical, 0, {{{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {}}},
      {FaceKind::horizontal, 0, {{{0, -10}, {10, -10}, {10, 0}, {0, 0}}, {{{2, -8}, {2, -2}, {8, -2}, {8, -8}}}}},
      {FaceKind::horizontal, 0.5, {{{2, -8}, {8, -8}, {8, -2}, {2, -2}}, {}}}};
  const FaceModel given = FaceModel::from_faces(10, 10, 10, faces, "f.json");
  const FaceModel sub = FaceModel::from_subdivision(10, 10, 10, faces, "f.json", true);
  ASSERT_EQ(sub.face_count(), given.face_count());
  for (std::size_t i = 0; i < given.faces().size(); ++i) {
    EXPECT_EQ(sub.faces()[i].polygon.outer, given.faces()[i].polygon.outer) << i;
    EXPECT_EQ(sub.faces()[i].t_mm, given.faces()[i].t_mm) << i;
  }
  const double third = 10.0 / 3;
  const std::vector<OAFace> slanted = {
      {FaceKind::vertical, 0, {{{0, 0}, {10, 0}, {10, third}, {0, 10}}, {}}},
      {FaceKind::vertical, 2, {{{0, 10}, {10, third}, {10, 10}}, {}}},
      {FaceKind::horizontal, 0, {{{0, -10}, {10, -10}, {10, 0}, {0, 0}}, {{{2, -8}, {8, -2}, {8, -8}}}}},
      {FaceKind::horizontal, 1, {{{1, -7}, {7, -1}, {1, -1}}, {}}}};  // as large as the hole, not in it
  try {
    FaceModel::from_subdivision(10, 10, 10, slanted, "s.json", true);
    FAIL() << "the last face overlaps the floor though the areas add up";
  } catch (const Error& e) {
    EXPECT_NE(e.message().find("overlaps"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace popcut
