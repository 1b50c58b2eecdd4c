// webOAcard cards imported into a design: every demo's faces drawn exactly by its items, the draft's round trip, and
// editing on after the import; faces with holes as design items and face-model edits.
#include "popcut/design/oa_design.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "error_of.h"
#include "pattern_compare.h"
#include "popcut/io/design_json.h"
#include "popcut/io/files.h"
#include "popcut/io/model_io.h"
#include "popcut/io/oa_model.h"
#include "popcut/pattern/face_pattern.h"
#include "shared_testdata.h"

namespace popcut {
namespace {

using testing::compare_patterns;
using testing::error_of;

std::vector<std::string> demo_paths() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(testing::shared_testdata("webOAcard/demo/")))
    if (e.path().extension() == ".oa") out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(OaDesign, EveryDemoBecomesItemsThatDrawExactlyTheFacesItsEditorShows) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  const auto paths = demo_paths();
  ASSERT_GE(paths.size(), 10u);
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    const OaCard card = parse_oa_card(read_text_file(path), path);
    const FaceModel derived = face_model_from_oa(card, path);
    const FaceDesign design = design_from_oa(card, path);
    EXPECT_EQ(compare_patterns(design.pattern(), make_pattern(derived, path)), "");
    EXPECT_FALSE(design.items().empty());
    EXPECT_FALSE(design.can_undo()) << "the import is where the history starts";
    for (const auto& p : design.items()) {
      EXPECT_TRUE(p.item.tool == DesignTool::wall || p.item.tool == DesignTool::roof);
      if (p.item.tool == DesignTool::wall) {
        EXPECT_FALSE(p.item.top) << "the card's top faces are items of their own";
      }
      EXPECT_GT(p.item.t_mm, 0) << "the boards are the blank card's";
    }
    // The draft as saved reads back as the same card, item for item.
    const std::string saved = to_design_json(design, "demo");
    const FaceDesign back = parse_design(saved, "draft");
    ASSERT_EQ(back.items().size(), design.items().size());
    for (std::size_t i = 0; i < back.items().size(); ++i) EXPECT_EQ(back.items()[i].item, design.items()[i].item);
    EXPECT_EQ(compare_patterns(back.pattern(), design.pattern()), "");
  }
}

// A face with more corners than a design item may have is refused naming it, before any draft
// exists that could not be read back.
TEST(OaDesign, AFaceTooDetailedForADesignItemIsRefusedByName) {
  std::string ring;
  for (int i = 0; i < 1200; ++i) {
    const double a = 2 * M_PI * i / 1200;
    ring += (i ? ", " : "") + std::string(R"({"X": )") + std::to_string(60 + 20 * std::cos(a)) + R"(, "Y": )" +
            std::to_string(-30 + 20 * std::sin(a)) + "}";
  }
  const std::string text = R"({"settings": {"cardW": 120, "cardH": 100}, "faces": [{"contours": [{"outer": [)" + ring +
                           R"(], "holes": []}], "type": "VFACE", "mode": 0, "t": 40, "contoursType": ""}]})";
  const Error e = error_of([&] { design_from_oa(parse_oa_card(text, "round.oa"), "round.oa"); });
  EXPECT_EQ(e.code(), ErrorCode::limit);
  EXPECT_NE(e.location().find("a wall at t = 40 mm"), std::string::npos) << e.location();
  EXPECT_NE(e.message().find("at most 1000"), std::string::npos) << e.message();
}

TEST(OaDesign, AnImportedCardIsEditedLikeAnyOther) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  const std::string path = testing::shared_testdata("webOAcard/demo/house.oa");
  FaceDesign design = design_from_oa(parse_oa_card(read_text_file(path), path), path);
  ASSERT_TRUE(design.report().pops_up());
  const Pattern before = design.pattern();
  // A wall in front of everything, with its top back to the house: still a card, one more face.
  design.add({DesignTool::wall, 90, {{5, 0}, {25, 0}, {25, 8}, {5, 8}}, true, false});
  EXPECT_NE(compare_patterns(design.pattern(), before), "");
  EXPECT_TRUE(design.report().pops_up());
  // Taking an imported face away leaves what it covered; undo brings it back.
  const std::uint64_t first = design.items().front().id;
  ASSERT_TRUE(design.remove(first));
  ASSERT_TRUE(design.undo());
  ASSERT_TRUE(design.undo());
  EXPECT_EQ(compare_patterns(design.pattern(), before), "");
}

