// Nested copies through popcutd end to end: killed half way through the sheet, resumed, every card cut once.
#include <gtest/gtest.h>

#include <csignal>
#include <sstream>
#include <string>

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

// One simulated cutter, in wall-clock time and slowed (time_scale > 0) or as fast as it goes.
std::string config(const TempDir& dir, double time_scale) {
  std::ostringstream o;
  o << "[server]\ndata_dir = \"unused\"\n[[device]]\nname = \"slow\"\nprofile = \"" << kSrc
    << "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
    << "sim_time_scale = " << time_scale << "\nsim_slowdown = " << (time_scale > 0 ? 20 : 1) << "\n"
    << "[[token]]\nname = \"kiosk\"\ntoken = \"" << kKiosk << "\"\n";
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

}  // namespace
