// popcut.pattern.v1 JSON round trip and errors, and the SVG's units, groups and styles.
#include "popcut/io/pattern_io.h"

#include <gtest/gtest.h>

#include "popcut/error.h"
#include "popcut/io/voxel_json.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
namespace {

Pattern sample() {
  return make_pattern(parse_voxel_model(
      R"({"format": "popcut.voxel.v1", "voxel_mm": 2.5, "heights": [[3, 3, 1], [4, 2], [2]], "windows": [[0, 1]]})",
      "s.json"));
}

TEST(PatternJson, RoundTripIsExact) {
  const Pattern p = sample();
  const std::string text = to_pattern_json(p);
  EXPECT_EQ(parse_pattern(text, "p.json"), p) << "write + read gives the same pattern";
  EXPECT_NE(text.find("\"format\": \"popcut.pattern.v1\""), std::string::npos) << "format tag";
  EXPECT_NE(text.find("\"units\": \"mm\""), std::string::npos) << "units";
}

TEST(PatternJson, BadFieldsAreNamed) {
  const std::string good = to_pattern_json(sample());
  std::string bad = good;
  bad.replace(bad.find("\"valley\""), 8, "\"crease\"");
  try {
    parse_pattern(bad, "p.json");
    FAIL() << "an unknown line kind is rejected";
  } catch (const Error& e) {
    EXPECT_NE(e.location().find("lines["), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("\"crease\""), std::string::npos) << e.what();
  }
}

// The error's "location: message" for this pattern text, or "" when it reads.
std::string pattern_error(const std::string& text) {
  try {
    parse_pattern(text, "p.json");
  } catch (const Error& e) {
    return e.location() + ": " + e.message();
  }
  return "";
}

TEST(PatternJson, KindsAreReadByTheirFileNames) {
  const std::string good = to_pattern_json(sample());
  // The text with the first "kind" after `section` set to `kind`.
  const auto with_kind = [&](const char* section, const std::string& kind) {
    std::string text = good;
    const std::size_t at = text.find("\"kind\": \"", text.find(section)) + 9;
    text.replace(at, text.find('"', at) - at, kind);
    return text;
  };
  EXPECT_EQ(pattern_error(with_kind("\"lines\"", "fold")),
            "lines[0].kind: expected \"cut\", \"mountain\" or \"valley\", got \"fold\"");
  EXPECT_EQ(pattern_error(with_kind("\"faces\"", "v")), "faces[0].kind: expected \"V\" or \"H\", got \"v\"")
      << "case matters";
  EXPECT_EQ(pattern_error(with_kind("\"folds\"", "cut")), "folds[0].kind: a fold is \"mountain\" or \"valley\"");
  EXPECT_EQ(pattern_error(with_kind("\"folds\"", "crease")),
            "folds[0].kind: expected \"cut\", \"mountain\" or \"valley\", got \"crease\"");
  for (const char* kind : {"cut", "mountain", "valley"})
    EXPECT_EQ(pattern_error(with_kind("\"lines\"", kind)), "") << kind;
  for (const char* kind : {"V", "H"}) EXPECT_EQ(pattern_error(with_kind("\"faces\"", kind)), "") << kind;
}

TEST(PatternSvg, MillimetreUnitsAndOneGroupPerKind) {
  const Pattern p = sample();
  const std::string svg = to_pattern_svg(p);
  const double w = p.sheet.max.x_mm - p.sheet.min.x_mm, h = p.sheet.max.v_mm - p.sheet.min.v_mm;
  char dims[128];
  std::snprintf(dims, sizeof dims, "width=\"%gmm\" height=\"%gmm\" viewBox=\"0 0 %g %g\"", w, h, w, h);
  EXPECT_NE(svg.find(dims), std::string::npos) << "real millimetres and a matching viewBox: " << dims;
  EXPECT_NE(svg.find("id=\"cut\""), std::string::npos) << "cut group";
  EXPECT_NE(svg.find("stroke=\"#000000\""), std::string::npos) << "cut is solid black";
  EXPECT_NE(svg.find("stroke=\"#d62728\" stroke-dasharray=\"2 0.5 0.4 0.5\""), std::string::npos)
      << "mountain red dash-dot";
  EXPECT_NE(svg.find("stroke=\"#1f5fd6\" stroke-dasharray=\"1.5 0.75\""), std::string::npos) << "valley blue dashed";
  EXPECT_NE(svg.find("id=\"outline\""), std::string::npos) << "sheet outline group";
  std::size_t count = 0;
  for (std::size_t at = svg.find("<line "); at != std::string::npos; at = svg.find("<line ", at + 1)) ++count;
  EXPECT_EQ(count, p.lines.size()) << "one SVG line per pattern line; the outline is a rect";
  EXPECT_EQ(svg.find("id=\"faces\""), std::string::npos) << "no shading unless asked";
  EXPECT_NE(to_pattern_svg(p, {true}).find("id=\"faces\""), std::string::npos) << "shading when asked";
}

}  // namespace
}  // namespace popcut
