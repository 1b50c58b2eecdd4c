// Text items in a face design: walls of letters that pop up whatever the word, letters cut through walls, one undo per
// text, and texts the design refuses without changing.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "error_of.h"
#include "popcut/design/face_design.h"
#include "popcut/io/design_json.h"

namespace popcut {
namespace {

using testing::error_of;

DesignItem text(DesignTool tool, double t, const std::string& s, double x, double z, double size = 12,
                bool frame = true) {
  DesignItem item{tool, t, {{x, z}}, true, false};
  item.text = TextSpec{s, "DejaVu Sans", size, frame};
  return item;
}

std::string problems(const PopupReport& r) {
  std::string out;
  for (const auto& p : r.not_standing) out += "face " + std::to_string(p.face) + " does not stand\n";
  for (const auto& p : r.loose_pieces)
    out +=
        "a loose piece at x " + std::to_string(p.bounds.min.x_mm) + ", v " + std::to_string(p.bounds.min.v_mm) + "\n";
  return out;
}

// Random words, sizes, fonts and depths, with and without a wall behind: a framed wall of letters
// always pops up, its letters held by the frame whatever their shapes.
TEST(FaceDesignText, AFramedWallOfLettersPopsUpForAnyWord) {
  std::mt19937 rng(7);
  const std::string letters = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789&?@%";
  for (int round = 0; round < 24; ++round) {
    std::string word;
    const int n = std::uniform_int_distribution<int>(1, 8)(rng);
    for (int i = 0; i < n; ++i) word += letters[std::uniform_int_distribution<std::size_t>(0, letters.size() - 1)(rng)];
    const double size = std::uniform_real_distribution<double>(4, 14)(rng);
    const double t = std::uniform_real_distribution<double>(20, 50)(rng);
    FaceDesign d(240, 80, 80);
    if (round % 2 == 1) d.add({DesignTool::wall, 10, {{0, 0}, {240, 0}, {240, 60}, {0, 60}}, true, false});
    DesignItem item = text(DesignTool::wall, t, word, 5, 0, size);
    if (round % 3 == 2) item.text->font = "DejaVu Serif";
    d.add(item);
    EXPECT_TRUE(d.report().pops_up()) << "\"" << word << "\" at " << size << " mm, y = " << t << " mm:\n"
                                      << problems(d.report());
  }
}

TEST(FaceDesignText, CapitalsStandFreeOnTheirBarWithTheirOwnTops) {
  FaceDesign d(120, 80, 80);
  d.add(text(DesignTool::wall, 30, "ANNA", 20, 0, 15, false));
  EXPECT_TRUE(d.report().pops_up()) << problems(d.report());
  FaceDesign bang(120, 80, 80);
  bang.add(text(DesignTool::wall, 30, "HI!", 20, 0, 15, false));
  EXPECT_FALSE(bang.report().pops_up()) << "the bar of a free \"!\" stands on nothing";
  EXPECT_FALSE(bang.report().not_standing.empty());
}

TEST(FaceDesignText, LettersCutThroughAWallLoseTheirCountersAndTheCardStillPopsUp) {
  FaceDesign d(140, 80, 80);
  d.add({DesignTool::wall, 50, {{10, 0}, {130, 0}, {130, 50}, {10, 50}}, true, false});
  const std::size_t before = d.model().edits().size();
  d.add(text(DesignTool::opening, 50, "Bob\nand Ada", 30, 15, 8));
  EXPECT_TRUE(d.report().pops_up()) << problems(d.report());
  const auto& edits = d.model().edits();
  const auto holes = std::count_if(edits.begin() + static_cast<std::ptrdiff_t>(before), edits.end(),
                                   [](const FaceEdit& e) { return e.op == EditOp::add_vhole; });
  EXPECT_EQ(holes, 9) << "one hole per letter, none for the counters of B, o, b, a, d, A, d, a";
  EXPECT_EQ(edits.size() - before, 9u) << "and nothing else";
}

TEST(FaceDesignText, ATextIsOneItemThatOneUndoTakesAway) {
  FaceDesign d(120, 80, 80);
  d.add(text(DesignTool::wall, 30, "Hello", 10, 0));
  ASSERT_EQ(d.items().size(), 1u);
  EXPECT_GT(d.model().edits().size(), 5u);
  ASSERT_TRUE(d.undo());
  EXPECT_TRUE(d.model().edits().empty());
  ASSERT_TRUE(d.redo());
  EXPECT_EQ(d.items().size(), 1u);
  EXPECT_TRUE(d.report().pops_up());
}

TEST(FaceDesignText, RefusedTextsLeaveTheDesignAsItWas) {
  FaceDesign d(120, 80, 80);
  d.add({DesignTool::wall, 30, {{10, 0}, {110, 0}, {110, 40}, {10, 40}}, true, false});
  const std::size_t edits = d.model().edits().size();
  DesignItem mirrored = text(DesignTool::wall, 40, "Jo", 10, 0);
  mirrored.mirror = true;
  EXPECT_NE(error_of([&] { d.add(mirrored, "item"); }).message().find("read backwards"), std::string::npos);
  EXPECT_EQ(error_of([&] { d.add(text(DesignTool::roof, 20, "Jo", 10, 5), "item"); }).location(), "item.tool");
  EXPECT_EQ(error_of([&] { d.add(text(DesignTool::wall, 40, "Jo\nAl", 10, 0), "item"); }).location(),
            "item.text.string");
  Error off = error_of([&] { d.add(text(DesignTool::wall, 40, "A long name here", 80, 0, 20), "item"); });
  EXPECT_NE(off.message().find("sheet"), std::string::npos) << "past the sheet's edge: " << off.message();
  DesignItem font = text(DesignTool::wall, 40, "Jo", 10, 0);
  font.text->font = "Missing Sans";
  EXPECT_EQ(error_of([&] { d.add(font, "item"); }).location(), "item.text.font");
  DesignItem huge = text(DesignTool::wall, 40, std::string(10 * 1024 * 1024, 'x'), 10, 0);
  EXPECT_EQ(error_of([&] { d.add(huge, "item"); }).code(), ErrorCode::limit);
  EXPECT_EQ(d.items().size(), 1u);
  EXPECT_EQ(d.model().edits().size(), edits) << "every refused text left the model as it was";
}

TEST(FaceDesignText, ATextItemRoundTripsThroughTheDesignFile) {
  FaceDesign d(120, 80, 80);
  d.add(text(DesignTool::wall, 30, "Anna \"A\"", 10, 0, 9.5, false));
  d.add({DesignTool::wall, 10, {{5, 0}, {115, 0}, {115, 60}, {5, 60}}, true, false});
  d.add(text(DesignTool::opening, 10, "Happy\nBirthday", 30, 30, 6));
  const FaceDesign back = parse_design(to_design_json(d, "t"), "t.json");
  ASSERT_EQ(back.items().size(), d.items().size());
  for (std::size_t i = 0; i < d.items().size(); ++i) EXPECT_EQ(back.items()[i].item, d.items()[i].item) << i;
  EXPECT_EQ(back.model().edits(), d.model().edits());
  const std::string bad = R"({"format": "popcut.design.v1", "sheet": {"width": 100, "back": 80, "floor": 80},
    "items": [{"tool": "wall", "t": 30, "text": {"string": "Jo"}, "outline": [[0, 0], [1, 0], [1, 1]]}]})";
  EXPECT_EQ(error_of([&] { parse_design(bad, "bad.json"); }).location(), "items[0].outline");
  const std::string no_at = R"({"format": "popcut.design.v1", "sheet": {"width": 100, "back": 80, "floor": 80},
    "items": [{"tool": "wall", "t": 30, "text": {"string": "Jo", "frame": 1}, "at": [5, 0]}]})";
  EXPECT_EQ(error_of([&] { parse_design(no_at, "bad.json"); }).location(), "items[0].text.frame");
}

