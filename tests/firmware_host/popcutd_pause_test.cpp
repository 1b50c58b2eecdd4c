// popcutd pause and continue end to end: a real daemon, a slowed simulated cutter, kill -9 while paused.
#include <gtest/gtest.h>
#include <signal.h>

#include <sstream>
#include <string>

#include "popcutd_fixture.h"
#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::read_file;
using popcut::testing::Reply;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-change-me-0123456789";
const std::string kAdmin = "admin-change-me-0123456789";
const std::string kOther = "other-kiosk-0123456789";

// One simulated device; time_scale > 0 runs it in wall-clock time, slowed, so the castle takes minutes.
std::string config(const TempDir& dir, double time_scale, double slowdown) {
  std::ostringstream o;
  o << "[server]\ndata_dir = \"unused\"\n"
    << "[[device]]\nname = \"slow\"\nprofile = \"" << kSrc << "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
    << "sim_time_scale = " << time_scale << "\nsim_slowdown = " << slowdown << "\n"
    << "[[token]]\nname = \"kiosk\"\ntoken = \"" << kKiosk << "\"\n"
    << "[[token]]\nname = \"other\"\ntoken = \"" << kOther << "\"\n"
    << "[[token]]\nname = \"admin\"\ntoken = \"" << kAdmin << "\"\nrole = \"admin\"\n";
  return dir.write(time_scale > 0 ? "slow.toml" : "fast.toml", o.str());
}

std::string submission(const std::string& example, const std::string& name) {
  return json{{"model", json::parse(read_file(kSrc + "/examples/" + example))}, {"device", "slow"}, {"name", name}}
      .dump();
}

// The shared end-to-end fixture (a data directory, start, job, submit) and a job's actions.
class PopcutdPause : public popcut::testing::e2e::Popcutd {
 protected:
  static Reply act(httplib::Client& c, std::int64_t id, const std::string& what) {
    return post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/" + what, "");
  }
};

TEST_F(PopcutdPause, PauseMidCutSurvivesKillAndContinueCutsOnlyTheRest) {
  std::int64_t id = 0, box = 0, paused_after = 0, total = 0;
  {
    // Slowed 8 times the castle takes about 270 s; a pause waits for the device to cut what its
    // 1 KiB buffer holds (a third of the job), so it lands mid-cut and well within the wait below.
    const auto d = start(config(dir_, 1.0, 8.0));
    httplib::Client c = d->client(kKiosk);
    id = submit(c, submission("voxel/castle.json", "castle"));
    ASSERT_TRUE(wait_until([&] {
      const json j = job(c, id);
      return j["state"] == "cutting" && j.value("strokes_sent", 0) >= 2;
    })) << d->log();
    httplib::Client other = d->client(kOther);
    EXPECT_NE(act(other, id, "pause").status, 202) << "another kiosk's token may not pause the job";
    EXPECT_EQ(act(c, id, "continue").status, 409) << "a cutting job is not paused: nothing to continue";
    const Reply p = act(c, id, "pause");
    EXPECT_EQ(p.status, 202) << p.body.dump();
    ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "paused"; }, 300)) << d->log();
    const json j = job(c, id);
    paused_after = j.value("strokes_sent", std::int64_t{0});
    total = j.value("strokes_total", std::int64_t{0});
    EXPECT_LT(paused_after, total) << "paused mid-cut: " << j.dump();
    EXPECT_EQ(j["resume_from"], paused_after) << "continue starts after the last stroke cut";
    EXPECT_EQ(j["strokes_executed"], paused_after) << "the device drained: every stroke sent is executed";
    EXPECT_EQ(act(c, id, "pause").status, 409) << "a paused job does not pause again";
    // The paused job keeps the device: its half-cut sheet is on it.
    box = submit(c, submission("voxel/box.json", "box"));
    std::this_thread::sleep_for(std::chrono::seconds(2));
    EXPECT_EQ(job(c, box)["state"], "ready") << "nothing is cut onto a paused job's sheet";
    EXPECT_EQ(d->stop(SIGKILL), 128 + SIGKILL);
  }
  const auto d = start(config(dir_, 0, 1));
  httplib::Client c = d->client(kKiosk);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  json j = job(c, id);
  EXPECT_EQ(j["state"], "paused") << "still paused after kill -9 and a restart: " << j.dump();
  EXPECT_EQ(j["strokes_sent"], paused_after) << "and not cut on unasked";
  EXPECT_EQ(job(c, box)["state"], "ready") << "the device stays reserved across the restart";
  EXPECT_EQ(act(c, 999999, "continue").status, 404);
  EXPECT_EQ(act(c, 999999, "pause").status, 404);
  const Reply r = act(c, id, "continue");
  EXPECT_EQ(r.status, 200) << r.body.dump();
  ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "done"; })) << d->log();
  j = job(c, id);
  EXPECT_EQ(j["resume_from"], paused_after) << "the continued run started after the paused one's last stroke";
  EXPECT_EQ(j["strokes_sent"], total);
  EXPECT_EQ(j.value("sim_match", false), true) << "the continued run cut exactly the rest of the plan: " << j.dump();
  ASSERT_TRUE(wait_until([&] { return job(c, box)["state"] == "done"; })) << "then the device takes the next job";
  EXPECT_EQ(act(c, id, "continue").status, 409) << "a done job does not continue";
  EXPECT_EQ(act(c, id, "pause").status, 409) << "nor pause";
}

TEST_F(PopcutdPause, ReadyJobPausesAtOnceAndCancelEndsAPausedJob) {
  const auto d = start(config(dir_, 1.0, 20.0));
  httplib::Client c = d->client(kKiosk);
  httplib::Client admin = d->client(kAdmin);
  ASSERT_EQ(post_json(admin, "/api/v1/devices/slow/pause", "").status, 200) << "hold the device: jobs stay ready";
  const std::int64_t id = submit(c, submission("voxel/box.json", "box"));
  ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "ready"; })) << d->log();
  const Reply p = act(admin, id, "pause");
  EXPECT_EQ(p.status, 200) << "an admin pauses anyone's job; a ready one at once: " << p.body.dump();
  EXPECT_EQ(job(c, id)["state"], "paused");
  ASSERT_EQ(post_json(admin, "/api/v1/devices/slow/resume", "").status, 200);
  std::this_thread::sleep_for(std::chrono::seconds(1));
  EXPECT_EQ(job(c, id)["state"], "paused") << "a paused job is never cut unasked";
  const Reply x = act(c, id, "cancel");
  EXPECT_EQ(x.status, 202) << x.body.dump();
  EXPECT_EQ(job(c, id)["state"], "cancelled") << "cancel, unlike pause, ends the job";
  EXPECT_EQ(act(c, id, "continue").status, 409);
}

}  // namespace
