// Round trips: popcut's own pattern SVG, FOLD and DXF of examples and random models imports back to the same card.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <sstream>

#include "popcut/error.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/model_io.h"
#include "popcut/io/pattern_io.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/text.h"
#include "random_models.h"

namespace popcut {
namespace {

// Lines of one kind meeting end to end within 1e-4 mm of one straight line become one: the SVG
// keeps 4 decimals, so a crossing at 70/3 mm comes back as a corner a few nanometres off.
std::vector<Segment> merged(std::vector<Segment> lines) {
  const auto near = [](Point2 p, Point2 q) { return std::hypot(p.x_mm - q.x_mm, p.v_mm - q.v_mm) < 1e-6; };
  const auto off_line = [](Point2 p, Point2 a, Point2 b) {
    const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm;
    return std::abs((p.x_mm - a.x_mm) * dv - (p.v_mm - a.v_mm) * dx) / std::hypot(dx, dv);
  };
  for (bool again = true; again;) {
    again = false;
    for (std::size_t i = 0; i < lines.size() && !again; ++i)
      for (std::size_t j = i + 1; j < lines.size() && !again; ++j) {
        Segment a = lines[i], b = lines[j];
        if (a.kind != b.kind) continue;
        if (near(a.a, b.a) || near(a.a, b.b)) std::swap(a.a, a.b);
        if (near(a.b, b.b)) std::swap(b.a, b.b);
        if (!near(a.b, b.a) || off_line(a.b, a.a, b.b) > 1e-4) continue;
        lines[i] = {a.kind, a.a, b.b};
        lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(j));
        again = true;
      }
  }
  return lines;
}

// Same lines (maximal segments, either direction) within the 1e-4 mm the SVG writer keeps.
std::string same_lines(const Pattern& a, Pattern b) {
  b.lines = merged(b.lines);
  const auto key = [](const Pattern& p) {
    std::vector<std::array<double, 5>> out;
    for (const Segment& s : p.lines) {
      Point2 u{s.a.x_mm - p.sheet.min.x_mm, s.a.v_mm - p.sheet.min.v_mm},
          w{s.b.x_mm - p.sheet.min.x_mm, s.b.v_mm - p.sheet.min.v_mm};
      if (std::pair(w.x_mm, w.v_mm) < std::pair(u.x_mm, u.v_mm)) std::swap(u, w);
      out.push_back({static_cast<double>(s.kind), std::round(u.x_mm * 1e3), std::round(u.v_mm * 1e3),
                     std::round(w.x_mm * 1e3), std::round(w.v_mm * 1e3)});
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  const auto ka = key(a), kb = key(b);
  if (ka.size() != kb.size()) return std::to_string(ka.size()) + " lines against " + std::to_string(kb.size());
  for (std::size_t i = 0; i < ka.size(); ++i)
    if (ka[i] != kb[i])
      return "line " + std::to_string(i) + " differs: (" + std::to_string(ka[i][1] / 1e3) + ", " +
             std::to_string(ka[i][2] / 1e3) + ") against (" + std::to_string(kb[i][1] / 1e3) + ", " +
             std::to_string(kb[i][2] / 1e3) + ")";
  return "";
}

// Each original face's plane, looked up at its label in the imported card.
std::string same_planes(const Pattern& a, const Pattern& b) {
  double area_a = 0, area_b = 0;
  for (const PatternFace& f : a.faces) area_a += signed_area_mm2(f.outer);
  for (const PatternFace& f : b.faces) area_b += signed_area_mm2(f.outer);
  std::map<std::pair<int, long long>, double> planes_a, planes_b;
  const auto add = [](std::map<std::pair<int, long long>, double>& m, const Pattern& p) {
    for (const PatternFace& f : p.faces) {
      double area = signed_area_mm2(f.outer);
      for (const Ring& h : f.holes) area += signed_area_mm2(h);
      m[{static_cast<int>(f.kind), std::llround(f.t_mm * 1e3)}] += area;
    }
  };
  add(planes_a, a);
  add(planes_b, b);
  if (planes_a.size() != planes_b.size())
    return std::to_string(planes_a.size()) + " planes against " + std::to_string(planes_b.size());
  for (const auto& [plane, area] : planes_a) {
    const auto it = planes_b.find(plane);
    if (it == planes_b.end())
      return "plane t = " + format_decimal(static_cast<double>(plane.second) / 1e3, 3) + " is missing";
    if (std::abs(it->second - area) > 1e-2 * std::max(1.0, area))
      return "plane t = " + format_decimal(static_cast<double>(plane.second) / 1e3, 3) + " differs in area";
  }
  return "";
}

struct Imported {
  InferredCard card;
  Pattern pattern;
};

std::string fold_text(const Pattern& p) {
  std::ostringstream o;
  write_pattern_fold(o, p);
  return o.str();
}

enum class Via { svg, fold, dxf };
const char* name(Via via) { return via == Via::svg ? " (SVG)" : via == Via::fold ? " (FOLD)" : " (DXF)"; }

// Through popcut's SVG, FOLD or DXF.
Imported import_svg(const Pattern& p, Via via = Via::svg) {
  std::ostringstream dxf;
  if (via == Via::dxf) write_pattern_dxf(dxf, p);
  const LineDrawing d = via == Via::fold  ? read_fold_drawing(fold_text(p), "round-trip.fold")
                        : via == Via::dxf ? read_dxf_drawing(dxf.str(), "round-trip.dxf")
                                          : read_svg_drawing(to_pattern_svg(p), "round-trip.svg");
  const SheetMap map = build_sheet_map(d);
  Imported out{infer_card(d, map), {}};
  if (out.card.model) out.pattern = make_pattern(*out.card.model, "imported");
  return out;
}

TEST(CardFromSheet, EveryExampleImportsBackToItsCard) {
  for (const char* path : {"examples/faces/openings.json", "examples/faces/pavilion.json", "examples/faces/porch.json",
                           "examples/voxel/box.json", "examples/voxel/castle.json", "examples/voxel/pyramid.json",
                           "examples/voxel/townhouse.json"}) {
    const Pattern p = make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/" + path), path);
    for (const Via via : {Via::svg, Via::fold, Via::dxf}) {
      const Imported got = import_svg(p, via);
      ASSERT_TRUE(got.card.model) << path << name(via) << ":\n" << describe_conflicts(got.card);
      EXPECT_EQ(same_lines(p, got.pattern), "") << path << name(via);
      EXPECT_EQ(same_planes(p, got.pattern), "") << path << name(via);
      EXPECT_NEAR(got.card.centre_fold_v_mm, -p.sheet.min.v_mm, 1e-4) << path;
    }
  }
}

TEST(CardFromSheet, RandomFaceModelsImportBackToTheirCards) {
  std::mt19937_64 rng(20261202);
  int imported = 0, free_pieces = 0;
  for (int i = 0; i < 600; ++i) {
    testing::RandomFaceSpec spec;
    spec.edits = 2 + static_cast<int>(rng() % 8);
    const FaceModel m = testing::random_face_model(rng, spec);
    const Pattern p = make_pattern(m);
    const Imported got = import_svg(p, static_cast<Via>(i % 3));
    if (!check_popup(p).loose_pieces.empty()) {
      // Edits that cut a piece free make a model popcut refuses to cut; the import must say so.
      ASSERT_FALSE(got.card.model) << "model " << i;
      const std::string why = describe_conflicts(got.card);
      ASSERT_NE(why.find("piece"), std::string::npos) << "model " << i << ":\n" << why << to_pattern_svg(p);
      ++free_pieces;
      continue;
    }
    ASSERT_TRUE(got.card.model) << "model " << i << ":\n" << describe_conflicts(got.card) << "\n" << to_pattern_svg(p);
    ASSERT_EQ(same_lines(p, got.pattern), "") << "model " << i;
    ASSERT_EQ(same_planes(p, got.pattern), "") << "model " << i;
    ++imported;
  }
  EXPECT_GE(imported, 15) << free_pieces << " had pieces cut free";
}

TEST(CardFromSheet, RandomVoxelModelsImportBackToTheirCards) {
  std::mt19937_64 rng(7);
  int imported = 0;
  for (int i = 0; i < 150; ++i) {
    testing::RandomModelSpec spec;
    const VoxelModel m = testing::random_model(rng, spec);
    const Pattern p = make_pattern(m);
    const Imported got = import_svg(p, static_cast<Via>(i % 3));
    if (!got.card.model) {
      ASSERT_NE(describe_conflicts(got.card).find("piece"), std::string::npos) << "model " << i << ":\n"
                                                                               << describe_conflicts(got.card);
      continue;
    }
    ASSERT_EQ(same_lines(p, got.pattern), "") << "model " << i;
    ASSERT_EQ(same_planes(p, got.pattern), "") << "model " << i;
    ++imported;
  }
  EXPECT_GT(imported, 100);
}

// A drawing changed by one line (a fold drawn as a cut, an x-parallel cut drawn as a fold) is
// either refused or, when a card still comes out, that card's own pattern has exactly the drawn
// lines: the import never hands on a card that cuts or folds other than the drawing says.
TEST(CardFromSheet, ADrawingWithOneLineChangedIsRefusedOrFoldsAsDrawn) {
  std::mt19937_64 rng(20261207);
  int line_conflicts = 0, imported = 0;
  for (int i = 0; i < 300; ++i) {
    testing::RandomFaceSpec spec;
    spec.edits = 2 + static_cast<int>(rng() % 8);
    Pattern p = make_pattern(testing::random_face_model(rng, spec));
    std::vector<std::size_t> along_x;
    for (std::size_t k = 0; k < p.lines.size(); ++k)
      if (p.lines[k].a.v_mm == p.lines[k].b.v_mm && p.lines[k].a.v_mm != 0) along_x.push_back(k);
    if (along_x.empty()) continue;
    Segment& changed = p.lines[along_x[rng() % along_x.size()]];
    changed.kind = changed.kind == LineKind::cut ? (rng() % 2 ? LineKind::valley : LineKind::mountain) : LineKind::cut;
    const Imported got = import_svg(p, static_cast<Via>(i % 3));
    if (!got.card.model) {
      const std::string why = describe_conflicts(got.card);
      line_conflicts += why.find("line") != std::string::npos || why.find("fold") != std::string::npos;
      continue;
    }
    ASSERT_EQ(same_lines(p, got.pattern), "") << "model " << i << ": a card came out that differs from its drawing";
    ++imported;
  }
  EXPECT_GE(line_conflicts, 50) << "changed lines named as line or fold conflicts (" << imported << " imported)";
}

}  // namespace
}  // namespace popcut
