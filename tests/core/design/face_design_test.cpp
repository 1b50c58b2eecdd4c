// Face-mode design sessions: items drawn back to front, automatic tops, undo/redo by item, failed edits that change
// nothing.
#include "popcut/design/face_design.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include "error_of.h"
#include "popcut/io/design_json.h"
#include "popcut/io/files.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/face_pattern.h"

namespace popcut {
namespace {

using testing::error_of;

// A pattern independent of the order its faces come out in: lines (sorted by make_pattern) and
// each face's plane and area.
struct Summary {
  std::vector<Segment> lines;
  std::vector<std::tuple<int, double, long long>> faces;
  friend bool operator==(const Summary&, const Summary&) = default;
};

Summary summary(const Pattern& p) {
  Summary s{p.lines, {}};
  for (const PatternFace& f : p.faces)
    s.faces.emplace_back(static_cast<int>(f.kind), f.t_mm, std::llround(face_area_mm2(f) * 1e6));
  std::sort(s.faces.begin(), s.faces.end());
  return s;
}

DesignItem wall(double t, double x0, double x1, double h, bool top = true) {
  return {DesignTool::wall, t, {{x0, 0}, {x1, 0}, {x1, h}, {x0, h}}, top, false};
}

DesignItem opening(double t, double x0, double x1, double z0, double z1) {
  return {DesignTool::opening, t, {{x0, z0}, {x1, z0}, {x1, z1}, {x0, z1}}, true, false};
}

TEST(FaceDesign, TwoWallsWithTheirTopsMakeThePorchExample) {
  const FaceModel porch =
      parse_face_model(read_text_file(POPCUT_SOURCE_DIR "/examples/faces/porch.json"), "porch.json");
  FaceDesign d(100, 80, 80);
  d.add(wall(30, 15, 85, 40));
  d.add(wall(42, 35, 65, 20));
  EXPECT_EQ(summary(d.pattern()), summary(make_pattern(porch)));
  EXPECT_TRUE(d.report().pops_up());
  EXPECT_EQ(d.model().edits().size(), 4u) << "two walls and a top each";
  EXPECT_EQ(d.model().edits()[1].op, EditOp::add_hface);
  EXPECT_EQ(d.model().edits()[1].t_mm, 40) << "the back wall's top at its height";
}

TEST(FaceDesign, AWallAddedBehindRedrawsTheWallsInFrontAndTheirTopsStopAtIt) {
  FaceDesign front_first(100, 80, 80), back_first(100, 80, 80);
  front_first.add(wall(42, 35, 65, 20));
  EXPECT_EQ(front_first.model().edits()[1].outline[0][1], 0) << "alone, the top runs to the back board";
  front_first.add(wall(30, 15, 85, 40));
  EXPECT_EQ(front_first.last_edit_work(), 4u) << "the front wall and its top were drawn again";
  back_first.add(wall(30, 15, 85, 40));
  back_first.add(wall(42, 35, 65, 20));
  EXPECT_EQ(back_first.last_edit_work(), 2u) << "a wall in front is laid over what is there";
  EXPECT_EQ(summary(front_first.pattern()), summary(back_first.pattern()));
  EXPECT_EQ(front_first.items().front().item, wall(30, 15, 85, 40)) << "items are kept in drawing order";
}

TEST(FaceDesign, TopsStopWhereTheWallBehindStopsRising) {
  FaceDesign d(100, 80, 80);
  d.add(wall(20, 10, 50, 30));  // covers x 10..50 up to z 30
  d.add(wall(40, 0, 90, 25));   // its top at 25: stops at y 20 over 10..50, at the back board elsewhere
  std::vector<FaceEdit> tops;
  for (const FaceEdit& e : d.model().edits()) {
    if (e.op == EditOp::add_hface && e.t_mm == 25) tops.push_back(e);
  }
  ASSERT_EQ(tops.size(), 3u);
  std::sort(tops.begin(), tops.end(),
            [](const FaceEdit& a, const FaceEdit& b) { return a.outline[0][0] < b.outline[0][0]; });
  EXPECT_EQ(tops[0].outline[0], (std::array<double, 2>{0, 0}));
  EXPECT_EQ(tops[1].outline[0], (std::array<double, 2>{10, 20}));
  EXPECT_EQ(tops[1].outline[1], (std::array<double, 2>{50, 20}));
  EXPECT_EQ(tops[2].outline[0], (std::array<double, 2>{50, 0}));
  EXPECT_TRUE(d.report().pops_up());
}

TEST(FaceDesign, SlantedTopEdgesAndStretchesWithNothingBehindGetNoTop) {
  FaceModel blank(100, 30, 80);  // a back board only 30 high
  // A gable: two slanted top edges and one flat stretch at z = 20 between x 40 and 60.
  const std::vector<std::array<double, 2>> gable = {{20, 0}, {80, 0}, {80, 10}, {60, 20}, {40, 20}, {20, 10}};
  const std::vector<FaceEdit> tops = wall_tops(blank, 10, gable);
  ASSERT_EQ(tops.size(), 1u) << "the flat edge only";
  EXPECT_EQ(tops[0].t_mm, 20);
  EXPECT_EQ(tops[0].outline, (std::vector<std::array<double, 2>>{{40, 0}, {60, 0}, {60, 10}, {40, 10}}));
  // Clockwise input is read as the same wall.
  EXPECT_EQ(wall_tops(blank, 10, std::vector<std::array<double, 2>>(gable.rbegin(), gable.rend())), tops);
  // A wall taller than the back board: above z = 30 nothing stands behind, so no top.
  EXPECT_TRUE(wall_tops(blank, 10, {{20, 0}, {80, 0}, {80, 35}, {20, 35}}).empty());
}

TEST(FaceDesign, AWallWithItsTopTurnedOffGetsNone) {
  FaceDesign d(100, 80, 80);
  d.add(wall(30, 15, 85, 40, false));
  EXPECT_EQ(d.model().edits().size(), 1u);
  EXPECT_FALSE(d.report().pops_up()) << "a wall without a top is held from the floor only";
}

TEST(FaceDesign, UndoAndRedoTenStepsReturnEachState) {
  FaceDesign d(120, 80, 80);
  std::vector<Summary> states = {summary(d.pattern())};
  for (int i = 0; i < 10; ++i) {
    const double x0 = 5 + 11 * i;
    if (i % 3 == 2)
      d.add(opening(10 + i, x0 - 9, x0 - 5, 2, 6));  // in the wall just drawn, at its depth
    else
      d.add(wall(10 + i + (i % 3 == 1 ? 1 : 0), x0 - (i % 3 == 1 ? 11 : 0), x0 + 8, 10 + i));
    states.push_back(summary(d.pattern()));
  }
  for (int i = 10; i-- > 0;) {
    ASSERT_TRUE(d.undo());
    EXPECT_EQ(summary(d.pattern()), states[static_cast<std::size_t>(i)]) << "after undoing to state " << i;
  }
  EXPECT_FALSE(d.undo());
  for (int i = 1; i <= 10; ++i) {
    ASSERT_TRUE(d.redo());
    EXPECT_EQ(summary(d.pattern()), states[static_cast<std::size_t>(i)]) << "after redoing to state " << i;
  }
  EXPECT_FALSE(d.redo());
}

TEST(FaceDesign, AFailedEditLeavesTheDesignAsItWas) {
  FaceDesign d(100, 80, 80);
  d.add(wall(30, 15, 85, 40));
  const Summary before = summary(d.pattern());
  const Error e = error_of([&] { d.add(opening(35, 20, 30, 5, 15), "edit"); });
  EXPECT_NE(std::string(e.what()).find("not inside a VFace at depth y = 35"), std::string::npos) << e.what();
  const Error off = error_of([&] { d.add(wall(10, 90, 120, 20), "edit"); });
  EXPECT_NE(std::string(off.what()).find("leaves the sheet"), std::string::npos) << off.what();
  EXPECT_EQ(summary(d.pattern()), before);
  EXPECT_EQ(d.items().size(), 1u);
  EXPECT_FALSE(d.can_redo());
  ASSERT_TRUE(d.undo()) << "the undo history is the one before the failures";
  EXPECT_EQ(d.model().edits().size(), 0u);
}

TEST(FaceDesign, RedoAfterAFailedEditStillRedoes) {
  FaceDesign d(100, 80, 80);
  d.add(wall(30, 15, 45, 40));
  d.add(wall(42, 20, 40, 20));
  const Summary both = summary(d.pattern());
  ASSERT_TRUE(d.undo()) << "the front wall, taken back from the front";
  // A mirrored window: the first copy is cut, the mirrored one lies in no wall. The model applied
  // an edit on the way to the failure, so its own redo list is gone; the design's is not.
  DesignItem window = opening(30, 20, 28, 25, 35);
  window.mirror = true;
  const Error e = error_of([&] { d.add(window, "edit"); });
  EXPECT_NE(std::string(e.what()).find("not inside a VFace at depth y = 30"), std::string::npos) << e.what();
  ASSERT_TRUE(d.redo()) << "the front wall comes back";
  EXPECT_EQ(summary(d.pattern()), both);
}

TEST(FaceDesign, RemovingAWallThatHoldsAnOpeningIsRefusedAndChangesNothing) {
  FaceDesign d(100, 80, 80);
  d.add(wall(30, 15, 85, 40));
  d.add(opening(30, 40, 60, 10, 20));
  const Summary before = summary(d.pattern());
  const std::uint64_t wall_id = d.items().front().id;
  const Error e = error_of([&] { d.remove(wall_id); });
  EXPECT_NE(std::string(e.what()).find("the opening drawn as item 2"), std::string::npos) << e.what();
  EXPECT_EQ(summary(d.pattern()), before);
  EXPECT_EQ(d.items().size(), 2u);
  ASSERT_TRUE(d.remove(d.items().back().id));
  ASSERT_TRUE(d.remove(wall_id));
  EXPECT_EQ(d.model().edits().size(), 0u);
  ASSERT_TRUE(d.undo());
  ASSERT_TRUE(d.undo());
  EXPECT_EQ(summary(d.pattern()), before) << "undoing the removals puts both back";
}

TEST(FaceDesign, MirrorDrawsTheItemAgainAcrossTheCentreLine) {
  FaceDesign d(100, 80, 80);
  DesignItem w = wall(30, 10, 30, 40);
  w.mirror = true;
  d.add(w);
  FaceDesign both(100, 80, 80);
  both.add(wall(30, 10, 30, 40));
  both.add(wall(30, 70, 90, 40));
  EXPECT_EQ(summary(d.pattern()), summary(both.pattern()));
  DesignItem across = opening(30, 45, 55, 5, 10);
  across.mirror = true;
  d.add(wall(30, 40, 60, 20));
  const Error e = error_of([&] { d.add(across, "edit"); });
  EXPECT_NE(std::string(e.what()).find("one side of the centre line x = 50 mm"), std::string::npos) << e.what();
}

// Any order of adding the same walls, openings and roofs gives the same card as adding them
// back to front: the order is the design's, not the clicks'.
TEST(FaceDesign, TheCardDoesNotDependOnTheOrderItemsAreAddedIn) {
  std::mt19937_64 rng(77);
  int compared = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<DesignItem> items;
    for (int k = 0; k < 6; ++k) {
      const double t = 5.0 * std::uniform_int_distribution<int>(1, 8)(rng);
      const double x0 = 5.0 * std::uniform_int_distribution<int>(0, 14)(rng);
      const double w = 5.0 * std::uniform_int_distribution<int>(2, 6)(rng);
      const double h = 5.0 * std::uniform_int_distribution<int>(2, 9)(rng);
      items.push_back(wall(t, x0, std::min(100.0, x0 + w), h, k % 4 != 3));
      if (k % 2 == 0) items.push_back(opening(t, x0 + 1, std::min(99.0, x0 + w) - 1, 1, h / 2));
    }
    std::vector<DesignItem> order = items;
    std::shuffle(order.begin(), order.end(), rng);
    FaceDesign shuffled(100, 80, 80), sorted(100, 80, 80);
    std::vector<DesignItem> taken;
    for (const DesignItem& it : order) {
      try {
        shuffled.add(it);
        taken.push_back(it);
      } catch (const Error&) {
        // An opening that lands where a nearer wall covers it: refused, as the page shows.
      }
    }
    std::stable_sort(taken.begin(), taken.end(), [](const DesignItem& a, const DesignItem& b) {
      return std::tuple(a.t_mm, a.tool) < std::tuple(b.t_mm, b.tool);
    });
    try {
      for (const DesignItem& it : taken) sorted.add(it);
    } catch (const Error& e) {
      ADD_FAILURE() << "trial " << trial << ": items the shuffled design took fail back to front: " << e.what();
      continue;
    }
    const Summary expected = summary(sorted.pattern());
    EXPECT_EQ(summary(shuffled.pattern()), expected) << "trial " << trial;
    // Every item taken back (some from behind others, so redrawn) and put back again.
    while (shuffled.undo()) {
    }
    EXPECT_EQ(shuffled.model().edits().size(), 0u);
    while (shuffled.redo()) {
    }
    EXPECT_EQ(summary(shuffled.pattern()), expected) << "trial " << trial << ", after undoing and redoing all";
    ++compared;
  }
  EXPECT_EQ(compared, 40);
}

// add_all reads the faces behind once for many walls (as long as nothing drawn since covers their
// x): it must give exactly the edits of drawing the same items one by one, each wall reading
// the faces afresh. Narrow walls on a wide card, mirrored items, openings and roofs.
TEST(FaceDesign, AddingAllAtOnceGivesTheEditsOfAddingOneByOne) {
  std::mt19937_64 rng(2024);
  const auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  int compared = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<DesignItem> items;
    for (int k = 0; k < 14; ++k) {
      const double t = 2.5 * pick(1, 12), x0 = 2.0 * pick(0, 90), w = 2.0 * pick(1, trial % 2 ? 4 : 20);
      const double h = 2.5 * pick(2, 16);
      DesignItem it = wall(t, x0, std::min(199.0, x0 + w), h, pick(0, 5) != 0);
      it.mirror = pick(0, 3) == 0;
      items.push_back(it);
      if (pick(0, 2) == 0 && w > 3) items.push_back(opening(t, x0 + 1, std::min(198.0, x0 + w) - 1, 1, h / 2));
      if (pick(0, 4) == 0) {
        const double y0 = 2.5 * pick(0, 4);
        items.push_back({DesignTool::roof, h, {{x0, y0}, {x0 + w, y0}, {x0 + w, t}, {x0, t}}, true, false});
      }
    }
    std::stable_sort(items.begin(), items.end(), [](const DesignItem& a, const DesignItem& b) {
      return std::tuple(a.t_mm, a.tool) < std::tuple(b.t_mm, b.tool);
    });
    FaceDesign one_by_one(200, 80, 80), at_once(200, 80, 80);
    std::vector<DesignItem> taken;
    for (const DesignItem& it : items) {
      try {
        one_by_one.add(it);
        taken.push_back(it);
      } catch (const Error&) {
        // refused (an opening a nearer wall covers, a roof off the sheet): left out of both
      }
    }
    std::vector<std::string> where(taken.size(), "item");
    try {
      at_once.add_all(taken, where);
    } catch (const Error& e) {
      ADD_FAILURE() << "trial " << trial << ": " << e.what();
      continue;
    }
    ASSERT_EQ(at_once.model().edits().size(), one_by_one.model().edits().size()) << "trial " << trial;
    for (std::size_t i = 0; i < at_once.model().edits().size(); ++i) {
      const FaceEdit& a = at_once.model().edits()[i];
      const FaceEdit& b = one_by_one.model().edits()[i];
      EXPECT_TRUE(a.op == b.op && a.t_mm == b.t_mm && a.outline == b.outline) << "trial " << trial << ", edit " << i;
    }
    EXPECT_EQ(summary(at_once.pattern()), summary(one_by_one.pattern())) << "trial " << trial;
    EXPECT_EQ(at_once.items().size(), taken.size());
    ++compared;
  }
  EXPECT_EQ(compared, 40);
}

