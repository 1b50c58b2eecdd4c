// popcut plan and cut --copies: cards nested on one sheet, cut on the simulator exactly as planned, or refused naming
// how many fit.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_run.h"

namespace {
using nlohmann::json;

const std::string kSrc = POPCUT_SOURCE_DIR;

class CliCopies : public popcut::testing::CliFixture {
 protected:
  CliCopies() : CliFixture("popcut-clicopies") {}
  json plan(const std::string& args) {
    const popcut::testing::CliRun r =
        run("plan " + kSrc + "/examples/voxel/pyramid.json -o " + (dir_ / "job").string() + " --json " + args);
    EXPECT_EQ(r.code, 0) << r.err;
    return json::parse(r.out, nullptr, false);
  }
};

TEST_F(CliCopies, CopiesOnOneSheetCutOnTheSimulatorAsPlannedInBothLanguages) {
  const std::vector<std::string> profiles = {"sim", "silhouette-cameo4", "graphtec-ce6000"};
  for (const std::string& profile : profiles) {
    const std::string p = " --profile " + kSrc + "/configs/devices/" + profile + ".toml";
    const json one = plan(p);
    const json four = plan(p + " --copies 4 --gap-mm 3");
    EXPECT_EQ(four["strokes"], 4 * one["strokes"].get<int>()) << profile;
    EXPECT_NEAR(four["cut_mm"].get<double>(), 4 * one["cut_mm"].get<double>(), 1e-6 * four["cut_mm"].get<double>());
    EXPECT_EQ(four["copies"]["count"], 4);
    EXPECT_GE(four["copies"]["fit"].get<int>(), 4);
    EXPECT_EQ(one["copies"]["count"], 1);
    const popcut::testing::CliRun cut = run("cut " + kSrc + "/examples/voxel/pyramid.json --device sim" + p +
                                            " --copies 4 --gap-mm 3 --json --out " + (dir_ / profile).string());
    ASSERT_EQ(cut.code, 0) << profile << ": " << cut.err;
    const json r = json::parse(cut.out);
    EXPECT_TRUE(r["sim"]["strokes_match_plan"].get<bool>()) << profile;
    EXPECT_FALSE(r["sim"]["outside_area"].get<bool>()) << profile;
    EXPECT_EQ(r["sim"]["overflow_bytes"], 0) << profile;
    EXPECT_EQ(r["sim"]["strokes"], four["strokes"]) << profile;
  }
}

TEST_F(CliCopies, MoreCopiesThanFitAreRefusedSayingHowManyDo) {
  const std::string p = " --profile " + kSrc + "/configs/devices/sim.toml";
  const int fit = plan(p)["copies"]["fit"];
  ASSERT_GE(fit, 1);
  const popcut::testing::CliRun r = run("plan " + kSrc + "/examples/voxel/pyramid.json -o " + (dir_ / "job").string() +
                                        p + " --copies " + std::to_string(fit + 1));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("copies"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("it holds " + std::to_string(fit)), std::string::npos) << r.err;
  EXPECT_EQ(plan(p + " --copies " + std::to_string(fit))["copies"]["count"], fit) << "as many as fit do";
  EXPECT_EQ(run("plan x.json -o y --profile sim --copies 0").code, 2);
  EXPECT_EQ(run("plan x.json -o y --profile sim --copies 1001").code, 2);
  EXPECT_EQ(run("plan x.json -o y --profile sim --gap-mm -1").code, 2);
}

}  // namespace
