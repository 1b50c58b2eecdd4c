// popcut reads designs (popcut.design.v1) wherever it reads a model: validate, pattern, render.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_run.h"

namespace {
namespace fs = std::filesystem;
using popcut::testing::CliRun;

class CliDesign : public popcut::testing::CliFixture {
 protected:
  CliDesign() : CliFixture("popcut-design") {}
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }
};

// The porch of examples/faces/porch.json as a designer saves it: two walls, their tops automatic.
constexpr const char* kPorch = R"({"format": "popcut.design.v1", "name": "porch",
  "sheet": {"width": 100, "back": 80, "floor": 80},
  "items": [{"tool": "wall", "t": 42, "outline": [[35, 0], [65, 0], [65, 20], [35, 20]]},
            {"tool": "wall", "t": 30, "outline": [[15, 0], [85, 0], [85, 40], [15, 40]]}]})";

TEST_F(CliDesign, ValidatePatternAndRenderReadADesign) {
  const fs::path design = write("porch.json", kPorch);
  const CliRun r = run("validate " + design.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["pops_up"].get<bool>()) << r.out;
  const CliRun porch = run("validate " + std::string(POPCUT_SOURCE_DIR) + "/examples/faces/porch.json --json");
  ASSERT_EQ(porch.code, 0) << porch.err;
  EXPECT_EQ(j["faces"], nlohmann::json::parse(porch.out)["faces"]) << "the same card as the example's edits";
  const CliRun svg = run("pattern " + design.string() + " -o " + (dir_ / "porch.svg").string());
  EXPECT_EQ(svg.code, 0) << svg.err;
  EXPECT_TRUE(fs::exists(dir_ / "porch.svg"));
  const CliRun png = run("render " + design.string() + " --angle 80 -o " + (dir_ / "porch.png").string());
  EXPECT_EQ(png.code, 0) << png.err;
}

TEST_F(CliDesign, AnOpeningInNoWallExitsTwoNamingTheItem) {
  const fs::path bad = write("bad.json", R"({"format": "popcut.design.v1",
    "sheet": {"width": 100, "back": 80, "floor": 80},
    "items": [{"tool": "wall", "t": 30, "outline": [[15, 0], [85, 0], [85, 40], [15, 40]]},
              {"tool": "opening", "t": 35, "outline": [[20, 5], [30, 5], [30, 15], [20, 15]]}]})");
  const CliRun r = run("validate " + bad.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.json: items[1].outline: the hole is not inside a VFace at depth y = 35"), std::string::npos)
      << r.err;
}

// Strokes of one colour in poppler's SVG of a PDF: the segments ("M x y L x y") in its paths.
std::size_t segments_in(const std::string& svg, const std::string& colour) {
  std::size_t n = 0;
  for (std::size_t at = svg.find(colour); at != std::string::npos; at = svg.find(colour, at + 1)) {
    const std::size_t d = svg.find(" d=\"", at), end = svg.find('"', d + 4);
    const std::string path = svg.substr(d + 4, end - d - 4);
    for (std::size_t m = path.find("M "); m != std::string::npos; m = path.find("M ", m + 1)) ++n;
  }
  return n;
}

// A name in letters, written as PDF and read back by poppler (pdfinfo, pdftocairo), an
// independent reader: the page is the sheet at true size, and every line is there in its colour.
TEST_F(CliDesign, ANameInLettersWritesATrueSizePdfThatPopplerReadsBack) {
  const fs::path design = write("name.json", R"({"format": "popcut.design.v1",
    "sheet": {"width": 120, "back": 60, "floor": 60},
    "items": [{"tool": "wall", "t": 30, "text": {"string": "Zoë & Al", "size": 9}, "at": [10, 0]}]})");
  ASSERT_EQ(run("validate " + design.string()).code, 0);
  const CliRun json = run("pattern " + design.string() + " -o " + (dir_ / "name.pattern.json").string());
  ASSERT_EQ(json.code, 0) << json.err;
  const CliRun pdf = run("pattern " + design.string() + " -o " + (dir_ / "name.pdf").string());
  ASSERT_EQ(pdf.code, 0) << pdf.err;
  const nlohmann::json pattern = nlohmann::json::parse(popcut::testing::slurp(dir_ / "name.pattern.json"));
  std::map<std::string, std::size_t> kinds;
  for (const auto& line : pattern["lines"]) ++kinds[line["kind"].get<std::string>()];
  ASSERT_GT(kinds["cut"], 100u) << "letters are many chords";
  const std::string info = (dir_ / "info.txt").string(), back = (dir_ / "back.svg").string();
  ASSERT_EQ(std::system(("pdfinfo " + (dir_ / "name.pdf").string() + " > " + info).c_str()), 0);
  EXPECT_NE(popcut::testing::slurp(info).find("340.157 x 340.157 pts"), std::string::npos)
      << "120 x 120 mm: " << popcut::testing::slurp(info);
  ASSERT_EQ(std::system(("pdftocairo -svg " + (dir_ / "name.pdf").string() + " " + back).c_str()), 0);
  const std::string svg = popcut::testing::slurp(back);
  // Black cuts, red (0.84, 0.15, 0.16) mountains, blue (0.12, 0.37, 0.84) valleys.
  EXPECT_EQ(segments_in(svg, "stroke:rgb(0%,0%,0%)"), kinds["cut"]);
  EXPECT_EQ(segments_in(svg, "stroke:rgb(83."), kinds["mountain"]);
  EXPECT_EQ(segments_in(svg, "stroke:rgb(11."), kinds["valley"]);

  const fs::path font = write("font.json", R"({"format": "popcut.design.v1",
    "sheet": {"width": 120, "back": 60, "floor": 60},
    "items": [{"tool": "wall", "t": 30, "text": {"string": "Al", "font": "Nonesuch"}, "at": [10, 0]}]})");
  const CliRun missing = run("validate " + font.string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.err.find("items[0].text.font: font \"Nonesuch\" is not installed"), std::string::npos)
      << missing.err;
}

}  // namespace
