// DXF reader: files ezdxf (an independent DXF library) writes, against ezdxf's own flattening; bad input by line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "io/dxf_curves.h"
#include "error_of.h"
#include "popcut/error.h"
#include "popcut/fold/sheet_fold.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/files.h"
#include "popcut/io/model_io.h"
#include "popcut/io/pattern_io.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/pattern/face_pattern.h"

namespace popcut {
namespace {

using testing::error_of;

namespace fs = std::filesystem;

double to_segment(Point2 p, Point2 a, Point2 b) {
  const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, len2 = dx * dx + dv * dv;
  const double t = len2 > 0 ? std::clamp(((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / len2, 0.0, 1.0) : 0;
  return std::hypot(p.x_mm - a.x_mm - t * dx, p.v_mm - a.v_mm - t * dv);
}

double to_polyline(Point2 p, const std::vector<Point2>& line, bool closed) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, to_segment(p, line[i], line[i + 1]));
  if (closed) best = std::min(best, to_segment(p, line.back(), line.front()));
  return best;
}

// The larger of the two one-sided distances between the polylines.
double hausdorff(const std::vector<Point2>& a, bool a_closed, const std::vector<Point2>& b) {
  double d = 0;
  for (const Point2& p : a) d = std::max(d, to_polyline(p, b, false));
  for (const Point2& p : b) d = std::max(d, to_polyline(p, a, a_closed));
  return d;
}

class EzdxfFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("popcut-ezdxf-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    // Debian's python3-ezdxf (scripts/setup) is installed for the system interpreter.
    const std::string cmd = "/usr/bin/python3 " POPCUT_SOURCE_DIR "/tests/core/io/ezdxf_cases.py " + dir_.string();
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string file(const std::string& name) { return (dir_ / name).string(); }
  static fs::path dir_;
};
fs::path EzdxfFiles::dir_;

// A box dieline from CAD, in inches: it folds as a sheet into the same closed 80 × 60 × 30 mm box
// as examples/drawn/box.svg, its tabs turned in after the walls.
TEST_F(EzdxfFiles, ACadBoxDielineFoldsShut) {
  const LineDrawing d = load_drawing(file("box-in.dxf"));
  FoldableSheet s = make_foldable_sheet(d, build_sheet_map(d));
  ASSERT_EQ(s.map.regions.size(), 11u);
  ASSERT_EQ(s.hinges.size(), 10u);
  // The tabs are the four hinges shortest of all (26 mm): stage 2.
  for (SheetHinge& h : s.hinges)
    if (std::hypot(h.b.x_mm - h.a.x_mm, h.b.v_mm - h.a.v_mm) < 27) h.stage = 2;
  EXPECT_TRUE(check_sheet_motion(s, 13).ok());
  const CardMesh m = sheet_mesh(s, fold_sheet(s, 1));
  Point3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  for (const Point3& p : m.vertices) {
    lo = {std::min(lo.x_mm, p.x_mm), std::min(lo.y_mm, p.y_mm), std::min(lo.z_mm, p.z_mm)};
    hi = {std::max(hi.x_mm, p.x_mm), std::max(hi.y_mm, p.y_mm), std::max(hi.z_mm, p.z_mm)};
  }
  EXPECT_NEAR(hi.x_mm - lo.x_mm, 80, 1e-6);
  EXPECT_NEAR(hi.y_mm - lo.y_mm, 60, 1e-6);
  EXPECT_NEAR(hi.z_mm - lo.z_mm, 30, 1e-6);
}

TEST_F(EzdxfFiles, EveryEntityFollowsEzdxfsOwnFlattening) {
  const LineDrawing d = load_drawing(file("shapes.dxf"));
  const nlohmann::json oracle = nlohmann::json::parse(read_text_file(file("shapes.json")));
  ASSERT_EQ(d.lines.size(), oracle.size());
  for (std::size_t i = 0; i < d.lines.size(); ++i) {
    std::vector<Point2> expected;
    for (const auto& p : oracle[i]["points"]) expected.push_back({p[0].get<double>(), p[1].get<double>()});
    // The default chord tolerance, plus ezdxf's own flattening distance.
    EXPECT_LT(hausdorff(d.lines[i].points, d.lines[i].closed, expected), 0.05 + 0.001)
        << i << ": " << oracle[i]["type"] << " " << d.lines[i].where;
  }
  // Layer 0 in a block takes the insert's layer; others keep their own.
  EXPECT_EQ(d.lines[11].kind, DrawnKind::valley) << d.lines[11].why;
  EXPECT_EQ(d.lines[12].kind, DrawnKind::cut) << d.lines[12].why;
  EXPECT_NE(d.lines[12].where.find("in block \"TAB\""), std::string::npos) << d.lines[12].where;
  EXPECT_NE(d.lines[27].where.find("in block \"TAB\""), std::string::npos) << d.lines[27].where;
  EXPECT_EQ(d.lines[27].kind, DrawnKind::cut) << d.lines[27].why;  // PAIR on CUT, TAB on 0 in it, a line on 0
  // Without a layer that names a kind: linetype, then colour; yellow is nobody's convention.
  EXPECT_EQ(d.lines[29].kind, DrawnKind::valley) << d.lines[29].why;
  EXPECT_EQ(d.lines[30].kind, DrawnKind::mountain) << d.lines[30].why;
  EXPECT_EQ(d.lines[31].kind, DrawnKind::mountain) << d.lines[31].why;
  EXPECT_EQ(d.lines[32].kind, DrawnKind::unknown) << d.lines[32].why;
  EXPECT_NE(d.lines[32].why.find("colour 2 (yellow)"), std::string::npos) << d.lines[32].why;
  EXPECT_NE(d.lines[1].where.find("LWPOLYLINE"), std::string::npos) << d.lines[1].where;
  EXPECT_TRUE(d.lines[1].closed);
  bool text_noted = false;
  for (const std::string& n : d.notes) text_noted |= n.find("1 TEXT") != std::string::npos;
  EXPECT_TRUE(text_noted);
}

TEST_F(EzdxfFiles, TighterToleranceFollowsCloser) {
  DrawingOptions fine;
  fine.chord_tolerance_mm = 0.002;
  const LineDrawing d = load_drawing(file("shapes.dxf"), fine);
  const nlohmann::json oracle = nlohmann::json::parse(read_text_file(file("shapes.json")));
  ASSERT_EQ(d.lines.size(), oracle.size());
  for (std::size_t i = 0; i < d.lines.size(); ++i) {
    std::vector<Point2> expected;
    for (const auto& p : oracle[i]["points"]) expected.push_back({p[0].get<double>(), p[1].get<double>()});
    EXPECT_LT(hausdorff(d.lines[i].points, d.lines[i].closed, expected), 0.002 + 0.001) << i;
  }
}

TEST_F(EzdxfFiles, AStepDielinePopsUpInEveryUnit) {
  const CardImport svg = import_card(POPCUT_SOURCE_DIR "/examples/drawn/step.svg");
  ASSERT_TRUE(svg.card.model);
  const Pattern want = make_pattern(*svg.card.model, "svg");
  for (const char* name : {"step-mm.dxf", "step-in.dxf", "step-unitless.dxf"}) {
    const CardImport got = import_card(file(name));
    ASSERT_TRUE(got.card.model) << name << ":\n" << describe_conflicts(got.card);
    const Pattern p = make_pattern(*got.card.model, name);
    EXPECT_EQ(p.lines.size(), want.lines.size()) << name;
    EXPECT_EQ(p.faces.size(), want.faces.size()) << name;
    EXPECT_NEAR(p.sheet.max.x_mm - p.sheet.min.x_mm, 100, 1e-6) << name;
    EXPECT_NEAR(p.sheet.max.v_mm - p.sheet.min.v_mm, 120, 1e-6) << name;
    EXPECT_NEAR(got.card.centre_fold_v_mm, 60, 1e-6) << name;
  }
  const LineDrawing unitless = load_drawing(file("step-unitless.dxf"));
  ASSERT_FALSE(unitless.notes.empty());
  EXPECT_NE(unitless.notes.front().find("$INSUNITS is 0"), std::string::npos) << unitless.notes.front();
  DrawingOptions inches;
  inches.unit_mm = 25.4;
  const LineDrawing big = load_drawing(file("step-unitless.dxf"), inches);
  EXPECT_NEAR(big.lines[0].points[2].x_mm, 2540, 1e-6);
}

TEST_F(EzdxfFiles, BlocksThatInsertThemselvesAreNamed) {
  const Error e = error_of([&] { load_drawing(file("cyclic.dxf")); });
  EXPECT_EQ(e.code(), ErrorCode::invalid_input);
  EXPECT_NE(std::string(e.what()).find("block \"A\" inserts itself (A → B → A)"), std::string::npos) << e.what();
}

TEST_F(EzdxfFiles, PopcutsOwnDxfAuditsCleanInEzdxfAndReadsBack) {
  const Pattern p = make_pattern(load_model(POPCUT_SOURCE_DIR "/examples/faces/porch.json"), "porch");
  const std::string out = file("porch.dxf");
  {
    std::ofstream o(out);
    write_pattern_dxf(o, p);
  }
  const std::string cmd =
      "/usr/bin/python3 " POPCUT_SOURCE_DIR "/tests/core/io/ezdxf_cases.py --check " + out + " >" + file("porch.json");
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const nlohmann::json j = nlohmann::json::parse(read_text_file(file("porch.json")));
  EXPECT_TRUE(j["errors"].empty()) << j.dump();
  EXPECT_EQ(j["units"], 4);
  std::map<LineKind, int> kinds;
  for (const Segment& s : p.lines) ++kinds[s.kind];
  EXPECT_EQ(j["layers"]["CUT"]["LINE"], kinds[LineKind::cut]) << j.dump();
  EXPECT_EQ(j["layers"]["MOUNTAIN"]["LINE"], kinds[LineKind::mountain]) << j.dump();
  EXPECT_EQ(j["layers"]["VALLEY"]["LINE"], kinds[LineKind::valley]) << j.dump();
  EXPECT_EQ(j["layers"]["OUTLINE"]["LWPOLYLINE"], 1);
  EXPECT_EQ(j["linetypes"]["VALLEY"], "DASHED");
  const LineDrawing back = load_drawing(out);
  EXPECT_EQ(back.lines.size(), p.lines.size() + 1);
  EXPECT_EQ(back.lines.front().kind, DrawnKind::outline);
}

// A DXF entities section holding `entities` (group pairs, one per line).
std::string dxf_doc(const std::string& entities, const std::string& header = "") {
  return "0\nSECTION\n2\nHEADER\n" + header + "0\nENDSEC\n0\nSECTION\n2\nENTITIES\n" + entities + "0\nENDSEC\n0\nEOF\n";
}
const std::string kLine = "0\nLINE\n8\nCUT\n10\n0\n20\n0\n11\n10\n21\n0\n";

TEST(DxfDrawing, BadInputNamesTheLine) {
  EXPECT_EQ(read_dxf_drawing(dxf_doc(kLine), "ok.dxf").lines.size(), 1U);
  const auto msg = [](const std::string& text) {
    return std::string(error_of([&] { read_dxf_drawing(text, "bad.dxf"); }).what());
  };
  EXPECT_NE(msg("0\nSECTION\nabc\nx\n").find("line 3: expected a group code"), std::string::npos);
  EXPECT_NE(msg(dxf_doc("0\nLINE\n10\nx\n")).find("line 14: group code 10 expects a number"), std::string::npos);
  EXPECT_NE(msg(dxf_doc("0\nLINE\n70\n1.5\n")).find("expects an integer"), std::string::npos);
  EXPECT_NE(msg("0\nSECTION\n2\nENTITIES\n" + kLine).find("without \"0 EOF\""), std::string::npos);
  EXPECT_NE(msg("0\nSECTION\n2\nENTITIES\n0\nLINE\n10").find("has no value: the file is truncated"), std::string::npos);
  EXPECT_NE(msg("AutoCAD Binary DXF\r\n\x1a").find("binary DXF"), std::string::npos);
  const std::string poly = "0\nLWPOLYLINE\n8\nCUT\n90\n3\n70\n0\n10\n0\n20\n0\n10\n5\n20\n0\n";
  EXPECT_NE(msg(dxf_doc(poly)).find("LWPOLYLINE says 3 vertices (group 90) but has 2"), std::string::npos)
      << msg(dxf_doc(poly));
  const std::string huge = "0\nLWPOLYLINE\n8\nCUT\n90\n2000000000\n70\n0\n10\n0\n20\n0\n";
  EXPECT_NE(msg(dxf_doc(huge)).find("says 2000000000 vertices"), std::string::npos);
  EXPECT_NE(msg(dxf_doc(kLine, "9\n$INSUNITS\n70\n25\n")).find("unknown units 25"), std::string::npos);
  EXPECT_NE(msg(dxf_doc("0\nLINE\n8\nCUT\n10\n1\n20\n1\n11\n1\n21\n1\n"))
                .find("line 11, LINE on layer \"CUT\": a zero-length"),
            std::string::npos);
  EXPECT_NE(msg(dxf_doc("0\nLINE\n10\n1e9\n20\n0\n11\n0\n21\n0\n")).find("beyond the documented"), std::string::npos);
  EXPECT_NE(
      msg(dxf_doc("0\nINSERT\n2\nNOPE\n10\n0\n20\n0\n")).find("inserts block \"NOPE\", which the file does not define"),
      std::string::npos);
  EXPECT_NE(msg(dxf_doc("0\nTEXT\n1\nhello\n")).find("no lines"), std::string::npos);
  EXPECT_NE(msg(dxf_doc("0\nCIRCLE\n10\n0\n20\n0\n40\n5\n210\n1\n220\n0\n230\n0\n")).find("out of the sheet's plane"),
            std::string::npos);
  const std::string spline = "0\nSPLINE\n71\n3\n72\n3\n73\n2\n74\n0\n40\n0\n40\n1\n40\n2\n10\n0\n20\n0\n10\n1\n20\n1\n";
  EXPECT_NE(msg(dxf_doc(spline)).find("a degree 3 spline needs at least 4"), std::string::npos) << msg(dxf_doc(spline));
  const std::string fit = "0\nSPLINE\n71\n3\n72\n0\n73\n0\n74\n2\n11\n0\n21\n0\n11\n5\n21\n5\n";
  EXPECT_NE(msg(dxf_doc(fit)).find("fit points only"), std::string::npos) << msg(dxf_doc(fit));
  EXPECT_EQ(error_of([&] { read_dxf_drawing(dxf_doc(huge), "x"); }).code(), ErrorCode::invalid_input);
  // Counts given twice (the library would allocate from the second), values longer than the
  // library's line buffer, inserts and blocks without names.
  const std::string twice = "0\nLWPOLYLINE\n90\n1\n90\n600000000\n10\n0\n20\n0\n";
  EXPECT_NE(msg(dxf_doc(twice)).find("more than once"), std::string::npos) << msg(dxf_doc(twice));
  EXPECT_NE(msg(dxf_doc("0\nLINE\n8\n" + std::string(5000, 'L') + "\n")).find("line 14: a value of 5000 characters"),
            std::string::npos);
  EXPECT_NE(msg(dxf_doc("0\nINSERT\n10\n0\n20\n0\n")).find("line 11: an INSERT without a block name"),
            std::string::npos);
}

TEST(DxfDrawing, NestedArraysOfEmptyBlocksEndAtTheLimit) {
  // 1,000 × 1,000 copies of a block holding 1,000 × 1,000 copies of an empty block: no point is
  // ever drawn, so only the count of visits can stop it.
  const std::string blocks =
      "0\nSECTION\n2\nBLOCKS\n0\nBLOCK\n2\nEMPTY\n10\n0\n20\n0\n0\nENDBLK\n"
      "0\nBLOCK\n2\nGRID\n10\n0\n20\n0\n0\nINSERT\n2\nEMPTY\n10\n0\n20\n0\n70\n1000\n71\n1000\n44\n1\n45\n1\n"
      "0\nENDBLK\n0\nENDSEC\n";
  const std::string text = blocks +
                           "0\nSECTION\n2\nENTITIES\n0\nINSERT\n2\nGRID\n10\n0\n20\n0\n70\n1000\n71\n"
                           "1000\n44\n1\n45\n1\n0\nENDSEC\n0\nEOF\n";
  const Error e = error_of([&] { read_dxf_drawing(text, "nested.dxf"); });
  EXPECT_EQ(e.code(), ErrorCode::limit);
  EXPECT_NE(std::string(e.what()).find("more than 4000000 entities"), std::string::npos) << e.what();
}

TEST(DxfDrawing, ArcsSweepCounterClockwiseModuloAFullTurn) {
  // 30° to 400° is 10°, as CAD programs draw it; a huge angle neither hangs nor sweeps wrong.
  const LineDrawing d = read_dxf_drawing(dxf_doc("0\nARC\n8\nCUT\n10\n0\n20\n0\n40\n10\n50\n30\n51\n400\n"
                                                 "0\nARC\n8\nCUT\n10\n0\n20\n0\n40\n10\n50\n1e20\n51\n0\n"),
                                         "arcs.dxf");
  ASSERT_EQ(d.lines.size(), 2U);
  const Point2 end = d.lines[0].points.back();
  EXPECT_NEAR(std::atan2(end.v_mm, end.x_mm) * 180 / std::numbers::pi, 40, 1e-9);
  EXPECT_NEAR(std::atan2(d.lines[0].points[0].v_mm, d.lines[0].points[0].x_mm) * 180 / std::numbers::pi, 30, 1e-9);
  for (const Point2& p : d.lines[1].points) EXPECT_NEAR(std::hypot(p.x_mm, p.v_mm), 10, 1e-6);
  // US survey feet: 1200/3937 m.
  const LineDrawing survey = read_dxf_drawing(dxf_doc(kLine, "9\n$INSUNITS\n70\n21\n"), "survey.dxf");
  EXPECT_NEAR(survey.lines[0].points[1].x_mm, 10 * 1200000.0 / 3937, 1e-9);
}

TEST(DxfDrawing, MoreSegmentsThanTheLimitAreRefusedBeforeReading) {
  std::string entities;
  const std::size_t n = kMaxDrawingSegments / 2 + 1;
  entities.reserve(n * 48);
  for (std::size_t i = 0; i < n; ++i)
    entities += "0\nLINE\n10\n0\n20\n" + std::to_string(i % 1000) + "\n11\n1\n21\n0\n";
  const Error e = error_of([&] { read_dxf_drawing(dxf_doc(entities), "many.dxf"); });
  EXPECT_EQ(e.code(), ErrorCode::limit);
  // The scanner's wording ("points"), not the flattening's ("segments"): refused before dxflib.
  EXPECT_NE(std::string(e.what()).find("more than 2000000 points, the documented limit"), std::string::npos)
      << e.what();
}

TEST(DxfCurves, ARationalQuarterCircleIsExactAndWithinTolerance) {
  const double w = std::sqrt(0.5), tol = 0.01;
  const auto pts = dxf::spline_points(2, {0, 0, 0, 1, 1, 1}, {{10, 0}, {10, 10}, {0, 10}}, {1, w, 1}, tol);
  ASSERT_GT(pts.size(), 4U);
  for (const Point2& p : pts) EXPECT_NEAR(std::hypot(p.x_mm, p.v_mm), 10, 1e-9);
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const Point2 mid{(pts[i].x_mm + pts[i + 1].x_mm) / 2, (pts[i].v_mm + pts[i + 1].v_mm) / 2};
    EXPECT_LE(10 - std::hypot(mid.x_mm, mid.v_mm), tol * 1.01);
  }
  EXPECT_NEAR(pts.back().x_mm, 0, 1e-12);
  EXPECT_NEAR(pts.back().v_mm, 10, 1e-12);
  // Bulge 1 is a half circle, counter-clockwise: from (0, 0) to (10, 0) it passes below.
  const auto half = dxf::bulge_points({0, 0}, {10, 0}, 1, tol);
  for (const Point2& p : half) EXPECT_NEAR(std::hypot(p.x_mm - 5, p.v_mm), 5, 1e-9);
  EXPECT_LT(half[half.size() / 2].v_mm, -4.9);
}

}  // namespace
}  // namespace popcut
