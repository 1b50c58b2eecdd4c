// --as sheet from the command line: a box dieline checked, folded, drawn and cut; FOLD's diagonal; bad options.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cli_run.h"
#include "shared_testdata.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using popcut::testing::CliRun;

class SheetCli : public popcut::testing::CliFixture {
 protected:
  SheetCli() : CliFixture("popcut-sheet") {}
  std::string out(const std::string& name) { return (dir_ / name).string(); }
  static std::string box() { return std::string(POPCUT_SOURCE_DIR) + "/examples/drawn/box.svg"; }
};

// The extent of an OBJ's vertices along each axis.
std::array<double, 3> obj_extent(const std::string& path) {
  std::ifstream in(path);
  std::array<double, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<double>::max());
  hi.fill(std::numeric_limits<double>::lowest());
  for (std::string l; std::getline(in, l);) {
    if (l.rfind("v ", 0) != 0) continue;
    std::istringstream ss(l.substr(2));
    for (std::size_t k = 0; k < 3; ++k) {
      double v = 0;
      ss >> v;
      lo[k] = std::min(lo[k], v);
      hi[k] = std::max(hi[k], v);
    }
  }
  return {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
}

TEST_F(SheetCli, TheBoxsTabsCollideUnlessTheyFoldAfterTheWalls) {
  const CliRun at_once = run("validate " + box() + " --as sheet --json");
  ASSERT_EQ(at_once.code, 1) << at_once.err << at_once.out;
  const json j = json::parse(at_once.out);
  EXPECT_EQ(j["format"], "popcut.sheet-check.v1");
  ASSERT_EQ(j["regions"].size(), 11u);
  EXPECT_EQ(j["regions"][0]["piece"], 0);
  EXPECT_EQ(j["hinges"].size(), 10u);
  EXPECT_EQ(j["pieces"], 1);
  ASSERT_EQ(j["collisions"].size(), 4u);
  EXPECT_GT(j["collisions"][0]["fraction"].get<double>(), 0.3);
  EXPECT_EQ(j["collisions"][0]["regions"].size(), 2u);
  const CliRun staged = run("validate " + box() + " --as sheet --fold 'tab-*=90@2'");
  EXPECT_EQ(staged.code, 0) << staged.err << staged.out;
  EXPECT_NE(staged.out.find("folds (11 regions, 10 hinges, 1 piece"), std::string::npos) << staged.out;
}

TEST_F(SheetCli, TheFoldedBoxIsEightyBySixtyByThirty) {
  const CliRun f = run("fold " + box() + " --as sheet -o " + out("box.obj"));
  ASSERT_EQ(f.code, 0) << f.err;
  const auto e = obj_extent(out("box.obj"));
  // OBJ is Y-up: (x, height, depth).
  EXPECT_NEAR(e[0], 80, 1e-6);
  EXPECT_NEAR(e[1], 30, 1e-6);
  EXPECT_NEAR(e[2], 60, 1e-6);
  EXPECT_TRUE(fs::exists(out("box.mtl")));
  // Every crease at 45°: the walls lean out, so the box is wider than its base.
  ASSERT_EQ(run("fold " + box() + " --as sheet --crease-angle 45 -o " + out("half.obj")).code, 0);
  const auto half = obj_extent(out("half.obj"));
  EXPECT_NEAR(half[0], 80 + 2 * 30 * std::cos(M_PI / 4), 1e-6);
  // Halfway through the motion every 90° crease has turned 45°: the same box.
  const CliRun at = run("fold " + box() + " --as sheet --at 0.5 -o " + out("halfway.obj"));
  ASSERT_EQ(at.code, 0) << at.err;
  EXPECT_NE(at.err.find("50% of the motion"), std::string::npos) << at.err;
  EXPECT_NEAR(obj_extent(out("halfway.obj"))[0], half[0], 1e-6);
  EXPECT_NEAR(obj_extent(out("halfway.obj"))[1], half[1], 1e-6);
  ASSERT_EQ(run("fold " + box() + " --as sheet -o " + out("box.gltf")).code, 0);
  EXPECT_GT(fs::file_size(out("box.gltf")), 1000u);
}

