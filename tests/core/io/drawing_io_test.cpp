// Drawings from SVG (as Inkscape and popcut write them) and FOLD (the spec's examples): kinds, units, errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include "error_of.h"
#include "popcut/error.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/files.h"
#include "popcut/io/model_io.h"
#include "popcut/io/pattern_io.h"
#include "shared_testdata.h"

namespace popcut {
namespace {

using testing::error_of;

std::string svg_doc(const std::string& body,
                    const std::string& size = "width=\"100mm\" height=\"50mm\" viewBox=\"0 0 100 50\"") {
  return "<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" "
         "xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" " +
         size + ">\n" + body + "\n</svg>\n";
}

double length(const DrawnLine& l) {
  double s = 0;
  for (std::size_t i = 0; i + 1 < l.points.size(); ++i)
    s += std::hypot(l.points[i + 1].x_mm - l.points[i].x_mm, l.points[i + 1].v_mm - l.points[i].v_mm);
  if (l.closed) s += std::hypot(l.points[0].x_mm - l.points.back().x_mm, l.points[0].v_mm - l.points.back().v_mm);
  return s;
}

TEST(SvgDrawing, InkscapeLayersTransformsAndUnits) {
  // Inkscape writes layers as groups with inkscape:label and translates them; the page is 4 × 2 in
  // drawn in px user units (96 per inch).
  const std::string text = svg_doc(
      "<g inkscape:groupmode=\"layer\" inkscape:label=\"Talfalte\" transform=\"translate(10,0)\">"
      "<path id=\"v1\" style=\"stroke:#000000\" d=\"m 0,96 h 96\"/></g>"
      "<g inkscape:label=\"Layer 3 - Mountain folds\"><line id=\"m1\" x1=\"0\" y1=\"48\" x2=\"192\" y2=\"48\"/></g>"
      "<path id=\"c1\" stroke=\"black\" transform=\"scale(2)\" d=\"M0 0 L 48 0\"/>",
      "width=\"4in\" height=\"2in\" viewBox=\"0 0 384 192\"");
  const LineDrawing d = read_svg_drawing(text, "card.svg");
  ASSERT_EQ(d.lines.size(), 3u);
  ASSERT_TRUE(d.page);
  EXPECT_NEAR(d.page->max.x_mm, 101.6, 1e-9);
  EXPECT_EQ(d.lines[0].kind, DrawnKind::valley);
  EXPECT_EQ(d.lines[0].why, "layer \"Talfalte\"");
  EXPECT_NEAR(d.lines[0].points[0].x_mm, 10 * 25.4 / 96, 1e-9);
  EXPECT_NEAR(d.lines[0].points[0].v_mm, 50.8 - 25.4, 1e-9);  // y = 1 in down the page: v = 1 in up
  EXPECT_NEAR(length(d.lines[0]), 25.4, 1e-9);
  EXPECT_EQ(d.lines[1].kind, DrawnKind::mountain);
  EXPECT_EQ(d.lines[2].kind, DrawnKind::cut);
  EXPECT_NEAR(length(d.lines[2]), 25.4, 1e-9);
  EXPECT_NE(d.lines[2].where.find("<path id=\"c1\">"), std::string::npos) << d.lines[2].where;
}

TEST(SvgDrawing, DashPatternsAndColoursByConvention) {
  const LineDrawing d = read_svg_drawing(
      svg_doc("<line x1=\"0\" y1=\"0\" x2=\"10\" y2=\"0\" stroke=\"#777\" stroke-dasharray=\"2 1\"/>"
              "<line x1=\"0\" y1=\"1\" x2=\"10\" y2=\"1\" style=\"stroke:#123456;stroke-dasharray:2,0.5,0.4,0.5\"/>"
              "<line x1=\"0\" y1=\"2\" x2=\"10\" y2=\"2\" stroke=\"red\"/>"
              "<line x1=\"0\" y1=\"3\" x2=\"10\" y2=\"3\" stroke=\"rgb(0, 0, 255)\"/>"
              "<line id=\"odd\" x1=\"0\" y1=\"4\" x2=\"10\" y2=\"4\" stroke=\"#ffa500\"/>"
              "<rect x=\"0\" y=\"0\" width=\"5\" height=\"5\" fill=\"#eee\" stroke=\"none\"/>"),
      "s.svg");
  ASSERT_EQ(d.lines.size(), 5u);
  EXPECT_EQ(d.lines[0].kind, DrawnKind::valley);
  EXPECT_EQ(d.lines[1].kind, DrawnKind::mountain);
  EXPECT_EQ(d.lines[2].kind, DrawnKind::mountain);
  EXPECT_EQ(d.lines[3].kind, DrawnKind::valley);
  EXPECT_EQ(d.lines[4].kind, DrawnKind::unknown);
  EXPECT_NE(d.lines[4].why.find("#ffa500"), std::string::npos);
  EXPECT_EQ(d.notes.size(), 1u) << "the unstroked fill is noted";
  DrawingOptions laser;
  laser.red_is_cut = true;
  EXPECT_EQ(read_svg_drawing(svg_doc("<line x1=\"0\" y1=\"2\" x2=\"10\" y2=\"2\" stroke=\"#f00\"/>"), "s", laser)
                .lines[0]
                .kind,
            DrawnKind::cut);
}

TEST(SvgDrawing, StrokesSetByAStyleSheetAreListedNotGuessed) {
  // As Illustrator exports: classes styled from a <style> element.
  const LineDrawing d = read_svg_drawing(
      svg_doc("<defs><style>.cls-1{stroke:#ff0000}</style></defs>"
              "<line class=\"cls-1\" x1=\"0\" y1=\"0\" x2=\"10\" y2=\"0\"/>"
              "<g inkscape:label=\"Cut\"><line class=\"cls-1\" x1=\"0\" y1=\"1\" x2=\"9\" y2=\"1\"/></g>"),
      "ai.svg");
  ASSERT_EQ(d.lines.size(), 2u);
  EXPECT_EQ(d.lines[0].kind, DrawnKind::unknown);
  EXPECT_NE(d.lines[0].why.find("CSS class \"cls-1\""), std::string::npos) << d.lines[0].why;
  EXPECT_EQ(d.lines[1].kind, DrawnKind::cut) << "a layer name still decides";
}

TEST(SvgDrawing, CurvesFlattenWithinTheChordTolerance) {
  DrawingOptions o;
  o.chord_tolerance_mm = 0.01;
  const LineDrawing d = read_svg_drawing(svg_doc("<circle cx=\"50\" cy=\"25\" r=\"20\"/>"
                                                 "<path d=\"M 10 25 A 15 15 0 0 1 40 25\"/>"
                                                 "<path d=\"M0,0 C 0,10 10,10 10,0 S 20,-10 20,0\"/>"
                                                 "<rect x=\"1\" y=\"1\" width=\"20\" height=\"10\" rx=\"3\"/>"),
                                         "c.svg", o);
  ASSERT_EQ(d.lines.size(), 4u);
  for (const Point2& p : d.lines[0].points) EXPECT_NEAR(std::hypot(p.x_mm - 50, p.v_mm - 25), 20, 1e-9);
  EXPECT_NEAR(length(d.lines[0]), 2 * std::numbers::pi * 20, 0.05);
  EXPECT_TRUE(d.lines[0].closed);
  EXPECT_NEAR(length(d.lines[1]), std::numbers::pi * 15, 0.02);  // a half circle
  for (const Point2& p : d.lines[1].points) EXPECT_GE(p.v_mm, 25 - 1e-9) << "sweep 1 bulges up the page (v up)";
  EXPECT_NEAR(d.lines[2].points.back().x_mm, 20, 1e-12);
  EXPECT_NEAR(length(d.lines[3]), 2 * (14 + 4) + 2 * std::numbers::pi * 3, 0.02);
}

TEST(SvgDrawing, PopcutsOwnSvgReadsBackLineForLine) {
  const AnyModel m = load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/faces/pavilion.json");
  const Pattern p = make_pattern(m, "pagoda");
  const LineDrawing d = read_svg_drawing(to_pattern_svg(p, {.shade_faces = true}), "pagoda.svg");
  std::vector<Segment> in_file_order;  // the writer groups valley, mountain, cut
  for (const LineKind k : {LineKind::valley, LineKind::mountain, LineKind::cut})
    for (const Segment& s : p.lines)
      if (s.kind == k) in_file_order.push_back(s);
  const DrawnKind drawn[] = {DrawnKind::cut, DrawnKind::mountain, DrawnKind::valley};
  std::size_t outline = 0, lines = 0;
  for (const DrawnLine& l : d.lines) {
    if (l.kind == DrawnKind::outline) {
      ++outline;
      continue;
    }
    ASSERT_LT(lines, in_file_order.size());
    const Segment& s = in_file_order[lines++];
    EXPECT_EQ(l.kind, drawn[static_cast<int>(s.kind)]);
    EXPECT_NEAR(l.points[0].x_mm, s.a.x_mm - p.sheet.min.x_mm, 1e-4);
    EXPECT_NEAR(l.points[0].v_mm, s.a.v_mm - p.sheet.min.v_mm, 1e-4);
  }
  EXPECT_EQ(outline, 1u);
  EXPECT_EQ(lines, p.lines.size());
}

TEST(SvgDrawing, BadInputNamesTheElement) {
  const auto err = [](const std::string& body,
                      const std::string& size = "width=\"100mm\" height=\"50mm\" viewBox=\"0 0 100 50\"") {
    return error_of([&] { read_svg_drawing(svg_doc(body, size), "bad.svg"); });
  };
  EXPECT_NE(error_of([] { read_svg_drawing("<svg><g></svg>", "bad.svg"); }).message().find("malformed XML"),
            std::string::npos);
  EXPECT_NE(error_of([] { read_svg_drawing("<html/>", "bad.svg"); }).message().find("expected an <svg>"),
            std::string::npos);
  const Error unit = err("", "width=\"10furlong\" height=\"5mm\"");
  EXPECT_NE(unit.message().find("unknown unit \"furlong\""), std::string::npos) << unit.message();
  const Error d = err("<path id=\"p9\" d=\"M 0 0 L 1 x\"/>");
  EXPECT_EQ(d.location(), "line 3, <path id=\"p9\">");
  EXPECT_NE(d.message().find("expected a number"), std::string::npos);
  EXPECT_NE(err("<path d=\"M 0 0 K 1 1\"/>").message().find("unknown path command \"K\""), std::string::npos);
  EXPECT_NE(err("<line x1=\"3\" y1=\"3\" x2=\"3\" y2=\"3\"/>").message().find("zero-length"), std::string::npos);
  EXPECT_NE(err("<line x1=\"1e9\" y1=\"0\" x2=\"0\" y2=\"0\"/>").message().find("beyond"), std::string::npos);
  EXPECT_NE(err("<g transform=\"spin(3)\"><line x1=\"0\" y1=\"0\" x2=\"1\" y2=\"0\"/></g>")
                .message()
                .find("unknown transform"),
            std::string::npos);
  EXPECT_NE(err("<g id=\"a\"><use href=\"#a\"/></g>").message().find("deeper"), std::string::npos);
  EXPECT_NE(err("<use href=\"#nothing\"/>").message().find("no element"), std::string::npos);
  std::string many = "<path d=\"M0 0";
  for (int i = 0; i < 2'000'001; ++i) many += " L1 1";
  EXPECT_EQ(err(many + "\"/>").code(), ErrorCode::limit);
  std::string circles;  // each flattens to about 3,000 chords: 700 of them pass the limit
  for (int i = 0; i < 700; ++i) circles += "<circle cx=\"50\" cy=\"25\" r=\"90000\"/>";
  EXPECT_EQ(err(circles).code(), ErrorCode::limit);
}

TEST(SvgDrawing, LayerNamesInManyLanguagesAndConfigured) {
  const DrawingOptions none;
  EXPECT_EQ(kind_of_layer_name("VALLEY", none), DrawnKind::valley);
  EXPECT_EQ(kind_of_layer_name("Berg", none), DrawnKind::mountain);
  EXPECT_EQ(kind_of_layer_name("Layer 2 - scores", none), DrawnKind::fold);
  EXPECT_EQ(kind_of_layer_name("谷折り", none), DrawnKind::valley);
  EXPECT_EQ(kind_of_layer_name("cut and fold", none), std::nullopt);
  EXPECT_EQ(kind_of_layer_name("artwork", none), std::nullopt);
  DrawingOptions custom;
  custom.layer_names = {{"Knife", DrawnKind::cut}};
  EXPECT_EQ(kind_of_layer_name("knife", custom), DrawnKind::cut);
}

// Throws naming the file when it is missing, so a test without its inputs says so.
std::string slurp(const std::string& path) { return read_text_file(path); }

TEST(FoldDrawing, TheSpecsCreasePatternExample) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  const std::string path = popcut::testing::shared_testdata("fold/diagonal-cp.fold");
  const LineDrawing d = read_fold_drawing(slurp(path), path);
  int outline = 0, valley = 0;
  for (const DrawnLine& l : d.lines) {
    outline += l.kind == DrawnKind::outline;
    valley += l.kind == DrawnKind::valley;
  }
  EXPECT_EQ(outline, 4);
  EXPECT_EQ(valley, 1);
  EXPECT_EQ(d.notes.size(), 1u) << "no unit stated, so the unit is noted";
}

TEST(FoldDrawing, FoldedFormsAreRefusedByName) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  for (const char* name : {"box", "simple"}) {
    const std::string path = popcut::testing::shared_testdata(std::string("fold/") + name + ".fold");
    const Error e = error_of([&] { read_fold_drawing(slurp(path), path); });
    EXPECT_NE(e.message().find("folded"), std::string::npos) << name << ": " << e.message();
  }
}

