// popcut test-cut and calibrate as a user runs them: plans, refusals, the overlay every later job uses, prompts on a
// pipe.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli_run.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using popcut::testing::CliRun;
using popcut::testing::slurp;

class CliCalibrate : public popcut::testing::CliFixture {
 protected:
  CliCalibrate() : CliFixture("popcut-clical") {}

  // popcut with its own calibration directory and, when given, standard input from `input`.
  CliRun popcut(const std::string& args, const std::string& input = "") const {
    const fs::path in = dir_ / "cli.stdin";
    std::ofstream(in) << input;
    const std::string cmd = "POPCUT_CALIBRATION_DIR=" + cal_dir().string() + " " + POPCUT_CLI + " " + args + " <" +
                            in.string() + " >" + (dir_ / "cli.stdout").string() + " 2>" +
                            (dir_ / "cli.stderr").string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir_ / "cli.stdout"), slurp(dir_ / "cli.stderr")};
  }
  fs::path cal_dir() const { return dir_ / "cal"; }
  static json last_json(const std::string& out) {
    const std::size_t nl = out.find_last_of('\n', out.size() - 2);
    return json::parse(out.substr(nl == std::string::npos ? 0 : nl + 1));
  }
  // Every x,y pair a PA command of the job carries.
  static std::vector<std::array<long, 2>> job_points(const std::string& job) {
    std::vector<std::array<long, 2>> pts;
    const std::regex pa("PA([-0-9,]+);");
    for (auto it = std::sregex_iterator(job.begin(), job.end(), pa); it != std::sregex_iterator(); ++it) {
      std::stringstream ss((*it)[1].str());
      std::string a, b;
      while (std::getline(ss, a, ',') && std::getline(ss, b, ',')) pts.push_back({std::stol(a), std::stol(b)});
    }
    return pts;
  }
  static const std::string kMeasured;
};

const std::string CliCalibrate::kMeasured = "--measured-x-mm 100.4 --measured-y-mm 149.7 --measured-diagonal-mm 180.4";

