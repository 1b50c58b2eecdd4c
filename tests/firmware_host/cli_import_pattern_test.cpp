// popcut import-pattern and the commands that read drawings directly, run as a user would.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_run.h"
#include "shared_testdata.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using popcut::testing::CliRun;

class ImportPattern : public popcut::testing::CliFixture {
 protected:
  ImportPattern() : CliFixture("popcut-import-pattern") {}
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  static std::string example() { return std::string(POPCUT_SOURCE_DIR) + "/examples/drawn/step.svg"; }
};

TEST_F(ImportPattern, AnInkscapeDrawingBecomesACardThatPopsUp) {
  const CliRun r = run("import-pattern " + example() + " -o " + out("step.json"));
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("an OA card of 4 faces; centre fold 60 mm above the sheet's bottom edge"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("the SVG page (100 × 120 mm) is the sheet"), std::string::npos) << r.out;
  const CliRun v = run("validate " + out("step.json") + " --json");
  ASSERT_EQ(v.code, 0) << v.err << v.out;
  const json j = json::parse(v.out);
  EXPECT_EQ(j["lines"]["mountain"], 1);
  EXPECT_EQ(j["lines"]["valley"], 4);
  EXPECT_EQ(j["lines"]["cut"], 2);
  // Every command that reads a model reads the drawing itself.
  EXPECT_EQ(run("validate " + example()).code, 0);
  const CliRun plan = run("plan " + example() + " --profile " + std::string(POPCUT_SOURCE_DIR) +
                          "/configs/devices/generic-hpgl.toml -o " + out("step.hpgl"));
  EXPECT_EQ(plan.code, 0) << plan.err;
  const CliRun render = run("render " + example() + " -o " + out("step.png"));
  EXPECT_EQ(render.code, 0) << render.err;
  EXPECT_GT(fs::file_size(out("step.png")), 1000u);
}

TEST_F(ImportPattern, ConflictsNameThePlaceAndElementAndExitOne) {
  // The step's mountain fold drawn 10 mm too low: the planes the other folds give the step do not meet there.
  std::string text = popcut::testing::slurp(example());
  text.replace(text.find("M 30,60 H 70"), 12, "M 30,70 H 70");
  const std::string bad = write("bad.svg", text);
  const CliRun r = run("import-pattern " + bad + " --json");
  ASSERT_EQ(r.code, 1) << r.err << r.out;
  const json j = json::parse(r.out);
  EXPECT_FALSE(j["card"]);
  ASSERT_FALSE(j["conflicts"].empty());
  EXPECT_NE(j["conflicts"][0]["what"].get<std::string>().find("do not meet at the fold's height"), std::string::npos);
  EXPECT_NE(j["conflicts"][0]["drawn"].get<std::string>().find("id=\"step-edge\""), std::string::npos) << r.out;
  const CliRun v = run("validate " + bad);
  EXPECT_EQ(v.code, 1) << v.err;
  EXPECT_NE(v.err.find("no OA card folds from this sheet"), std::string::npos) << v.err;
}

TEST_F(ImportPattern, BadDrawingsExitTwoNamingTheElement) {
  const CliRun unknown =
      run("import-pattern " + write("u.svg",
                                    "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10mm\" height=\"10mm\" "
                                    "viewBox=\"0 0 10 10\"><line id=\"odd\" x1=\"1\" y1=\"1\" x2=\"9\" y2=\"1\" "
                                    "stroke=\"#ffa500\"/></svg>"));
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("<line id=\"odd\">"), std::string::npos) << unknown.err;
  EXPECT_NE(unknown.err.find("--layer NAME=KIND"), std::string::npos) << unknown.err;
  const CliRun xml = run("import-pattern " + write("x.svg", "<svg><g></svg>"));
  EXPECT_EQ(xml.code, 2);
  EXPECT_NE(xml.err.find("line 1"), std::string::npos) << xml.err;
  const CliRun fold =
      run("import-pattern " + write("f.fold", "{\"vertices_coords\": [[0,0]], \"edges_vertices\": [[0,5]]}"));
  EXPECT_EQ(fold.code, 2);
  EXPECT_NE(fold.err.find("edges_vertices[0][1]"), std::string::npos) << fold.err;
  const CliRun layer = run("import-pattern " + example() + " --layer Knife=blade");
  EXPECT_EQ(layer.code, 2);
  EXPECT_NE(layer.err.find("--layer"), std::string::npos) << layer.err;
  const CliRun dxf = run("validate " + write("box.dxf", "0\nSECTION\n2\nENTITIES\n0\nLINE\n10\n1,5\n"));
  EXPECT_EQ(dxf.code, 2);
  EXPECT_NE(dxf.err.find("box.dxf: line 8: group code 10 expects a number, got \"1,5\""), std::string::npos) << dxf.err;
  POPCUT_NEEDS_SHARED_TESTDATA();  // the FOLD spec's folded box, last
  const CliRun folded = run("import-pattern " + popcut::testing::shared_testdata("fold/box.fold"));
  EXPECT_EQ(folded.code, 2);
  EXPECT_NE(folded.err.find("folded form"), std::string::npos) << folded.err;
}

// A card written as a DXF dieline (as CAD software gets it) reads back as the same card.
TEST_F(ImportPattern, APatternWrittenAsDxfIsReadBackByEveryCommand) {
  const std::string porch = std::string(POPCUT_SOURCE_DIR) + "/examples/faces/porch.json";
  const CliRun w = run("pattern " + porch + " -o " + out("porch.dxf"));
  ASSERT_EQ(w.code, 0) << w.err;
  const CliRun want = run("validate " + porch + " --json");
  const CliRun got = run("validate " + out("porch.dxf") + " --json");
  ASSERT_EQ(got.code, 0) << got.err << got.out;
  EXPECT_EQ(json::parse(got.out)["lines"], json::parse(want.out)["lines"]) << got.out;
  const CliRun imported = run("import-pattern " + out("porch.dxf") + " --json -o " + out("porch-back.json"));
  ASSERT_EQ(imported.code, 0) << imported.err << imported.out;
  EXPECT_TRUE(fs::exists(out("porch-back.json")));
}

TEST_F(ImportPattern, ConfiguredLayerNames) {
  std::string text = popcut::testing::slurp(example());
  text.replace(text.find("inkscape:label=\"Cut\""), 20, "inkscape:label=\"Knife\"");
  text.replace(text.find("style=\"fill:none;stroke:#000000;stroke-width:0.25\""), 50, "stroke=\"#00ffff\"");
  const std::string drawn = write("knife.svg", text);
  EXPECT_EQ(run("import-pattern " + drawn).code, 2);
  const CliRun r = run("import-pattern " + drawn + " --layer knife=cut");
  EXPECT_EQ(r.code, 0) << r.err << r.out;
}

}  // namespace