TEST(FoldDrawing, BadInputNamesTheField) {
  const auto err = [](const std::string& text) { return error_of([&] { read_fold_drawing(text, "bad.fold"); }); };
  EXPECT_EQ(err("{\"vertices_coords\": [[0,0],[1,0]], \"edges_vertices\": [[0,2]]}").location(),
            "edges_vertices[0][1]");
  EXPECT_EQ(err("{\"vertices_coords\": [[0,0],[1,0]], \"edges_vertices\": [[0,1]], \"edges_assignment\": [\"X\"]}")
                .location(),
            "edges_assignment[0]");
  EXPECT_EQ(
      err("{\"vertices_coords\": [[0,0],[1,0]], \"edges_vertices\": [[0,1]], \"edges_assignment\": []}").location(),
      "edges_assignment");
  EXPECT_EQ(err("{\"vertices_coords\": [[0,0],[0,0]], \"edges_vertices\": [[0,1]]}").location(), "edges_vertices[0]");
  EXPECT_EQ(err("{\"frame_unit\": \"furlong\", \"vertices_coords\": [], \"edges_vertices\": []}").location(),
            "frame_unit");
  EXPECT_NE(err("{\"vertices_coords\": [[0,0]").location().find("line 1"), std::string::npos);
}

TEST(FoldDrawing, UnitsAndFoldAngles) {
  const LineDrawing d = read_fold_drawing(
      "{\"frame_unit\": \"cm\", \"vertices_coords\": [[0,0],[1,0],[1,1]], \"edges_vertices\": [[0,1],[1,2]],"
      " \"edges_assignment\": [\"U\", \"C\"], \"edges_foldAngle\": [-90, null]}",
      "u.fold");
  ASSERT_EQ(d.lines.size(), 2u);
  EXPECT_EQ(d.lines[0].kind, DrawnKind::mountain);
  EXPECT_EQ(d.lines[0].fold_angle_deg, -90);
  EXPECT_EQ(d.lines[0].points[1].x_mm, 10);
  EXPECT_EQ(d.lines[1].kind, DrawnKind::cut);
  EXPECT_TRUE(d.notes.empty());
}

}  // namespace
}  // namespace popcut