TEST_F(CliCalibrate, TestCutOnSimSaysWhatToLookAtAndHowToAdjust) {
  const CliRun r = popcut("test-cut --device sim");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("look at:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("10 mm square ([tool.cut] cut, force_g 120"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("28 mm triangle ([tool.valley] score, force_g 40"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("raise [tool.cut] force_g by about 10 % (120 -> 132)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("blade_offset_mm"), std::string::npos) << r.out;
}

TEST_F(CliCalibrate, TestCutJsonPlacesTheSquareInsideTheTriangleAtTheSpot) {
  const CliRun r = popcut("test-cut --device sim --at 50,60 --json --out " + (dir_ / "t").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = last_json(r.out);
  EXPECT_EQ(j["format"], "popcut.test_cut.v1");
  EXPECT_EQ(j["square"]["kind"], "cut");
  EXPECT_EQ(j["triangle"]["kind"], "valley");
  EXPECT_DOUBLE_EQ(j["box_mm"]["min_x"].get<double>(), 50);
  EXPECT_NEAR(j["box_mm"]["max_y"].get<double>(), 60 + 28 * std::sqrt(3.0) / 2, 1e-3)
      << "reports round to a micrometre";
  EXPECT_TRUE(j["sim"]["strokes_match_plan"].get<bool>());
  EXPECT_TRUE(j["sent"]["complete"].get<bool>());
  EXPECT_FALSE(j["calibration"]["calibrated"].get<bool>());
  EXPECT_GE(j["adjust"].size(), 4u);
  // On the plotter: the triangle's corners at (50, 60) and (78, 60) mm, its apex at 84.2 mm; the
  // square 10 mm wide in the middle.
  const auto pts = job_points(slurp(dir_ / "t" / "job.hpgl"));
  ASSERT_FALSE(pts.empty());
  long min_x = 1 << 30, max_x = 0, min_y = 1 << 30, max_y = 0;
  for (const auto& p : pts) {
    if (p == std::array<long, 2>{0, 0}) continue;
    min_x = std::min(min_x, p[0]), max_x = std::max(max_x, p[0]);
    min_y = std::min(min_y, p[1]), max_y = std::max(max_y, p[1]);
  }
  EXPECT_EQ(min_x, 2000);
  EXPECT_EQ(max_x, 3120);
  EXPECT_EQ(min_y, 2400);
  EXPECT_EQ(max_y, 3370);
  const bool square_corner = std::find(pts.begin(), pts.end(), std::array<long, 2>{2360, 2475}) != pts.end();
  EXPECT_TRUE(square_corner) << "the square's lower left corner: 50 + 9 mm, 60 + 1.86 mm";
  EXPECT_TRUE(fs::exists(dir_ / "t" / "cut.svg"));
  EXPECT_TRUE(fs::exists(dir_ / "t" / "report.json"));
}

TEST_F(CliCalibrate, TestCutRefusesASpotWhereItDoesNotFitNamingTheArea) {
  CliRun r = popcut("test-cut --device sim --at 590,10");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--at: '590,10': the test cut (28 x 24.2 mm on the plotter's axes) does not fit the usable area "
                       "of popcut simulated cutter (600 x 1000 mm from its origin corner) there, keeping 1 mm from its "
                       "edges: x may be 1 to 571, y 1 to 974.8"),
            std::string::npos)
      << r.err;
  r = popcut("test-cut --device sim --at 0,10");
  EXPECT_EQ(r.code, 2) << "on the area's edge";
  r = popcut("test-cut --device sim --at ten,10");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--at: 'ten,10' is not X,Y in mm"), std::string::npos) << r.err;
  r = popcut("test-cut --device sim --size-mm 60");
  EXPECT_EQ(r.code, 2) << r.err;
  r = popcut("test-cut --device sim --material no-such-stock");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--material"), std::string::npos) << r.err;
}

TEST_F(CliCalibrate, TestCutWithAMaterialAdvisesInTheMaterialsTerms) {
  const CliRun r = popcut("test-cut --device sim --material card-220 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = last_json(r.out);
  EXPECT_EQ(j["material"], "card-220");
  EXPECT_NE(j["square"]["tool"].get<std::string>().find("force_g 70/140"), std::string::npos) << j["square"];
  const std::string first = j["adjust"][0].get<std::string>();
  EXPECT_NE(first.find("card-220.toml [generic] cut pass_force_g (the last pass) by about 10 % (140 -> 154)"),
            std::string::npos)
      << first;
  EXPECT_TRUE(j["sim"]["strokes_match_plan"].get<bool>());
}

TEST_F(CliCalibrate, TestCutAndCalibrateSpeakGpgl) {
  const std::string cameo = std::string(POPCUT_SOURCE_DIR) + "/configs/devices/silhouette-cameo4.toml";
  CliRun r = popcut("test-cut --device sim --profile " + cameo + " --at 20,30 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  json j = last_json(r.out);
  EXPECT_TRUE(j["sim"]["strokes_match_plan"].get<bool>());
  EXPECT_NEAR(j["box_mm"]["max_x"].get<double>(), 20 + 28 * std::sqrt(3.0) / 2, 1e-3) << "turned: the height along x";
  EXPECT_NE(j["adjust"].back().get<std::string>().find("[gpgl] cutter_offset_mm by 0.05 (0.9 -> 0.95)"),
            std::string::npos)
      << j["adjust"].back();
  const fs::path overlay = dir_ / "sim-cameo4.toml";
  r = popcut("calibrate --device sim --profile " + cameo + " --overlay " + overlay.string() + " --json " + kMeasured);
  ASSERT_EQ(r.code, 0) << r.err;
  j = last_json(r.out);
  // A quarter turn: the frame's 100 mm width ran along the plotter's y.
  EXPECT_DOUBLE_EQ(j["error"]["side_x_mm"].get<double>(), 150);
  EXPECT_NEAR(j["correction"]["scale_y"].get<double>(), 100 / 100.4, 1e-5);
  EXPECT_TRUE(fs::exists(overlay));
  EXPECT_FALSE(fs::exists(cal_dir() / "silhouette-cameo4.toml")) << "the real device's overlay is left alone";
}

TEST_F(CliCalibrate, SimulatedFrameIsNotWrittenIntoARealDevicesOverlay) {
  const std::string cameo = std::string(POPCUT_SOURCE_DIR) + "/configs/devices/silhouette-cameo4.toml";
  CliRun r = popcut("calibrate --device sim --profile " + cameo + " " + kMeasured);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--overlay"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--device sim with the profile of a real device"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(cal_dir() / "silhouette-cameo4.toml")) << "nothing written";
  // Measurements of a frame cut earlier on the device itself are real: --no-cut writes the device's overlay.
  r = popcut("calibrate --device sim --no-cut --profile " + cameo + " " + kMeasured);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(cal_dir() / "silhouette-cameo4.toml"));
}

TEST_F(CliCalibrate, CalibrateWritesTheOverlayAndEveryLaterJobUsesIt) {
  const std::string model = std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/box.json";
  CliRun before = popcut("plan " + model + " --profile " + POPCUT_SOURCE_DIR + "/configs/devices/sim.toml -o " +
                         (dir_ / "before.hpgl").string() + " --json");
  ASSERT_EQ(before.code, 0) << before.err;
  EXPECT_FALSE(last_json(before.out)["calibration"]["calibrated"].get<bool>());
  const CliRun r = popcut("calibrate --device sim --sim-slowdown 1.2 --json " + kMeasured);
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = last_json(r.out);
  EXPECT_EQ(j["format"], "popcut.calibrate.v1");
  EXPECT_NEAR(j["error"]["x_percent"].get<double>(), 0.4, 1e-9);
  EXPECT_NEAR(j["error"]["y_mm"].get<double>(), -0.3, 1e-9);
  // Reports round (report_json.h); the overlay keeps 10 digits.
  EXPECT_NEAR(j["correction"]["scale_x"].get<double>(), 100 / 100.4, 1e-5);
  EXPECT_NEAR(j["correction"]["scale_y"].get<double>(), 150 / 149.7, 1e-5);
  EXPECT_GT(j["error"]["skew_deg"].get<double>(), 0.05);
  EXPECT_EQ(j["timing"]["timed_by"], "sim_clock");
  EXPECT_NEAR(j["timing"]["time_factor"].get<double>(), 1.2, 0.01);
  ASSERT_TRUE(fs::exists(cal_dir() / "sim.toml"));
  const std::string overlay = slurp(cal_dir() / "sim.toml");
  EXPECT_NE(overlay.find("[device]\nscale_x = 0.9960159363"), std::string::npos) << overlay;
  EXPECT_NE(overlay.find("[kinematics]\ntime_factor = 1.2"), std::string::npos) << overlay;
  // plan (and so cut, submit, popcutd) now reads the overlay: calibrated, and other bytes.
  const CliRun after = popcut("plan " + model + " --profile " + POPCUT_SOURCE_DIR + "/configs/devices/sim.toml -o " +
                              (dir_ / "after.hpgl").string() + " --json");
  ASSERT_EQ(after.code, 0) << after.err;
  const json a = last_json(after.out);
  EXPECT_TRUE(a["calibration"]["calibrated"].get<bool>());
  EXPECT_EQ(a["calibration"]["overlay"], (cal_dir() / "sim.toml").string());
  EXPECT_NEAR(a["calibration"]["time_factor"].get<double>(), 1.2, 0.01);
  EXPECT_NE(slurp(dir_ / "before.hpgl"), slurp(dir_ / "after.hpgl"));
  // The sim still cuts a calibrated job exactly as planned; slowed as it was measured, with the factor in the pacing.
  const CliRun cut = popcut("cut " + model + " --device sim --sim-slowdown 1.2 --out " + (dir_ / "c").string());
  EXPECT_EQ(cut.code, 0) << cut.err;
}

TEST_F(CliCalibrate, CalibrateRefusesAbsurdMeasurementsWithExit2) {
  CliRun r = popcut("calibrate --no-cut --measured-x-mm 130 --measured-y-mm 150 --measured-diagonal-mm 180");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--measured-x-mm: 130 mm for the width side (the one with the tick) (cut as 100 mm) is 1.3 "
                       "times its length, outside 0.9–1.1"),
            std::string::npos)
      << r.err;
  r = popcut("calibrate --no-cut --measured-x-mm 100 --measured-y-mm 150 --measured-diagonal-mm 300");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--measured-diagonal-mm: a diagonal of 300 mm is impossible for sides of 100 mm and 150 mm"),
            std::string::npos)
      << r.err;
  r = popcut("calibrate --no-cut --measured-x-mm -100 --measured-y-mm 150 --measured-diagonal-mm 180");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--measured-x-mm: -100 is not a length"), std::string::npos) << r.err;
  r = popcut("calibrate --no-cut --measured-x-mm 100");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("give all three"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(cal_dir() / "sim.toml")) << "nothing written for a refused measurement";
}

