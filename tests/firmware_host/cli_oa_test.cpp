// popcut reading webOAcard .oa files: validate on a demo card and on a broken one, as a user runs it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_run.h"

namespace {
namespace fs = std::filesystem;
using popcut::testing::CliRun;

class CliOa : public popcut::testing::CliFixture {
 protected:
  CliOa() : CliFixture("popcut-oa") {}
  static std::string demo(const std::string& name) {
    return std::string(POPCUT_SOURCE_DIR) + "/../shared/testdata/webOAcard/demo/" + name;
  }
};

TEST_F(CliOa, ValidateReadsADemoCard) {
  const CliRun r = run("validate " + demo("house.oa") + " --json");
  ASSERT_TRUE(r.code == 0 || r.code == 1) << "a demo card is a card (0 pops up, 1 does not): " << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["pops_up"].get<bool>(), r.code == 0) << "the exit code says whether it pops up: " << r.out;
  EXPECT_GT(j["faces"].get<int>(), 10) << "the house has its walls and top faces: " << r.out;
  const CliRun render = run("render " + demo("house.oa") + " --angle 75 -o " + (dir_ / "house.png").string());
  EXPECT_EQ(render.code, 0) << "render reads .oa too: " << render.err;
}

TEST_F(CliOa, AMalformedFileExitsTwoNamingTheField) {
  const fs::path bad = dir_ / "bad.oa";
  std::ofstream(bad)
      << R"({"settings": {"cardW": 120, "cardH": 100}, "faces": [{"contours": [{"outer": [)"
         R"({"X": 1, "Y": 1}, {"X": "two", "Y": 1}, {"X": 2, "Y": 5}]}], "type": "VFACE", "mode": 0, "t": 5}]})";
  const CliRun r = run("validate " + bad.string());
  EXPECT_EQ(r.code, 2) << "bad input is exit 2: " << r.err;
  EXPECT_NE(r.err.find("bad.oa: faces[0].contours[0].outer[1].X: expected a number"), std::string::npos)
      << "the message names the file and the field: " << r.err;
}

}  // namespace