// A round window has no bottom edge for its paper to fold on: the disc drops out of the wall as
// the window is cut. The check lists it as cut out, not as a fault; a piece of wall cut free is
// still one.
TEST(FaceDesign, ARoundWindowsDiscIsCutOutNotAFault) {
  FaceDesign d(100, 80, 80);
  d.add(wall(30, 15, 85, 45));
  DesignItem window{DesignTool::opening, 30, {}, true, true};
  for (int k = 0; k < 36; ++k) {
    const double a = 2 * 3.141592653589793 * k / 36;
    window.outline.push_back(
        {std::round((30 + 5 * std::cos(a)) * 1000) / 1000, std::round((25 + 5 * std::sin(a)) * 1000) / 1000});
  }
  d.add(window);
  EXPECT_TRUE(d.report().pops_up());
  EXPECT_TRUE(d.report().loose_pieces.empty());
  ASSERT_EQ(d.report().cut_out.size(), 2u) << "the window and its mirror";
  for (const LoosePiece& lp : d.report().cut_out) {
    EXPECT_NEAR(lp.area_mm2, 78.1, 0.5) << "a disc of radius 5 mm";
    for (int f : lp.faces) EXPECT_TRUE(d.pattern().faces[static_cast<std::size_t>(f)].opening_paper);
  }
  // A wall standing on nothing and held by nothing is cut free: that is a fault.
  FaceDesign floating(100, 80, 80);
  floating.add({DesignTool::wall, 30, {{20, 10}, {40, 10}, {40, 20}, {20, 20}}, false, false});
  EXPECT_FALSE(floating.report().pops_up());
  EXPECT_EQ(floating.report().loose_pieces.size(), 1u);
  EXPECT_TRUE(floating.report().cut_out.empty());
}

