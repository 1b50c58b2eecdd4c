// popcut.design.v1: designs read back as the same card, and every malformed field named.
#include "popcut/io/design_json.h"

#include <gtest/gtest.h>

#include "error_of.h"
#include "popcut/io/model_io.h"

namespace popcut {
namespace {

using testing::error_of;

DesignItem wall(double t, double x0, double x1, double h) {
  return {DesignTool::wall, t, {{x0, 0}, {x1, 0}, {x1, h}, {x0, h}}, true, false};
}

std::string doc(const std::string& items) {
  return R"({"format": "popcut.design.v1", "sheet": {"width": 100, "back": 80, "floor": 80}, "items": [)" + items +
         "]}";
}

TEST(DesignJson, ADesignReadsBackAsTheSameCard) {
  FaceDesign d(100, 80, 80);
  d.add(wall(42, 35, 65, 20));  // added front first: the file keeps drawing order
  d.add(wall(30, 15, 85, 40));
  DesignItem door{DesignTool::opening, 42, {{45, 0}, {55, 0}, {55, 12}, {45, 12}}, true, false};
  d.add(door);
  DesignItem side = wall(20, 2.5, 10.25, 30);
  side.mirror = true;
  side.top = false;
  d.add(side);
  const std::string text = to_design_json(d, "porch \"draft\"");
  const FaceDesign back = parse_design(text, "draft.json");
  ASSERT_EQ(back.items().size(), d.items().size());
  for (std::size_t i = 0; i < d.items().size(); ++i) {
    EXPECT_EQ(back.items()[i].item, d.items()[i].item) << i;
    EXPECT_EQ(back.items()[i].id, d.items()[i].id) << i << ": an editor's ids survive the file";
  }
  EXPECT_EQ(back.items().front().id, 4u) << "the mirrored side wall, added last, is drawn first";
  EXPECT_EQ(back.model().edits(), d.model().edits()) << "the same face edits, so the same faces";
  EXPECT_EQ(to_design_json(back, "porch \"draft\""), text);
  EXPECT_EQ(to_face_json(back.model()), to_face_json(d.model()));
}

TEST(DesignJson, AnEmptyDesignIsTheBlankCard) {
  const FaceDesign d = parse_design(to_design_json(FaceDesign(60, 40, 30)), "blank.json");
  EXPECT_TRUE(d.items().empty());
  EXPECT_EQ(d.model().sheet().max.v_mm, 40);
  EXPECT_EQ(d.model().sheet().min.v_mm, -30);
}

TEST(DesignJson, EveryBadFieldIsNamed) {
  const struct {
    std::string text, where, says;
  } cases[] = {
      {R"({"format": "popcut.faces.v1", "sheet": {"width": 1, "back": 1, "floor": 1}, "items": []})", "format",
       "popcut.design.v1"},
      {doc(R"({"tool": "door", "t": 1, "outline": [[0,0],[1,0],[1,1]]})"), "items[0].tool", "\"wall\""},
      {doc(R"({"tool": "wall", "t": -1, "outline": [[0,0],[1,0],[1,1]]})"), "items[0].t", ""},
      {doc(R"({"tool": "wall", "t": 1, "outline": [[0,0],[1,0]]})"), "items[0].outline", ""},
      {doc(R"({"tool": "wall", "t": 1, "outline": [[0,0],[1,0],[1,"a"]]})"), "items[0].outline[2][1]", ""},
      {doc(R"({"tool": "wall", "t": 1, "outline": [[0,0],[1,0],[1,1]], "colour": 3})"), "items[0].colour",
       "unknown field"},
      {doc(R"({"id": 1, "tool": "wall", "t": 1, "outline": [[0,0],[1,0],[1,1]]}, {"id": 1, "tool": "wall", "t": 2,
              "outline": [[0,0],[1,0],[1,1]]})"),
       "items[1].id", "repeats"},
      {doc(R"({"id": 1.5, "tool": "wall", "t": 1, "outline": [[0,0],[1,0],[1,1]]})"), "items[0].id", "whole number"},
      {doc(R"({"id": 1, "tool": "wall", "t": 1, "outline": [[0,0],[1,0],[1,1]]}, {"tool": "wall", "t": 2,
              "outline": [[0,0],[1,0],[1,1]]})"),
       "items[1].id", "every item an id, or none"},
      {doc(R"({"tool": "wall", "t": 1, "outline": [[0,0],[1,0],[1,1]], "mirror": "yes"})"), "items[0].mirror",
       "true or false"},
      {doc(R"({"tool": "roof", "t": 1, "outline": [[0,0],[1,0],[1,1]], "top": false})"), "items[0].top", "only a wall"},
      {doc(R"({"tool": "wall", "t": 30, "outline": [[15,0],[85,0],[85,40],[15,40]]},
              {"tool": "opening", "t": 35, "outline": [[20,5],[30,5],[30,15],[20,15]]})"),
       "items[1].outline", "not inside a VFace"},
      {doc(R"({"tool": "wall", "t": 10, "outline": [[90,0],[120,0],[120,20],[90,20]]})"), "items[0].outline",
       "leaves the sheet"},
  };
  for (const auto& c : cases) {
    const Error e = error_of([&] { parse_design(c.text, "d.json"); });
    EXPECT_EQ(e.source(), "d.json") << c.text;
    EXPECT_EQ(e.location(), c.where) << c.text << "\n" << e.what();
    EXPECT_NE(e.message().find(c.says), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace popcut
