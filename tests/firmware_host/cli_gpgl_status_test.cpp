// popcut cut on a simulated GP-GL device: the whole card, no sheet loaded before the job, the pause key during it and
// the resume that finishes it.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli_run.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using popcut::testing::CliRun;
using popcut::testing::slurp;

class CliGpglStatus : public popcut::testing::CliFixture {
 protected:
  CliGpglStatus() : CliFixture("popcut-gpgl") {}
  // popcut cut of the townhouse on a simulated Cameo 4, into DIR/NAME, with `extra` options.
  CliRun cut(const std::string& name, const std::string& extra = "") const {
    return run(std::string("cut ") + POPCUT_SOURCE_DIR + "/examples/voxel/townhouse.json --profile " +
               POPCUT_SOURCE_DIR + "/configs/devices/silhouette-cameo4.toml --device sim --no-progress --out " +
               (dir_ / name).string() + " " + extra);
  }
  json report(const std::string& name) const { return json::parse(slurp(dir_ / name / "report.json")); }
};

TEST_F(CliGpglStatus, CutsTheTownhouseOnASimulatedCameo4) {
  const CliRun r = cut("whole");
  ASSERT_EQ(r.code, 0) << r.err;
  const json rep = report("whole");
  EXPECT_TRUE(rep["sim"]["strokes_match_plan"].get<bool>());
  EXPECT_EQ(rep["sim"]["overflow_bytes"], 0);
  EXPECT_EQ(rep["sent"]["drained_by"], "esc_enq") << "the device said \"ready\" at the end";
  EXPECT_TRUE(rep["sent"]["device_stop"].is_null());
  // The job file is named for its language, and the report says which and how big, not "hpgl_bytes".
  EXPECT_FALSE(fs::exists(dir_ / "whole" / "job.hpgl"));
  const std::string job = slurp(dir_ / "whole" / "job.gpgl");
  EXPECT_EQ(rep["language"], "gpgl");
  EXPECT_EQ(rep["job_bytes"].get<std::size_t>(), job.size());
  EXPECT_FALSE(rep.contains("hpgl_bytes"));
  EXPECT_NE(r.err.find("wrote " + (dir_ / "whole" / "job.gpgl").string()), std::string::npos) << r.err;
}

TEST_F(CliGpglStatus, NoSheetLoadedIsExit3BeforeAnyByte) {
  const CliRun r = cut("empty", "--sim-tray-empty-after 0");
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("no sheet loaded"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing was sent: run the same command again"), std::string::npos) << r.err;
  const json rep = report("empty");
  EXPECT_EQ(rep["sent"]["device_stop"], "tray_empty");
  EXPECT_EQ(rep["sent"]["bytes"], 0);
  EXPECT_EQ(rep["sim"]["strokes"], 0) << "nothing cut";
  EXPECT_EQ(rep["sim"]["knife_downs"], 0);
}

// The pause key mid-job: exit 3 with the device's reason, the knife-up sent, and the resume point
// the message gives finishes the card exactly on a fresh device.
TEST_F(CliGpglStatus, ThePauseKeyMidJobIsExit3AndItsResumeCutsTheRest) {
  const CliRun r = cut("paused", "--sim-pause-after 300");
  ASSERT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("the device stopped the job (sim): the device is paused (ESC ENQ answer)"), std::string::npos)
      << r.err;
  const json rep = report("paused");
  EXPECT_EQ(rep["sent"]["device_stop"], "paused");
  EXPECT_TRUE(rep["sent"]["abort_sent"].get<bool>()) << "the knife-up went out";
  EXPECT_FALSE(rep["sent"]["cancelled"].get<bool>());
  const std::size_t m = rep["sent"]["last_stroke_sent"];
  std::smatch k;
  ASSERT_TRUE(std::regex_search(r.err, k,
                                std::regex("goes on cutting, finish with the same command and --resume-from "
                                           "([0-9]+)")))
      << r.err;
  EXPECT_EQ(std::stoul(k[1]), m + 1) << "M+1 for a device that keeps its buffer";
  const CliRun rest = cut("rest", "--resume-from " + std::string(k[1]));
  ASSERT_EQ(rest.code, 0) << rest.err;
  EXPECT_TRUE(report("rest")["sim"]["strokes_match_plan"].get<bool>()) << "strokes M+1.. exactly as planned";
}

// The simulator's line faults work on a GP-GL device as on an HP-GL one.
TEST_F(CliGpglStatus, ADeviceThatStopsAnsweringOrHangsUpIsExit3WithTheCounts) {
  const CliRun stopped = cut("stopped", "--sim-stop-after 300");
  EXPECT_EQ(stopped.code, 3) << stopped.err;
  EXPECT_NE(stopped.err.find("the device stopped answering: no answer to ESC ENQ"), std::string::npos) << stopped.err;
  EXPECT_NE(stopped.err.find("--resume-from"), std::string::npos) << stopped.err;
  const CliRun dropped = cut("dropped", "--sim-drop-after 300");
  EXPECT_EQ(dropped.code, 3) << dropped.err;
  EXPECT_NE(dropped.err.find("connection dropped"), std::string::npos) << dropped.err;
  EXPECT_LE(report("dropped")["sent"]["bytes"].get<std::size_t>(), 300u);
  const CliRun slow = cut("slow", "--sim-slowdown 1.2");
  EXPECT_EQ(slow.code, 0) << slow.err;
  EXPECT_TRUE(report("slow")["sim"]["strokes_match_plan"].get<bool>());
}

}  // namespace
