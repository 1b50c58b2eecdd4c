// The popcut binary refusing a profile whose set-up strings would cut: exit 2 naming the file and key, nothing sent.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_run.h"

namespace {
namespace fs = std::filesystem;

class CliProfile : public popcut::testing::CliFixture {
 protected:
  CliProfile() : CliFixture("popcut-cliprof") {}

  // The shipped simulator profile with one line replaced.
  std::string sim_profile_with(const std::string& from, const std::string& to) {
    std::ifstream in(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/sim.toml");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from << " is not in sim.toml";
    if (at != std::string::npos) text.replace(at, from.size(), to);
    const fs::path p = dir_ / "knife.toml";
    std::ofstream(p) << text;
    return p.string();
  }
  popcut::testing::CliRun cut(const std::string& profile, const fs::path& out) const {
    return run(std::string("cut ") + POPCUT_SOURCE_DIR + "/examples/voxel/box.json --device sim --profile " + profile +
               " --out " + out.string());
  }
};

TEST_F(CliProfile, CutRefusesAKnifeDownInitFinishOrAbortWithExit2) {
  struct Case {
    const char* from;
    const char* to;
    const char* key;
  };
  const Case cases[] = {
      {"[hpgl]\ninit = \"IN;\"", "[hpgl]\ninit = \"IN;PD4000,4000;\"", "[hpgl] init: 'PD4000,4000;' lowers the knife"},
      {"finish = \"PU;SP0;\"", "finish = \"CI40;PU;SP0;\"", "[hpgl] finish: 'CI40;' is not a set-up command"},
      {"finish = \"PU;SP0;\"", "finish = \"PA0,0;\"", "[hpgl] finish: 'PA0,0;' moves with the knife perhaps down"},
      {"abort = \"\\u001b.K\"", "abort = \"\\u001b.KPD;\"", "[transport] abort: must not lower the knife"},
  };
  for (const Case& c : cases) {
    const std::string profile = sim_profile_with(c.from, c.to);
    const fs::path out = dir_ / "out";
    const popcut::testing::CliRun r = cut(profile, out);
    EXPECT_EQ(r.code, 2) << c.to << ": " << r.err;
    EXPECT_NE(r.err.find("knife.toml: " + std::string(c.key)), std::string::npos)
        << "file, section, key and why: " << r.err;
    EXPECT_NE(r.err.find("allowed are IN"), std::string::npos) << "says what is allowed: " << r.err;
    EXPECT_FALSE(fs::exists(out / "job.hpgl")) << c.to << ": nothing planned or sent";
  }
  const popcut::testing::CliRun ok =
      cut(sim_profile_with("finish = \"PU;SP0;\"", "finish = \"PU;PA0,0;SP0;\""), dir_ / "ok");
  EXPECT_EQ(ok.code, 0) << "going home after lifting the knife is fine: " << ok.err;
}

// [kinematics] starts_at = "origin" through the popcut binary: a finish that leaves the head
// where the job ended is refused before anything is cut (exit 2, the key and where the head is
// left); one that goes home absolutely cuts the card on the simulator, its cut matching the plan.
TEST_F(CliProfile, StartsAtOriginNeedsAFinishThatParksTheHead) {
  const popcut::testing::CliRun bad =
      cut(sim_profile_with("[kinematics]", "[kinematics]\nstarts_at = \"origin\""), dir_ / "bad");
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("knife.toml: [kinematics] starts_at"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("leaves it at"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir_ / "bad" / "job.hpgl")) << "nothing planned or sent";
  std::string parked = sim_profile_with("finish = \"PU;SP0;\"", "finish = \"PU;PA0,0;SP0;\"");
  {
    std::ifstream in(parked);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    text.replace(text.find("[kinematics]"), 12, "[kinematics]\nstarts_at = \"origin\"");
    std::ofstream(parked) << text;
  }
  const popcut::testing::CliRun ok = cut(parked, dir_ / "ok");
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(popcut::testing::slurp(dir_ / "ok" / "report.json").find("\"strokes_match_plan\": true"), std::string::npos)
      << popcut::testing::slurp(dir_ / "ok" / "report.json");
}

}  // namespace