// A square window whose paper should not fold down as a ledge: with "ledge": false it is cut all
// round and drops out as the round one does, and the choice survives the design file and the
// faces file popcutd is sent.
TEST(FaceDesign, AnOpeningWithoutALedgeIsCutAllRoundAndDropsOut) {
  const auto sill_folds = [](const Pattern& p) {
    // The window's sill at z = 20 in the wall at depth 30 is the pattern line v = -10, x 40..60.
    return std::count_if(p.lines.begin(), p.lines.end(), [](const Segment& l) {
      return l.kind != LineKind::cut && l.a.v_mm == -10 && std::min(l.a.x_mm, l.b.x_mm) >= 40 &&
             std::max(l.a.x_mm, l.b.x_mm) <= 60;
    });
  };
  FaceDesign ledge(100, 80, 80), plain(100, 80, 80);
  for (FaceDesign* d : {&ledge, &plain}) d->add(wall(30, 15, 85, 45));
  DesignItem window = opening(30, 40, 60, 20, 35);
  ledge.add(window);
  window.ledge = false;
  plain.add(window);
  EXPECT_EQ(sill_folds(ledge.pattern()), 1) << "the ledge folds down on the sill";
  EXPECT_TRUE(ledge.report().cut_out.empty());
  EXPECT_EQ(sill_folds(plain.pattern()), 0) << "cut all round";
  ASSERT_EQ(plain.report().cut_out.size(), 1u);
  EXPECT_NEAR(plain.report().cut_out[0].area_mm2, 300, 1e-6);
  EXPECT_TRUE(plain.report().pops_up());
  const std::string file = to_design_json(plain);
  EXPECT_NE(file.find(R"("ledge": false)"), std::string::npos) << file;
  EXPECT_EQ(parse_design(file, "d.json").items().back().item, plain.items().back().item);
  const FaceModel sent = parse_face_model(to_face_json(plain.model()), "faces.json");
  EXPECT_EQ(sill_folds(make_pattern(sent)), 0) << "the faces file keeps the edit's drop";
  // Only an opening's paper can drop out.
  DesignItem bad = wall(40, 10, 20, 10);
  bad.ledge = false;
  EXPECT_EQ(error_of([&] { plain.add(bad, "item"); }).location(), "item.ledge");
  EXPECT_EQ(error_of([&] {
              parse_design(R"({"format": "popcut.design.v1", "sheet": {"width": 100, "back": 80, "floor": 80},
                "items": [{"tool": "wall", "t": 5, "outline": [[0, 0], [5, 0], [5, 5]], "ledge": false}]})",
                           "d.json");
            }).location(),
            "items[0].ledge");
}

}  // namespace
}  // namespace popcut
