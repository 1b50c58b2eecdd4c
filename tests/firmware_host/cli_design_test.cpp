// popcut reads designs (popcut.design.v1) wherever it reads a model: validate, pattern, render.
#include <gtest/gtest.h>

#include <filesystem>
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

}  // namespace
