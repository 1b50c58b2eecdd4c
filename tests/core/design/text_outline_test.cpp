// Text set as outlines: letters and counters by nesting, the letter height, curves within the tolerance, and every
// way a text can be refused.
#include "popcut/design/text_outline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "error_of.h"

namespace popcut {
namespace {

using testing::error_of;

TextSetting set(const std::string& text, double size_mm = 10, const std::string& font = "DejaVu Sans",
                double tolerance_mm = 0.02) {
  return set_text({text, font, size_mm}, tolerance_mm, "item.text");
}

TEST(TextOutline, CountersAreHolesOfTheirLetterAndDotsAreLettersOfTheirOwn) {
  EXPECT_EQ(set("O").shapes.size(), 1u);
  EXPECT_EQ(set("O").shapes[0].holes.size(), 1u) << "an O has one counter";
  EXPECT_EQ(set("B").shapes[0].holes.size(), 2u) << "a B has two";
  EXPECT_EQ(set("L").shapes[0].holes.size(), 0u);
  EXPECT_EQ(set("i").shapes.size(), 2u) << "an i's dot is paper of its own";
  EXPECT_EQ(set("8").shapes.size(), 1u);
  EXPECT_EQ(set("8").shapes[0].holes.size(), 2u);
  for (const TextShape& s : set("Bog%").shapes) {
    EXPECT_GT(signed_area_mm2(s.outer), 0) << "outer edges run counter-clockwise";
    for (const Ring& h : s.holes) EXPECT_LT(signed_area_mm2(h), 0) << "counters clockwise";
  }
}

TEST(TextOutline, ACapitalIsAsTallAsAskedAndLettersRunLeftToRightFromTheOrigin) {
  for (double size : {2.0, 10.0, 37.5}) {
    for (const char* font : {"DejaVu Sans", "DejaVu Serif"}) {
      const Rect h = bounds(set("H", size, font).shapes[0].outer);
      EXPECT_NEAR(h.max.v_mm - h.min.v_mm, size, 1e-9) << font << " at " << size << " mm";
      EXPECT_NEAR(h.min.v_mm, 0, 1e-9) << "on the baseline";
      EXPECT_GE(h.min.x_mm, 0) << "from x = 0";
    }
  }
  const TextSetting abc = set("ABC");
  ASSERT_EQ(abc.shapes.size(), 3u);
  EXPECT_LT(bounds(abc.shapes[0].outer).max.x_mm, bounds(abc.shapes[2].outer).min.x_mm);
  EXPECT_GT(abc.descent_mm, 0);
  ASSERT_EQ(abc.line_boxes.size(), 1u);
  EXPECT_GT(abc.line_boxes[0].max.v_mm, 10) << "the line's box is its letters' extent: a C's round top overshoots";
  EXPECT_LT(abc.line_boxes[0].max.v_mm, 10.5);
}

TEST(TextOutline, LinesGoDownOneLineHeightEach) {
  const TextSetting two = set("HE\nL");
  ASSERT_EQ(two.line_boxes.size(), 2u);
  EXPECT_NEAR(two.line_boxes[0].min.v_mm - two.line_boxes[1].min.v_mm, two.line_height_mm, 1e-9);
  EXPECT_GT(two.line_height_mm, 10) << "lines do not touch";
  EXPECT_EQ(set("A\n\nB").line_boxes.size(), 3u) << "an empty line is a line";
}

double distance_to_ring(Point2 p, const Ring& r) {
  double best = INFINITY;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const Point2 a = r[i], b = r[(i + 1) % r.size()];
    const double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm, len2 = dx * dx + dv * dv;
    const double s = len2 > 0 ? std::clamp(((p.x_mm - a.x_mm) * dx + (p.v_mm - a.v_mm) * dv) / len2, 0.0, 1.0) : 0;
    best = std::min(best, std::hypot(p.x_mm - a.x_mm - s * dx, p.v_mm - a.v_mm - s * dv));
  }
  return best;
}

// The curve itself stands in as the text set a hundred times finer: every point of it lies
// within the tolerance of the chords cut.
TEST(TextOutline, ChordsStayWithinTheToleranceOfTheFontsCurves) {
  for (const char* font : {"DejaVu Sans", "DejaVu Serif"}) {
    const TextSetting cut = set("Sog@&", 60, font, 0.02), curve = set("Sog@&", 60, font, 0.0002);
    ASSERT_EQ(cut.shapes.size(), curve.shapes.size());
    double worst = 0;
    for (std::size_t i = 0; i < cut.shapes.size(); ++i) {
      for (const Point2& p : curve.shapes[i].outer) worst = std::max(worst, distance_to_ring(p, cut.shapes[i].outer));
      ASSERT_EQ(cut.shapes[i].holes.size(), curve.shapes[i].holes.size());
      for (std::size_t k = 0; k < cut.shapes[i].holes.size(); ++k)
        for (const Point2& p : curve.shapes[i].holes[k])
          worst = std::max(worst, distance_to_ring(p, cut.shapes[i].holes[k]));
    }
    EXPECT_LE(worst, 0.02 + 1e-9) << font;
    EXPECT_GT(worst, 0.002) << font << ": the tolerance is used, not a needlessly fine cut";
  }
}

TEST(TextOutline, RefusedTextsSayWhichFieldAndWhy) {
  Error e = error_of([] { set("Anna", 10, "No Such Font Family"); });
  EXPECT_EQ(e.code(), ErrorCode::invalid_input);
  EXPECT_EQ(e.location(), "item.text.font");
  EXPECT_NE(e.message().find("\"No Such Font Family\" is not installed"), std::string::npos) << e.message();
  EXPECT_NE(e.message().find("DejaVu Sans"), std::string::npos) << "lists the fonts there are: " << e.message();

  e = error_of([] { set(std::string(10 * 1024 * 1024, 'A')); });
  EXPECT_EQ(e.code(), ErrorCode::limit) << "a 10 MB text is over a limit, said before any letter is set";
  EXPECT_EQ(e.location(), "item.text.string");
  EXPECT_NE(e.message().find("at most 200 characters"), std::string::npos) << e.message();

  e = error_of([] { set(std::string(201, 'A')); });
  EXPECT_EQ(e.code(), ErrorCode::limit);
  EXPECT_NE(e.message().find("201 characters"), std::string::npos) << e.message();

  EXPECT_EQ(error_of([] { set("A\xff"); }).message(), "text is not UTF-8");
  EXPECT_NE(error_of([] { set("A\tB"); }).message().find("character 2 is the control character U+0009"),
            std::string::npos);
  EXPECT_NE(error_of([] { set(" \n "); }).message().find("no letters"), std::string::npos);
  e = error_of([] { set("Ab\xe6\x97\xa5"); });  // 日: DejaVu has no CJK
  EXPECT_EQ(e.location(), "item.text.string");
  EXPECT_NE(e.message().find("no letter for character 3 (U+65E5)"), std::string::npos) << e.message();
  e = error_of([] { set("A", 0.5); });
  EXPECT_EQ(e.location(), "item.text.size");
  EXPECT_NE(e.message().find("expected 2–300 mm"), std::string::npos) << e.message();
}

TEST(TextOutline, InstalledFontsIncludeTheDefault) {
  const std::vector<std::string> fonts = installed_font_families();
  EXPECT_TRUE(std::is_sorted(fonts.begin(), fonts.end()));
  EXPECT_NE(std::find(fonts.begin(), fonts.end(), TextSpec{}.font), fonts.end())
      << "scripts/setup installs fonts-dejavu-core";
}

}  // namespace
}  // namespace popcut