// The upper dots of ":" and ";" stand on nothing, below the tallest letter and between letters
// (touching no side of the frame): each hangs from the frame by a strip and stays paper of the
// wall, where cut away with the space around it it would be an opening's paper.
TEST(FaceDesignText, AFrameHoldsTheDotsOfItsLettersByStrips) {
  for (const char* word : {"H:H", "H;H"}) {
    FaceDesign d(120, 80, 80);
    d.add(text(DesignTool::wall, 30, word, 10, 0, 20));
    EXPECT_TRUE(d.report().pops_up()) << word << ": " << problems(d.report());
    const TextSetting set = set_text({word, "DejaVu Sans", 20}, kTextToleranceMm, "t");
    int marks = 0;
    for (const TextShape& s : set.shapes) {
      const Rect b = bounds(s.outer);
      if (b.min.v_mm < 2) continue;  // stands on the baseline
      ++marks;
      // The mark's own paper (its middle row), where the wall is at depth 30: in the pattern,
      // v = z - 30, with z = 10 mm of letters lifted by the descent.
      const Point2 p = interior_point(s.outer, s.holes);
      const Point2 at{10 + p.x_mm, p.v_mm + set.descent_mm - 30};
      bool wall = false;
      for (const OAFace& f : d.model().faces()) {
        if (f.kind != FaceKind::vertical || f.t_mm != 30 || !inside_ring(at, f.polygon.outer)) continue;
        wall = std::none_of(f.polygon.holes.begin(), f.polygon.holes.end(),
                            [&](const Ring& h) { return inside_ring(at, h); });
      }
      EXPECT_TRUE(wall) << word << ": the mark at x " << at.x_mm << " is the wall's paper";
    }
    EXPECT_EQ(marks, 1) << word;
  }
}

}  // namespace
}  // namespace popcut
