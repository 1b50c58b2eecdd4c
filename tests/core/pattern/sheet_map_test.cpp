// The sheet map of hand-made drawings: snapping, holes, slits, the sheet's edge; and each kind of card conflict.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "error_of.h"
#include "popcut/error.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/pattern.h"

namespace popcut {
namespace {

DrawnLine line(DrawnKind kind, std::vector<Point2> points, const std::string& where, bool closed = false) {
  return {kind, std::move(points), closed, where, "test", {}};
}

// A 100 × 120 sheet with the one-step card of examples/drawn/step.svg (v up; centre fold at 60).
LineDrawing step(DrawnKind top = DrawnKind::valley, DrawnKind edge = DrawnKind::mountain, double edge_v = 60) {
  LineDrawing d;
  d.source = "step";
  d.lines = {line(DrawnKind::outline, {{0, 0}, {100, 0}, {100, 120}, {0, 120}}, "outline", true),
             line(DrawnKind::cut, {{30, 40}, {30, 80}}, "left side"),
             line(DrawnKind::cut, {{70, 40}, {70, 80}}, "right side"),
             line(DrawnKind::valley, {{0, 60}, {30, 60}}, "centre left"),
             line(DrawnKind::valley, {{70, 60}, {100, 60}}, "centre right"),
             line(top, {{30, 80}, {70, 80}}, "step top"),
             line(edge, {{30, edge_v}, {70, edge_v}}, "step edge"),
             line(DrawnKind::valley, {{30, 40}, {70, 40}}, "step foot")};
  return d;
}

Error error_of(const LineDrawing& d) {
  return testing::error_of([&] { build_sheet_map(d); });
}

std::string conflicts(const LineDrawing& d) { return describe_conflicts(infer_card(d, build_sheet_map(d))); }

TEST(SheetMap, TheStepCardsRegionsAndTheCardTheyMake) {
  const LineDrawing d = step();
  const SheetMap m = build_sheet_map(d);
  EXPECT_EQ(m.regions.size(), 4u);
  double area = 0;
  for (const SheetRegion& r : m.regions) area += r.area_mm2;
  EXPECT_NEAR(area, 100 * 120, 1e-9);
  const InferredCard card = infer_card(d, m);
  ASSERT_TRUE(card.model) << describe_conflicts(card);
  EXPECT_DOUBLE_EQ(card.centre_fold_v_mm, 60);
  const Pattern p = make_pattern(*card.model);
  const LineCounts c = count_lines(p);
  EXPECT_EQ(c.mountain, 1);
  EXPECT_EQ(c.valley, 4);
}

TEST(SheetMap, ScoresTakeTheDirectionTheCardFoldsThem) {
  LineDrawing d = step(DrawnKind::fold, DrawnKind::fold);
  for (DrawnLine& l : d.lines)
    if (l.kind == DrawnKind::valley) l.kind = DrawnKind::fold;
  const InferredCard card = infer_card(d, build_sheet_map(d));
  ASSERT_TRUE(card.model) << describe_conflicts(card);
  EXPECT_EQ(count_lines(make_pattern(*card.model)).mountain, 1);
}

TEST(SheetMap, EndsAHairApartSnapWithinTheTolerance) {
  LineDrawing d = step();
  d.lines[3].points[1].x_mm = 29.995;  // the centre fold stops 5 µm short of the cut
  d.lines[6].points[0] = {30.004, 60.003};
  const SheetMap m = build_sheet_map(d);
  EXPECT_EQ(m.snapped_ends, 2);
  EXPECT_TRUE(infer_card(d, m).model) << conflicts(d);
  d.lines[3].points[1].x_mm = 29.9;  // 0.1 mm short: a slit, not a junction
  EXPECT_NE(conflicts(d).find("ends inside one face"), std::string::npos) << conflicts(d);
}

TEST(SheetMap, AHoleAndAPieceCutFree) {
  LineDrawing d = step();
  d.lines.push_back(line(DrawnKind::cut, {{40, 95}, {60, 95}, {60, 110}, {40, 110}}, "window", true));
  const SheetMap m = build_sheet_map(d);
  ASSERT_EQ(m.regions.size(), 5u);
  int with_hole = 0;
  for (const SheetRegion& r : m.regions) with_hole += r.holes.size() == 1;
  EXPECT_EQ(with_hole, 1);
  const std::string why = conflicts(d);
  EXPECT_NE(why.find("a piece cut free of the sheet (300 mm²)"), std::string::npos) << why;
}

TEST(SheetMap, EachKindOfConflictIsNamed) {
  EXPECT_NE(conflicts(step(DrawnKind::valley, DrawnKind::mountain, 65)).find("do not meet at the fold's height"),
            std::string::npos);
  EXPECT_NE(conflicts(step(DrawnKind::valley, DrawnKind::valley))
                .find("drawn as a valley fold, but the card folds it mountain"),
            std::string::npos);
  LineDrawing slanted = step();
  slanted.lines[6].points[1].v_mm = 61;
  EXPECT_NE(conflicts(slanted).find("not parallel to the centre fold"), std::string::npos) << conflicts(slanted);
  LineDrawing slit = step();
  slit.lines.push_back(line(DrawnKind::cut, {{10, 90}, {20, 100}}, "slit"));
  const std::string why = conflicts(slit);
  EXPECT_NE(why.find("at (15, 95) mm, slit: a cut line ends inside one face"), std::string::npos) << why;
  LineDrawing lacks = step(DrawnKind::valley, DrawnKind::cut);  // the step's front edge drawn as a cut
  EXPECT_NE(
      conflicts(lacks).find("at (50, 60) mm, step edge: the card needs a mountain line here that the drawing lacks"),
      std::string::npos)
      << conflicts(lacks);
  LineDrawing stray = step();  // a cut from the top edge down to the centre fold parts the back board
  stray.lines.push_back(line(DrawnKind::cut, {{15, 60}, {15, 120}}, "stray"));
  EXPECT_NE(conflicts(stray).find(
                "stray: a drawn cut line the card does not have: the faces on its two sides lie in one plane"),
            std::string::npos)
      << conflicts(stray);
  LineDrawing skew = step();
  skew.lines[0].points.insert(skew.lines[0].points.begin() + 3, Point2{50, 130});  // a gable on the top edge
  EXPECT_NE(conflicts(skew).find("not a rectangle"), std::string::npos) << conflicts(skew);
}

TEST(SheetMap, BadSheetsNameTheElement) {
  LineDrawing open = step();
  open.lines[0].closed = false;
  const Error e = error_of(open);
  EXPECT_EQ(e.location(), "outline");
  EXPECT_NE(e.message().find("the sheet's outline is not closed"), std::string::npos) << e.message();
  LineDrawing outside = step();
  outside.lines.push_back(line(DrawnKind::cut, {{110, 10}, {120, 10}}, "stray"));
  EXPECT_EQ(error_of(outside).location(), "stray");
  LineDrawing crossing = step();
  crossing.lines.push_back(line(DrawnKind::cut, {{35, 40}, {65, 40}}, "cut on a fold"));
  const Error over = error_of(crossing);
  EXPECT_NE(over.message().find("drawn over"), std::string::npos) << over.message();
  LineDrawing unknown = step();
  unknown.lines[1].kind = DrawnKind::unknown;
  EXPECT_EQ(error_of(unknown).location(), "left side");
  LineDrawing edge_fold;
  edge_fold.lines = {line(DrawnKind::cut, {{0, 0}, {10, 0}, {10, 10}}, "cut"),
                     line(DrawnKind::valley, {{10, 10}, {0, 0}}, "v")};
  EXPECT_NE(error_of(edge_fold).message().find("on the sheet's edge"), std::string::npos);
  LineDrawing two;
  two.lines = {line(DrawnKind::cut, {{0, 0}, {1, 0}, {1, 1}}, "a", true),
               line(DrawnKind::cut, {{5, 5}, {6, 5}, {6, 6}}, "b", true)};
  EXPECT_NE(error_of(two).message().find("2 separate sheets"), std::string::npos);
}

}  // namespace
}  // namespace popcut