TEST_F(SheetCli, RenderDrawsTheMotionFromFlatToFolded) {
  const CliRun r = run("render " + box() + " --as sheet --fold 'tab-*=90@2' --frames 3 -o " + out("box.png"));
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f : {"box-000.png", "box-001.png", "box-002.png"}) EXPECT_GT(fs::file_size(out(f)), 1000u) << f;
  EXPECT_NE(r.err.find("folded from flat"), std::string::npos) << r.err;
}

TEST_F(SheetCli, TheDielineIsCutWithItsOutlineAndScoredOnItsCreases) {
  const CliRun c = run("cut " + box() + " --as sheet --device sim --out " + out("cut"));
  ASSERT_EQ(c.code, 0) << c.err;
  const json report = json::parse(popcut::testing::slurp(out("cut/report.json")));
  const CliRun p = run("pattern " + box() + " --as sheet -o " + out("box.dxf") + " --json");
  ASSERT_EQ(p.code, 0) << p.err;
  const json lines = json::parse(p.out);
  EXPECT_EQ(lines["lines"]["cut"], 32);
  EXPECT_EQ(lines["lines"]["valley"], 10);
  EXPECT_NEAR(lines["length_mm"]["valley"].get<double>(), 4 * 80 + 2 * 60 + 4 * 26, 1e-6);
  // The planner cuts what the pattern holds (fold gaps shorten the scores a little).
  EXPECT_GT(report.dump().find("\"strokes\""), 0u);
  const CliRun plan = run("plan " + box() + " --as sheet --profile " + std::string(POPCUT_SOURCE_DIR) +
                          "/configs/devices/generic-hpgl.toml -o " + out("box.hpgl") + " --json");
  ASSERT_EQ(plan.code, 0) << plan.err;
  const json planned = json::parse(plan.out);
  EXPECT_NE(planned.dump().find("cut_mm"), std::string::npos) << plan.out;
  EXPECT_NEAR(planned["kinds"]["cut"]["cut_mm"].get<double>(), 741.22, 0.1) << plan.out;
  // The card reading of the same file says why it is no card, and what to do.
  const CliRun card = run("validate " + box());
  EXPECT_EQ(card.code, 1);
  EXPECT_NE(card.err.find("--as sheet"), std::string::npos) << card.err;
}

TEST_F(SheetCli, ImportPatternWritesTheReportOrTheFoldedSheet) {
  const CliRun r = run("import-pattern " + box() + " --as sheet --fold 'tab-*=90@2' -o " + out("box.json"));
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  EXPECT_EQ(json::parse(popcut::testing::slurp(out("box.json")))["format"], "popcut.sheet-check.v1");
  ASSERT_EQ(run("import-pattern " + box() + " --as sheet -o " + out("box.gltf")).code, 1);  // written, with collisions
  EXPECT_GT(fs::file_size(out("box.gltf")), 1000u);
}

// The FOLD specification's diagonal crease pattern folds flat: its two layers stack, no collision.
TEST_F(SheetCli, FoldSpecsDiagonalFoldsFlat) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  const std::string cp = popcut::testing::shared_testdata("fold/diagonal-cp.fold");
  ASSERT_TRUE(fs::exists(cp)) << "missing " << cp;
  const CliRun r = run("validate " + cp + " --as sheet --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["hinges"].size(), 1u);
  EXPECT_DOUBLE_EQ(j["hinges"][0]["angle_deg"].get<double>(), 180);
}

