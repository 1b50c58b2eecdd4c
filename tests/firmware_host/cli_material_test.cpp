// popcut plan and cut with --material: the material's forces reach the bytes and the simulator, per pass; bad names exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using popcut::testing::slurp;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kBox = kSrc + "/examples/voxel/box.json";
const std::string kSim = kSrc + "/configs/devices/sim.toml";

class CliMaterial : public popcut::testing::CliFixture {
 protected:
  CliMaterial() : CliFixture("popcut-climat") {}
};

// (kind pen, force) of every stroke the simulator cut, from cut.svg's polylines.
std::vector<std::pair<int, int>> svg_pen_forces(const std::string& svg) {
  std::vector<std::pair<int, int>> out;
  const std::regex re("<polyline data-pen=\"(\\d+)\" data-force=\"(\\d+)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it)
    out.emplace_back(std::stoi((*it)[1]), std::stoi((*it)[2]));
  return out;
}

TEST_F(CliMaterial, PlanTakesTheMaterialsPerPassForces) {
  const auto plain = run("plan " + kBox + " --profile " + kSim + " -o " + (dir_ / "a.hpgl").string() + " --json");
  ASSERT_EQ(plain.code, 0) << plain.err;
  const auto m = run("plan " + kBox + " --profile " + kSim + " --material card-220 -o " + (dir_ / "b.hpgl").string() +
                     " --json");
  ASSERT_EQ(m.code, 0) << m.err;
  const json a = json::parse(plain.out), b = json::parse(m.out);
  EXPECT_TRUE(a["material"].is_null());
  EXPECT_EQ(b["material"], "card-220");
  EXPECT_EQ(b["kinds"]["cut"]["strokes"].get<int>(), 2 * a["kinds"]["cut"]["strokes"].get<int>())
      << "card-220 cuts in two passes, each a stroke";
  EXPECT_EQ(b["kinds"]["outline"]["strokes"].get<int>(), 2 * a["kinds"]["outline"]["strokes"].get<int>());
  const std::string hpgl = slurp(dir_ / "b.hpgl");
  // sim.toml is the generic family: card-220's cut passes are 70 g then 140 g, its valleys 45 g.
  EXPECT_NE(hpgl.find("FS70;"), std::string::npos) << hpgl;
  EXPECT_NE(hpgl.find("FS140;"), std::string::npos) << hpgl;
  EXPECT_NE(hpgl.find("FS45;"), std::string::npos) << hpgl;
  EXPECT_EQ(hpgl.find("FS120;"), std::string::npos) << "the profile's own cut force is replaced";
  EXPECT_NE(slurp(dir_ / "a.hpgl").find("FS120;"), std::string::npos) << "without a material, the profile's";
}

TEST_F(CliMaterial, TheSimulatorCutsEachPassWithItsForce) {
  const auto r = run("cut " + kBox + " --device sim --material card-300 --no-progress --json --out " +
                     (dir_ / "out").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const json report = json::parse(r.out);
  EXPECT_TRUE(report["sim"]["strokes_match_plan"].get<bool>()) << "each pass is a numbered stroke of the plan";
  // sim.toml: valley pen 2, mountain 3, cut 1, outline 4 (one pen per kind).
  const auto strokes = svg_pen_forces(slurp(dir_ / "out" / "cut.svg"));
  ASSERT_EQ(strokes.size(), report["strokes"].get<std::size_t>());
  std::vector<int> cut_forces;
  for (const auto& [pen, force] : strokes) {
    if (pen == 1) cut_forces.push_back(force);
    if (pen == 2) {
      EXPECT_EQ(force, 60) << "card-300 scores valleys at 60 g";
    }
    if (pen == 3) {
      EXPECT_EQ(force, 180) << "and perforates mountains at 180 g";
    }
  }
  ASSERT_FALSE(cut_forces.empty());
  ASSERT_EQ(cut_forces.size() % 2, 0u);
  for (std::size_t i = 0; i < cut_forces.size(); ++i)
    EXPECT_EQ(cut_forces[i], i % 2 == 0 ? 100 : 200) << "cut stroke " << i << ": a light pass, then a full one";
}

TEST_F(CliMaterial, AnUnknownMaterialListsTheKnownOnes) {
  for (const char* cmd : {"plan", "cut"}) {
    const std::string out = std::string(cmd) == "plan" ? "-o " + (dir_ / "x.hpgl").string() : "--out " + dir_.string();
    const auto r = run(std::string(cmd) + " " + kBox + " --profile " + kSim + " --material card-999 " + out);
    EXPECT_EQ(r.code, 2) << cmd;
    EXPECT_NE(r.err.find("--material: unknown material \"card-999\" (known: card-160, card-220, card-300, copy-80"),
              std::string::npos)
        << r.err;
  }
}

TEST_F(CliMaterial, AMaterialWithoutTheFamilySaysWhichItHas) {
  fs::create_directories(dir_ / "configs" / "materials");
  std::ofstream(dir_ / "configs" / "materials" / "foil.toml")
      << "[material]\ndescription = \"foil\"\nsources = [\"a test\"]\n[graphtec]\n"
         "cut = { force_g = 50, speed_cm_s = 5 }\noutline = { force_g = 50, speed_cm_s = 5 }\n"
         "valley = { mode = \"score\", force_g = 10, speed_cm_s = 5 }\n"
         "mountain = { mode = \"score\", force_g = 10, speed_cm_s = 5 }\n";
  const std::string env = "POPCUT_CONFIG_DIR=" + (dir_ / "configs").string() + " ";
  const std::string cmd = env + POPCUT_CLI + std::string(" plan ") + kBox + " --profile " + kSim +
                          " --material foil -o " + (dir_ / "x.hpgl").string() + " 2>" + (dir_ / "err").string();
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2);
  const std::string err = slurp(dir_ / "err");
  EXPECT_NE(err.find("material \"foil\" has no values for the generic family of popcut simulated cutter"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("it has values for graphtec"), std::string::npos) << err;
}

}  // namespace