// A wall seen through a window of the wall in front: a face with a hole, drawn over the wall
// behind, shows it in the hole; an opening there would fold a ledge instead.
TEST(OaDesign, AFaceWithAHoleShowsWhatIsBehindThroughIt) {
  FaceDesign d(100, 80, 80);
  DesignItem framed{DesignTool::wall, 30, {{20, 0}, {80, 0}, {80, 40}, {20, 40}}, false, false};
  framed.holes = {{{40, 10}, {40, 30}, {60, 30}, {60, 10}}};  // either winding
  d.add(framed);
  const Pattern& p = d.pattern();
  const auto at = [&](double x, double v) -> const PatternFace* {
    for (const PatternFace& f : p.faces)
      if (inside_ring({x, v}, f.outer) && std::none_of(f.holes.begin(), f.holes.end(), [&](const Ring& h) {
            return inside_ring({x, v}, h);
          }))
        return &f;
    return nullptr;
  };
  // In the pattern the wall at depth 30 is v = z - 30; z = 20 is v = -10.
  ASSERT_NE(at(30, -10), nullptr);
  EXPECT_EQ(at(30, -10)->kind, FaceKind::vertical);
  EXPECT_EQ(at(30, -10)->t_mm, 30) << "the wall";
  ASSERT_NE(at(50, -10), nullptr);
  EXPECT_EQ(at(50, -10)->kind, FaceKind::horizontal) << "through its hole, the floor";
  EXPECT_EQ(at(50, -10)->t_mm, 0);
  // The same through the faces file: the edit keeps its hole.
  const FaceModel back = parse_face_model(to_face_json(d.model()), "faces.json");
  ASSERT_EQ(back.edits().size(), 1u);
  EXPECT_EQ(back.edits()[0].holes.size(), 1u);
  EXPECT_EQ(compare_patterns(make_pattern(back), p), "");
}

TEST(OaDesign, HolesWhereTheyMeanNothingAreRefusedAndChangeNothing) {
  FaceDesign d(100, 80, 80);
  DesignItem opening{DesignTool::opening, 30, {{20, 0}, {80, 0}, {80, 40}, {20, 40}}, true, false};
  opening.holes = {{{40, 10}, {60, 10}, {60, 30}}};
  EXPECT_EQ(error_of([&] { d.add(opening, "item"); }).location(), "item.holes");
  DesignItem topped{DesignTool::wall, 30, {{20, 0}, {80, 0}, {80, 40}, {20, 40}}, true, false};
  topped.holes = opening.holes;
  EXPECT_EQ(error_of([&] { d.add(topped, "item"); }).location(), "item.holes");
  DesignItem crossing = topped;
  crossing.top = false;
  crossing.holes = {{{70, 10}, {90, 10}, {90, 30}, {70, 30}}};  // reaches past the wall's edge
  const auto e = error_of([&] { d.add(crossing, "item"); });
  EXPECT_EQ(e.location(), "item.holes");
  EXPECT_NE(e.message().find("inside the outer ring"), std::string::npos) << e.message();
  EXPECT_TRUE(d.items().empty());
  EXPECT_EQ(d.model().edits().size(), 0u);
  // A design file's holes are read with the field named.
  const std::string bad = R"({"format": "popcut.design.v1", "sheet": {"width": 100, "back": 80, "floor": 80},
    "items": [{"tool": "roof", "t": 20, "outline": [[0, 0], [50, 0], [50, 20]], "holes": [[[1, 1], [2, 2]]]}]})";
  EXPECT_EQ(error_of([&] { parse_design(bad, "d.json"); }).location(), "items[0].holes[0]");
}

}  // namespace
}  // namespace popcut