TEST_F(CliCalibrate, CalibrateAsksOnAPipeAndComposesWithTheOverlayInEffect) {
  CliRun r = popcut("calibrate --no-cut", "100.4\n149.7\n180.4\n");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("the width side, cut 100 mm (the one with the tick): "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the diagonal, cut 180.28 mm: "), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("the device was off by: x +0.4 % (+0.4 mm over 100 mm), y -0.2 % (-0.3 mm over 150 mm)"),
            std::string::npos)
      << r.out;
  // Cut again with that correction, still 0.1 mm long in x: the two compose.
  r = popcut("calibrate --no-cut --json --measured-x-mm 100.1 --measured-y-mm 150 --measured-diagonal-mm 180.28");
  ASSERT_EQ(r.code, 0) << r.err;
  const json j = last_json(r.out);
  EXPECT_TRUE(j["in_effect"]["calibrated"].get<bool>());
  EXPECT_NEAR(j["correction"]["scale_x"].get<double>(), (100 / 100.4) * (100 / 100.1), 1e-6);
  EXPECT_NE(slurp(cal_dir() / "sim.toml").find("scale_x = 0.99502091"), std::string::npos);
  r = popcut("calibrate --no-cut", "hundred\n");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("'hundred' is not a length in mm"), std::string::npos) << r.err;
}

TEST_F(CliCalibrate, MalformedOverlayStopsEveryJobNamingItsFileAndKey) {
  fs::create_directories(cal_dir());
  std::ofstream(cal_dir() / "sim.toml") << "[device]\nskew_deg = 12\n";
  const CliRun r = popcut("test-cut --device sim");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find((cal_dir() / "sim.toml").string() + ": [device] skew_deg: 12 is out of range -5 to 5"),
            std::string::npos)
      << r.err;
}

TEST_F(CliCalibrate, HelpTextsSayWhatTheCommandsDo) {
  CliRun r = popcut("test-cut --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("square-in-triangle"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--at"), std::string::npos);
  r = popcut("calibrate --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("overlay"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--measured-diagonal-mm"), std::string::npos);
  EXPECT_NE(r.out.find("--no-cut"), std::string::npos);
}

}  // namespace