// A square of paper folded in half and in half again along lines, from the command line: three
// creases, the last two through both layers, and four layers in the report.
TEST_F(SheetCli, FoldLinesFoldEveryLayer) {
  std::ofstream(out("paper.svg"))
      << R"(<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="100mm" viewBox="0 0 100 100">
<rect id="edge" x="0" y="0" width="100" height="100" style="fill:none;stroke:#000"/></svg>)";
  const CliRun r =
      run("validate " + out("paper.svg") + " --as sheet --fold-line 50,0,50,100 --fold-line 100,50,50,50 --json");
  ASSERT_EQ(r.code, 0) << r.err << r.out;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["hinges"].size(), 4u);  // the second fold crosses both layers: two creases, each split at the first
  std::set<int> layers;
  for (const json& g : j["regions"]) layers.insert(g["layer"].get<int>());
  EXPECT_EQ(layers.size(), 4u) << r.out;
  const CliRun png =
      run("render " + out("paper.svg") + " --as sheet --fold-line 50,0,50,100 --frames 3 -o " + out("p.png"));
  EXPECT_EQ(png.code, 0) << png.err;
  const CliRun bad = run("validate " + out("paper.svg") + " --as sheet --fold-line 1,2,3");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("expected X1,V1,X2,V2"), std::string::npos) << bad.err;
  const CliRun miss = run("validate " + out("paper.svg") + " --as sheet --fold-line 500,0,500,100");
  EXPECT_EQ(miss.code, 2);
  EXPECT_NE(miss.err.find("crosses no layer"), std::string::npos) << miss.err;
}

TEST_F(SheetCli, BadOptionsAreExitTwoNamingTheOption) {
  const std::string model = std::string(POPCUT_SOURCE_DIR) + "/examples/faces/porch.json";
  const CliRun m = run("validate " + model + " --as sheet");
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.err.find("--as sheet reads drawings"), std::string::npos) << m.err;
  const CliRun a = run("fold " + box() + " --as sheet --angle 30 -o " + out("x.obj"));
  EXPECT_EQ(a.code, 2);
  EXPECT_NE(a.err.find("--angle opens a card"), std::string::npos) << a.err;
  for (const char* at : {"1.5", "0x1", "-0.1"})
    EXPECT_EQ(run("fold " + box() + " --as sheet --at " + at + " -o " + out("x.obj")).code, 2) << at;
  const CliRun card_at = run("fold " + model + " --at 0.5 -o " + out("x.obj"));
  EXPECT_EQ(card_at.code, 2);
  EXPECT_NE(card_at.err.find("--at is how far a sheet's motion"), std::string::npos) << card_at.err;
  const CliRun f = run("validate " + box() + " --as sheet --fold lid");
  EXPECT_EQ(f.code, 2);
  EXPECT_NE(f.err.find("expected LINE=DEGREES"), std::string::npos) << f.err;
  const CliRun n = run("validate " + box() + " --as sheet --fold nosuch=10 --json");
  EXPECT_EQ(n.code, 2);
  EXPECT_EQ(json::parse(n.out)["error"]["location"], "--fold");
  EXPECT_EQ(run("validate " + box() + " --as paper").code, 2);
  const CliRun fixed = run("validate " + box() + " --as sheet --fixed 11");
  EXPECT_EQ(fixed.code, 2);
  EXPECT_NE(fixed.err.find("0 to 10"), std::string::npos) << fixed.err;
  EXPECT_EQ(run("render " + box() + " --as sheet --fold 'lid=30@0' -o " + out("x.png")).code, 2);
  EXPECT_EQ(run("validate " + box() + " --as sheet --crease-angle nan").code, 2);
  EXPECT_EQ(run("validate " + box() + " --as sheet --fold lid=0x5A").code, 2);
  const CliRun alone = run("validate " + box() + " --fold lid=30");
  EXPECT_EQ(alone.code, 2);
  EXPECT_NE(alone.err.find("--fold folds a sheet: it needs --as sheet"), std::string::npos) << alone.err;
}

}  // namespace
