// Nested copies through popcutd end to end: killed half way through the sheet, resumed, every card cut once.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <sstream>
#include <string>
#include <thread>

#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::Reply;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-change-me-0123456789";

const std::string kAdmin = "admin-change-me-0123456789";

// One simulated cutter, in wall-clock time and slowed (time_scale > 0) or as fast as it goes.
std::string config(const TempDir& dir, double time_scale, bool confirm_sheet = false) {
  std::ostringstream o;
  o << "[server]\ndata_dir = \"unused\"\n[[device]]\nname = \"slow\"\nprofile = \"" << kSrc
    << "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
    << "sim_time_scale = " << time_scale << "\nsim_slowdown = " << (time_scale > 0 ? 20 : 1) << "\n"
    << "confirm_sheet = " << (confirm_sheet ? "true" : "false") << "\n"
    << "[[token]]\nname = \"kiosk\"\ntoken = \"" << kKiosk << "\"\n"
    << "[[token]]\nname = \"admin\"\ntoken = \"" << kAdmin << "\"\nrole = \"admin\"\n";
  return dir.write(time_scale > 0 ? "slow.toml" : "fast.toml", o.str());
}

TEST(PopcutdCopies, KilledHalfWayThroughTheSheetAndResumedEveryCardIsCutOnce) {
  TempDir dir("popcutd-copies");
  const std::string data = (dir.path() / "data").string();
  const std::string body = R"({"device": "slow", "copies": 4, "model": )" +
                           popcut::testing::read_file(kSrc + "/examples/voxel/box.json") + "}";
  std::int64_t id = 0, total = 0, seen = 0;
  {
    PopcutdProcess d(POPCUTD, config(dir, 1.0), data);
    httplib::Client c = d.client(kKiosk);
    const Reply r = post_json(c, "/api/v1/jobs", body);
    ASSERT_EQ(r.status, 201) << r.body.dump();
    id = r.body["id"];
    const std::string path = "/api/v1/jobs/" + std::to_string(id);
    // Killed once the first card is behind it: the cut is somewhere on the second or later.
    ASSERT_TRUE(wait_until([&] {
      const json j = get_json(c, path).body;
      total = j.value("strokes_total", std::int64_t{0});
      seen = j.value("strokes_sent", std::int64_t{0});
      return j["state"] == "cutting" && seen > total / 4;
    })) << d.log();
    EXPECT_EQ(d.stop(SIGKILL), 128 + SIGKILL);
  }
  PopcutdProcess d(POPCUTD, config(dir, 0), data);
  httplib::Client c = d.client(kKiosk);
  const std::string path = "/api/v1/jobs/" + std::to_string(id);
  json j = get_json(c, path).body;
  ASSERT_EQ(j["state"], "interrupted") << j.dump();
  EXPECT_LT(j["strokes_sent"].get<std::int64_t>(), total) << "the kill came mid-sheet";
  EXPECT_GE(j["strokes_sent"].get<std::int64_t>(), seen);
  EXPECT_EQ(j["copies"], 4);
  ASSERT_EQ(post_json(c, path + "/resume", "").status, 202);
  ASSERT_TRUE(wait_until([&] { return get_json(c, path).body["state"] == "done"; })) << d.log();
  j = get_json(c, path).body;
  EXPECT_EQ(j["strokes_sent"], total) << "the rest of the sheet, to its last outline";
  EXPECT_TRUE(j["sim_match"].get<bool>()) << "the resumed run cut exactly the nested plan's remaining strokes";
}

// More copies than a sheet holds (box.json: 104 on the sim profile's area): sheet after sheet,
// each on a fresh one, the last with the one left; killed between two sheets, nothing is cut onto
// the full one.
TEST(PopcutdCopies, MoreCopiesThanOneSheetHoldsAreCutSheetAfterSheetEachOnAFreshOne) {
  TempDir dir("popcutd-sheets-of-copies");
  const std::string data = (dir.path() / "data").string();
  const std::string body = R"({"device": "slow", "copies": 209, "model": )" +
                           popcut::testing::read_file(kSrc + "/examples/voxel/box.json") + "}";
  std::int64_t id = 0;
  std::string path;
  const auto awaiting = [](httplib::Client& c) {
    return get_json(c, "/api/v1/devices").body["devices"][0]["sheet"] == "awaiting_sheet";
  };
  json j;
  {
    PopcutdProcess d(POPCUTD, config(dir, 0, true), data);
    httplib::Client c = d.client(kKiosk);
    const Reply r = post_json(c, "/api/v1/jobs", body);
    ASSERT_EQ(r.status, 201) << "more than a sheet holds is no longer refused: " << r.body.dump();
    id = r.body["id"];
    path = "/api/v1/jobs/" + std::to_string(id);
    ASSERT_TRUE(wait_until([&] { return awaiting(c) && get_json(c, path).body["state"] == "ready"; })) << d.log();
    j = get_json(c, path).body;
    EXPECT_EQ(j["sheets"], 3) << j.dump();
    EXPECT_EQ(j["sheet"], 2) << "the first is cut: " << j.dump();
    EXPECT_EQ(d.stop(SIGKILL), 128 + SIGKILL) << "killed between two sheets";
  }
  const std::int64_t per_sheet = j["strokes_sent"], total = j["strokes_total"];
  EXPECT_EQ(total, 2 * per_sheet + 8) << "two full sheets and one card (box.json: 8 strokes): " << j.dump();
  PopcutdProcess d(POPCUTD, config(dir, 0, true), data);
  httplib::Client c = d.client(kKiosk);
  httplib::Client admin = d.client(kAdmin);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  EXPECT_TRUE(awaiting(c)) << "still waiting for a fresh sheet after the restart";
  EXPECT_EQ(get_json(c, path).body["strokes_sent"], per_sheet) << "nothing cut onto the full sheet";
  for (int sheet = 2; sheet <= 3; ++sheet) {
    ASSERT_EQ(post_json(admin, "/api/v1/devices/slow/sheet", "").status, 200);
    ASSERT_TRUE(wait_until([&] {
      const json now = get_json(c, path).body;
      return awaiting(c) && (now["state"] == "done" || now["strokes_sent"] == sheet * per_sheet);
    })) << d.log();
  }
  j = get_json(c, path).body;
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_EQ(j["strokes_sent"], total);
  EXPECT_EQ(j["sheet"], 3);
  EXPECT_TRUE(j["sim_match"].get<bool>()) << "the last sheet cut exactly its plan";
  const std::string logs = d.log();  // both processes': one log file per data directory
  for (const std::int64_t from : {std::int64_t{1}, per_sheet + 1, 2 * per_sheet + 1}) {
    const std::string run = "job " + std::to_string(id) + ": cutting on slow from stroke " + std::to_string(from) + " ";
    EXPECT_NE(logs.find(run), std::string::npos) << run << "\n" << logs;
    EXPECT_EQ(logs.find(run), logs.rfind(run)) << "each sheet once: " << run;
  }
}

// popcut submit --copies sends them; 0 is refused before anything is sent.
TEST(PopcutdCopies, PopcutSubmitSendsCopies) {
  TempDir dir("popcutd-submit-copies");
  PopcutdProcess d(POPCUTD, config(dir, 0), (dir.path() / "data").string());
  const std::string out = (dir.path() / "out").string();
  const std::string submit = std::string(POPCUT_CLI) + " submit " + kSrc + "/examples/voxel/box.json --device slow" +
                             " --server http://127.0.0.1:" + std::to_string(d.port()) + " --token " + kKiosk;
  ASSERT_EQ(WEXITSTATUS(std::system((submit + " --copies 3 --wait --json >" + out + " 2>&1").c_str())), 0)
      << popcut::testing::read_file(out);
  const json j = json::parse(popcut::testing::read_file(out));
  EXPECT_EQ(j["copies"], 3);
  EXPECT_EQ(j["sheets"], 1);
  EXPECT_EQ(j["state"], "done");
  EXPECT_EQ(j["strokes_total"], 24) << "three box cards of 8 strokes";
  EXPECT_EQ(WEXITSTATUS(std::system((submit + " --copies 0 >" + out + " 2>&1").c_str())), 2);
  EXPECT_NE(popcut::testing::read_file(out).find("--copies"), std::string::npos) << popcut::testing::read_file(out);
}

}  // namespace
