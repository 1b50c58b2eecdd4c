// popcutd end to end on loopback: real daemon processes, simulated cutters, crashes, load and bad requests.
#include <gtest/gtest.h>
#include <signal.h>

#include <atomic>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "cut_job.h"
#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcutd_fixture.h"
#include "popcutd_process.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::read_file;
using popcut::testing::Reply;
using popcut::testing::TempDir;
using popcut::testing::wait_until;
using namespace popcut::testing::e2e;

// A config like the sample with one device whose simulated cut runs in wall-clock time, slowed:
// the castle then takes minutes, so a test can act in the middle of it without racing it.
std::string slow_config(const TempDir& dir, double time_scale, double slowdown) {
  std::ostringstream o;
  o << "[server]\ndata_dir = \"unused\"\n"
    << "[[device]]\nname = \"slow\"\nprofile = \"" << kSrc << "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
    << "sim_time_scale = " << time_scale << "\nsim_slowdown = " << slowdown << "\n"
    << "[[token]]\nname = \"kiosk\"\ntoken = \"" << kKiosk << "\"\n"
    << "[[token]]\nname = \"other\"\ntoken = \"other-kiosk-0123456789\"\n"
    << "[[token]]\nname = \"admin\"\ntoken = \"" << kAdmin << "\"\nrole = \"admin\"\n";
  return dir.write(time_scale > 0 ? "slow.toml" : "fast.toml", o.str());
}

TEST_F(Popcutd, TwoDevicesManyJobsInOrder) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  httplib::Client c = d->client(kKiosk);
  const std::vector<std::string> models = {"voxel/box.json", "voxel/pyramid.json", "faces/porch.json",
                                           "voxel/townhouse.json"};
  std::vector<std::int64_t> ids;
  std::map<std::int64_t, std::string> target;
  for (int i = 0; i < 12; ++i) {
    const std::string model = example(models[static_cast<std::size_t>(i) % models.size()]);
    const bool by_profile = i % 3 == 2;
    const std::string dev = i % 2 ? "sim-b" : "sim-a";
    ids.push_back(submit(
        c, submission(model, by_profile ? "profile" : "device", by_profile ? "sim" : dev, "job" + std::to_string(i))));
    target[ids.back()] = by_profile ? "" : dev;
  }
  ASSERT_TRUE(wait_until([&] {
    for (std::int64_t id : ids) {
      if (!final_state(job(c, id))) return false;
    }
    return true;
  })) << "every job finishes; log:\n"
      << d->log();
  std::map<std::string, std::vector<std::pair<double, std::int64_t>>> starts;  // device -> (started_at, id)
  for (std::int64_t id : ids) {
    const json j = job(c, id);
    EXPECT_EQ(j["state"], "done") << "job " << id << " is done: " << j.dump();
    EXPECT_EQ(j.value("sim_match", false), true) << "job " << id << ": the simulated cutter cut exactly the plan";
    EXPECT_EQ(j["strokes_sent"], j["strokes_total"]) << "job " << id << ": every stroke sent";
    EXPECT_EQ(j["strokes_executed"], j["strokes_total"])
        << "job " << id << ": the device confirmed it executed every stroke";
    if (!target[id].empty()) {
      EXPECT_EQ(j["cut_on"], target[id]) << "job " << id << " was cut on the device it named";
    }
    starts[j["cut_on"].get<std::string>()].push_back({j["started_at"].get<double>(), id});
  }
  EXPECT_EQ(starts.size(), 2u) << "both devices cut";
  for (auto& [dev, list] : starts) {
    std::sort(list.begin(), list.end());
    for (std::size_t i = 1; i < list.size(); ++i) {
      EXPECT_LT(list[i - 1].second, list[i].second) << dev << " cut its jobs in the order they were queued";
    }
  }
  httplib::Client admin = d->client(kAdmin);
  const Reply devices = get_json(admin, "/api/v1/devices");
  ASSERT_EQ(devices.body["devices"].size(), 2u) << "two devices listed";
  EXPECT_EQ(devices.body["devices"][0]["state"], "idle") << "idle after the queue drained";
  EXPECT_EQ(d->stop(SIGTERM), 0) << "SIGTERM with nothing cutting exits 0";
}

TEST_F(Popcutd, KillDuringCutThenRestartAndResume) {
  const std::string slow = slow_config(dir_, 1.0, 20.0);
  const std::string castle = example("voxel/castle.json");
  std::int64_t id = 0, seen = 0, total = 0;
  {
    const auto d = start(slow);
    httplib::Client c = d->client(kKiosk);
    id = submit(c, submission(castle, "device", "slow", "castle"));
    // The castle's 93 strokes take about ten minutes on this device: a few strokes in, kill it.
    ASSERT_TRUE(wait_until([&] {
      const json j = job(c, id);
      seen = j.value("strokes_sent", std::int64_t{0});
      total = j.value("strokes_total", std::int64_t{0});
      return j["state"] == "cutting" && seen >= 2;
    })) << "the cut starts; log:\n"
        << d->log();
    EXPECT_EQ(d->stop(SIGKILL), 128 + SIGKILL) << "popcutd dies of SIGKILL";
  }
  const auto d = start(slow_config(dir_, 0, 1));
  httplib::Client c = d->client(kKiosk);
  json j = job(c, id);
  EXPECT_EQ(j["state"], "interrupted") << "after kill -9 the cutting job is interrupted: " << j.dump();
  const std::int64_t sent = j.value("strokes_sent", std::int64_t{0});
  EXPECT_GE(sent, seen) << "no stroke reported sent is forgotten";
  EXPECT_LT(sent, total) << "the kill came mid-cut (else this test proves nothing)";
  EXPECT_EQ(j["resume_from"], sent) << "it will resume at the first stroke not fully sent";
  EXPECT_TRUE(j["strokes_executed"].is_null())
      << "a cut killed midway never learnt what the device executed: " << j.dump();
  EXPECT_NE(d->log().find("recovered after an unclean stop: 1 cutting -> interrupted"), std::string::npos)
      << "the restart says it recovered the job: " << d->log();
  // The device goes on with other work while the interrupted job waits to be asked.
  const std::int64_t other = submit(c, submission(example("voxel/box.json"), "device", "slow", "box"));
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, other)); })) << "the next job is cut";
  EXPECT_EQ(job(c, other)["state"], "done") << "the device cut the next job";
  EXPECT_EQ(job(c, id)["state"], "interrupted") << "the interrupted job is not resumed unasked";
  const Reply unknown = post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", R"({"from": "executed"})");
  EXPECT_EQ(unknown.status, 409) << "no executed point to resume from: the crash came before the device was asked: "
                                 << unknown.body.dump();
  EXPECT_EQ(unknown.body["error"].value("field", ""), "from") << unknown.body.dump();
  EXPECT_NE(unknown.body["error"].value("message", "").find("executed are unknown"), std::string::npos)
      << "says why: " << unknown.body.dump();
  EXPECT_EQ(job(c, id)["state"], "interrupted") << "a refused resume changes nothing";
  const Reply r = post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", "");
  EXPECT_EQ(r.status, 202) << "resume accepted: " << r.body.dump();
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); })) << "the resumed job finishes";
  j = job(c, id);
  EXPECT_EQ(j["state"], "done") << "the resumed job is done: " << j.dump();
  EXPECT_EQ(j["strokes_sent"], total) << "every stroke sent in the end";
  EXPECT_EQ(j["resume_from"], sent) << "the second cut started at the first stroke not fully sent";
  EXPECT_EQ(j["resume_point"], "received") << "an empty body resumes after the strokes received: " << j.dump();
  EXPECT_EQ(j.value("sim_match", false), true) << "the resumed cut is exactly the plan's remaining strokes";
  EXPECT_EQ(post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", "").body["error"]["code"], "conflict")
      << "a done job does not resume";
}

// Two simulated cutters with one profile, "sim-a" and "sim-b": slowed to minutes for the castle
// (time_scale > 0), or as fast as they go.
std::string two_cutters_config(const TempDir& dir, double time_scale) {
  std::ostringstream o;
  o << "[server]\ndata_dir = \"unused\"\n";
  for (const char* name : {"sim-a", "sim-b"}) {
    o << "[[device]]\nname = \"" << name << "\"\nprofile = \"" << kSrc
      << "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
      << "sim_time_scale = " << time_scale << "\nsim_slowdown = " << (time_scale > 0 ? 20 : 1) << "\n";
  }
  o << "[[token]]\nname = \"kiosk\"\ntoken = \"" << kKiosk << "\"\n"
    << "[[token]]\nname = \"admin\"\ntoken = \"" << kAdmin << "\"\nrole = \"admin\"\n";
  return dir.write(time_scale > 0 ? "two-slow.toml" : "two-fast.toml", o.str());
}

// A job for a profile, half cut on one cutter when popcutd is killed: resumed, it waits for that
// cutter (here paused) and is never finished on the other, idle one. It used to be.
TEST_F(Popcutd, AResumedJobWaitsForTheCutterHoldingItsSheet) {
  std::int64_t id = 0;
  std::string first;
  {
    const auto d = start(two_cutters_config(dir_, 1.0));
    httplib::Client c = d->client(kKiosk);
    id = submit(c, submission(example("voxel/castle.json"), "profile", "sim", "castle"));
    ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "cutting" && job(c, id)["strokes_sent"] >= 2; }))
        << d->log();
    first = job(c, id)["cut_on"];
    EXPECT_EQ(d->stop(SIGKILL), 128 + SIGKILL);
  }
  const std::string other = first == "sim-a" ? "sim-b" : "sim-a";
  const auto d = start(two_cutters_config(dir_, 0));
  httplib::Client c = d->client(kKiosk);
  httplib::Client admin = d->client(kAdmin);
  json j = job(c, id);
  ASSERT_EQ(j["state"], "interrupted") << j.dump();
  EXPECT_EQ(j["bound_to"], first) << "the API says which cutter holds the sheet: " << j.dump();
  ASSERT_EQ(post_json(admin, "/api/v1/devices/" + first + "/pause", "").status, 200);
  ASSERT_EQ(post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", "").status, 202);
  // The other cutter is idle and takes other work meanwhile.
  const std::int64_t box = submit(c, submission(example("voxel/box.json"), "profile", "sim", "box"));
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, box)); })) << d->log();
  EXPECT_EQ(job(c, box)["cut_on"], other) << "the idle cutter cut the next job";
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  j = job(c, id);
  EXPECT_EQ(j["state"], "ready") << "the resumed job waits for its cutter: " << j.dump();
  EXPECT_EQ(j["cut_on"], first) << j.dump();
  EXPECT_EQ(j["bound_to"], first) << j.dump();
  EXPECT_TRUE(j["eta_s"].is_null()) << "its cutter is paused: no forecast: " << j.dump();
  ASSERT_EQ(post_json(admin, "/api/v1/devices/" + first + "/resume", "").status, 200);
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); })) << d->log();
  j = job(c, id);
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_EQ(j["cut_on"], first) << "finished on the cutter holding its sheet: " << j.dump();
  EXPECT_TRUE(j["bound_to"].is_null()) << "done: no sheet waits any more: " << j.dump();
  EXPECT_EQ(j.value("sim_match", false), true) << j.dump();
  EXPECT_EQ(d->stop(SIGTERM), 0);
}

TEST_F(Popcutd, SigtermStopsTheCutSafelyAndCancelStopsAJob) {
  const std::string slow = slow_config(dir_, 1.0, 20.0);
  const std::string castle = example("voxel/castle.json");
  std::int64_t a = 0, b = 0;
  {
    const auto d = start(slow);
    httplib::Client c = d->client(kKiosk);
    a = submit(c, submission(castle, "device", "slow", "a"));
    b = submit(c, submission(castle, "device", "slow", "b"));
    ASSERT_TRUE(wait_until([&] { return job(c, a)["state"] == "cutting" && job(c, a)["strokes_sent"] >= 1; }))
        << "a is cutting";
    EXPECT_EQ(job(c, b)["place_in_line"], 0) << "b is next in line";
    const Reply cancel = post_json(c, "/api/v1/jobs/" + std::to_string(a) + "/cancel", "");
    EXPECT_EQ(cancel.status, 202) << "cancel accepted: " << cancel.body.dump();
    ASSERT_TRUE(wait_until([&] { return final_state(job(c, a)); })) << "the cancelled cut stops";
    EXPECT_EQ(job(c, a)["state"], "cancelled") << "a was cancelled mid-cut";
    EXPECT_LT(job(c, a)["strokes_sent"], job(c, a)["strokes_total"]) << "a stopped before its end";
    ASSERT_TRUE(wait_until([&] { return job(c, b)["state"] == "cutting" && job(c, b)["strokes_sent"] >= 1; }))
        << "b is cutting next";
    EXPECT_EQ(d->stop(SIGTERM), 0) << "SIGTERM during a cut exits 0 once the cut is stopped";
  }
  const auto d = start(slow);
  httplib::Client c = d->client(kKiosk);
  const json j = job(c, b);
  EXPECT_EQ(j["state"], "interrupted") << "SIGTERM leaves the cut interrupted, resumable: " << j.dump();
  EXPECT_NE(j["error"]["message"].get<std::string>().find("knife was lifted"), std::string::npos)
      << "it says the knife was lifted";
  EXPECT_EQ(d->log().find("recovered"), std::string::npos) << "a clean stop leaves nothing to recover";
}

TEST_F(Popcutd, HundredConcurrentSubmissionsNoneLostOrDuplicated) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  const std::string box = example("voxel/box.json");
  std::vector<std::thread> threads;
  std::mutex m;
  std::vector<std::int64_t> ids;
  std::atomic<int> refused{0};
  for (int t = 0; t < 10; ++t) {
    threads.emplace_back([&, t] {
      httplib::Client c = d->client(kKiosk);
      for (int i = 0; i < 10; ++i) {
        const Reply r =
            post_json(c, "/api/v1/jobs",
                      submission(box, "profile", "sim", "load-" + std::to_string(t) + "-" + std::to_string(i)));
        if (r.status != 201) {
          ++refused;
          continue;
        }
        std::lock_guard lock(m);
        ids.push_back(r.body["id"].get<std::int64_t>());
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(refused, 0) << "every submission accepted";
  EXPECT_EQ(std::set<std::int64_t>(ids.begin(), ids.end()).size(), 100u) << "100 distinct ids";
  httplib::Client admin = d->client(kAdmin);
  ASSERT_TRUE(wait_until([&] {
    const json all = get_json(admin, "/api/v1/jobs?limit=1000").body["jobs"];
    return std::all_of(all.begin(), all.end(), [](const json& j) { return final_state(j); });
  })) << "all jobs finish";
  const json all = get_json(admin, "/api/v1/jobs?limit=1000").body["jobs"];
  ASSERT_EQ(all.size(), 100u) << "exactly 100 jobs in the store";
  std::set<std::string> names;
  for (const json& j : all) {
    names.insert(j["name"].get<std::string>());
    EXPECT_EQ(j["state"], "done") << "job " << j["id"] << " done";
    EXPECT_EQ(j.value("sim_match", false), true) << "job " << j["id"] << " cut as planned";
  }
  EXPECT_EQ(names.size(), 100u) << "each submission is one job";
  const std::string metrics = d->client("").Get("/metrics")->body;
  EXPECT_NE(metrics.find("popcutd_jobs{state=\"done\"} 100"), std::string::npos) << "metrics count 100 done jobs:\n"
                                                                                 << metrics;
}

TEST_F(Popcutd, BadRequestsGetDocumentedCodesAndTheDaemonKeepsServing) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  httplib::Client c = d->client(kKiosk);
  httplib::Client none = d->client("");
  httplib::Client wrong = d->client("wrong-token-0123456789");
  const std::string box = example("voxel/box.json");
  const std::int64_t mine = submit(c, submission(box, "device", "sim-a", "mine"));
  struct Case {
    httplib::Client* client;
    std::string method, path, body;
    int status;
    std::string code;
  };
  const std::string big(2 << 20, ' ');
  json huge = json::parse(box);
  huge["voxel_mm"] = 200;
  const std::string huge_box = huge.dump();
  // 100,000 levels inside the model: its copy for the job (a recursive dump) overflowed the stack.
  const std::string deep_model = R"({"device": "sim-a", "model": {"format": "popcut.voxel.v1", "heights": )" +
                                 std::string(100000, '[') + std::string(100000, ']') + "}}";
  const std::vector<Case> cases = {
      {&c, "POST", "/api/v1/jobs", deep_model, 400, "bad_json"},
      {&c, "POST", "/api/v1/jobs", "{not json", 400, "bad_json"},
      {&c, "POST", "/api/v1/jobs", "[1,2]", 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs", R"({"device": 5, "model": {}})", 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-a"})", 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-a", "model": "box"})", 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-a", "profile": "sim", "model": {}})", 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-a", "model": {}, "colour": 1})", 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-a", "model": {"format": "popcut.voxel.v1", "heights": "x"}})",
       422, "bad_model"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-z", "model": {}})", 422, "no_device"},
      {&c, "POST", "/api/v1/jobs", R"({"profile": "roland", "model": {}})", 422, "no_device"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "../sim-a", "model": {}})", 400, "bad_name"},
      {&c, "POST", "/api/v1/jobs", submission(box, "device", "sim-a", "../../etc/passwd"), 400, "bad_name"},
      {&c, "POST", "/api/v1/jobs", submission(box, "device", "sim-a", "a/b"), 400, "bad_name"},
      {&c, "POST", "/api/v1/jobs",
       R"({"device": "sim-a", "model": {"format": "popcut.voxel.v1", "voxel_mm": 1, "grid": {"width": 101, "depth": 100, "height": 100}, "heights": [[1]]}})",
       413, "model_too_complex"},
      {&c, "POST", "/api/v1/jobs", big, 413, "too_large"},
      {&none, "GET", "/api/v1/jobs", "", 401, "unauthorized"},
      {&wrong, "GET", "/api/v1/jobs", "", 401, "unauthorized"},
      {&wrong, "POST", "/api/v1/jobs", submission(box, "device", "sim-a", "x"), 401, "unauthorized"},
      {&c, "GET", "/api/v1/jobs/999999", "", 404, "not_found"},
      {&c, "GET", "/api/v1/jobs/99999999999999999999", "", 404, "not_found"},
      {&c, "GET", "/api/v1/jobs/abc", "", 404, "not_found"},
      {&c, "GET", "/api/v1/jobs?limit=-1", "", 400, "bad_request"},
      {&c, "GET", "/api/v1/jobs/" + std::to_string(mine) + "/preview.png?angle=270", "", 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs/999999/cancel", "", 404, "not_found"},
      {&c, "POST", "/api/v1/devices/sim-a/pause", "", 403, "forbidden"},
      {&c, "GET", "/api/v1/examples/..%2F..%2Fconfigs%2Fpopcutd.toml", "", 404, "not_found"},
      {&c, "GET", "/kiosk/../../configs/popcutd.toml", "", 404, "not_found"},
      {&c, "GET", "/api/v1/nothing", "", 404, "not_found"},
      // A model whose sheet (800 x 2000 mm) does not fit the sim cutter (600 x 1000 mm): refused
      // at once, not accepted and failed at planning.
      {&c, "POST", "/api/v1/jobs", submission(huge_box, "device", "sim-a", "huge"), 422, "bad_model"},
      {&c, "POST", "/api/v1/jobs", submission(huge_box, "profile", "sim", "huge"), 422, "bad_model"},
      {&c, "POST", "/api/v1/render/pattern.svg", "{not json", 400, "bad_json"},
      {&c, "POST", "/api/v1/render/preview.png", "not json at all", 400, "bad_json"},
      {&c, "POST", "/api/v1/render/pattern.svg", R"({"format": "popcut.voxel.v1", "heights": "x"})", 422, "bad_model"},
      {&c, "POST", "/api/v1/import", box, 400, "bad_request"},
      // A key twice in one object would silently keep the last; a query parameter twice, the first.
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-a", "device": "sim-b", "model": )" + box + "}", 400,
       "bad_request"},
      {&c, "POST", "/api/v1/jobs", R"({"device": "sim-a", "model": {"format": "popcut.voxel.v1", "format": "x"}})", 400,
       "bad_request"},
      {&c, "GET", "/api/v1/jobs/" + std::to_string(mine) + "/preview.png?angle=10&angle=20", "", 400, "bad_request"},
      {&c, "GET", "/api/v1/jobs?limit=1&limit=2", "", 400, "bad_request"},
      {&c, "GET", "/api/v1/jobs?foo=1", "", 400, "bad_request"},
      {&c, "GET", "/api/v1/jobs/" + std::to_string(mine) + "/preview.png?zoom=2", "", 400, "bad_request"},
      {&c, "GET", "/api/v1/devices?limit=5", "", 400, "bad_request"},
      // Names are labels: any text, but not empty, not control characters, not direction overrides.
      {&c, "POST", "/api/v1/jobs", submission(box, "device", "sim-a", ""), 400, "bad_request"},
      {&c, "POST", "/api/v1/jobs", submission(box, "device", "sim-a", std::string("a\x01") + "b"), 400, "bad_name"},
      {&c, "POST", "/api/v1/jobs", submission(box, "device", "sim-a", "abc\u202e"), 400, "bad_name"},
      {&c, "POST", "/api/v1/jobs", submission(box, "device", "sim-a", std::string(65, 'n')), 400, "bad_name"},
  };
  for (const Case& k : cases) {
    const Reply r = k.method == "GET" ? get_json(*k.client, k.path) : post_json(*k.client, k.path, k.body);
    EXPECT_EQ(r.status, k.status) << k.method << " " << k.path << " " << k.body.substr(0, 120) << " -> "
                                  << r.body.dump();
    EXPECT_EQ(r.body.is_object() && r.body.contains("error") ? r.body["error"].value("code", "") : "", k.code)
        << k.method << " " << k.path << " " << k.body.substr(0, 120)
        << " answers with the documented code: " << r.body.dump();
  }
  const Reply unicode = post_json(c, "/api/v1/jobs", submission(box, "device", "sim-a", "café 城 2"));
  EXPECT_EQ(unicode.status, 201) << "a name in any script is a fine label: " << unicode.body.dump();
  EXPECT_EQ(unicode.body.value("name", ""), "café 城 2") << "and is kept as given";
  const Reply unnamed = post_json(c, "/api/v1/jobs", json{{"device", "sim-a"}, {"model", json::parse(box)}}.dump());
  EXPECT_EQ(unnamed.body.value("name", ""), json::parse(box)["name"])
      << "an unnamed job takes its model's name: " << unnamed.body.dump();
  httplib::Client admin = d->client(kAdmin);
  EXPECT_EQ(post_json(admin, "/api/v1/devices/sim-a/pause", "").status, 200) << "the admin pauses a device";
  const std::int64_t held = submit(c, submission(box, "device", "sim-a", "held"));
  EXPECT_EQ(post_json(admin, "/api/v1/jobs/" + std::to_string(held) + "/cancel", "").status, 202)
      << "the admin cancels anyone's job";
  EXPECT_EQ(job(c, held)["state"], "cancelled") << "a job waiting on a paused device is cancelled at once";
  const std::int64_t waiting = submit(c, submission(box, "device", "sim-a", "waiting"));
  ASSERT_TRUE(wait_until([&] { return job(c, waiting)["state"] == "ready"; })) << "planned while the device is paused";
  EXPECT_EQ(get_json(admin, "/api/v1/devices").body["devices"][0]["state"], "paused") << "the device says it is paused";
  EXPECT_EQ(job(c, waiting)["state"], "ready") << "a paused device takes no job";
  EXPECT_EQ(post_json(admin, "/api/v1/devices/sim-a/resume", "").status, 200) << "the admin resumes the device";
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, waiting)); }))
      << "the waiting job is cut once the device resumes";
  EXPECT_EQ(job(c, waiting)["state"], "done") << "and it is done";
  EXPECT_EQ(job(c, held)["error"]["code"], "cancelled")
      << "a cancelled job says so in its error code: " << job(c, held).dump();
  EXPECT_EQ(get_json(none, "/healthz").status, 200) << "the daemon still serves after every bad request";
  // RFC 7235: the scheme is case-insensitive.
  httplib::Client lower = d->client("");
  lower.set_default_headers({{"Authorization", "bearer " + kKiosk}});
  EXPECT_EQ(get_json(lower, "/api/v1/jobs").status, 200) << "'bearer' in lower case is the Bearer scheme";
  lower.set_default_headers({{"Authorization", "Basic " + kKiosk}});
  EXPECT_EQ(get_json(lower, "/api/v1/jobs").status, 401) << "another scheme is refused";
  EXPECT_EQ(d->stop(SIGTERM), 0) << "and stops cleanly";
}

// Sends raw bytes on a fresh loopback connection and returns what comes back until the daemon
// closes it (or 30 s pass: a safety net, the daemon closes at once).
std::string raw_exchange(int port, const std::string& request) {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval tv{30, 0};
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  std::string out;
  if (::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
      ::send(s, request.data(), request.size(), 0) > 0) {
    char buf[4096];
    for (ssize_t n; (n = ::recv(s, buf, sizeof buf, 0)) > 0;) out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(s);
  return out;
}

// A POST without Content-Length used to hold a request thread until the read timeout (httplib
// reads such a body until the client closes): with every thread held, /healthz waited too.
TEST_F(Popcutd, PostWithoutContentLengthIsRefusedAtOnce) {
  const std::string cfg = dir_.write("two-threads.toml",
                                     "[server]\ndata_dir = \"x\"\nhttp_threads = 2\n"
                                     "[[device]]\nname = \"a\"\nprofile = \"" +
                                         kSrc +
                                         "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
                                         "[[token]]\nname = \"kiosk\"\ntoken = \"" +
                                         kKiosk + "\"\n");
  const auto d = start(cfg);
  std::vector<std::thread> holders;
  std::vector<std::string> answers(2);
  // As many such clients as there are threads; each keeps its connection open.
  for (std::size_t i = 0; i < answers.size(); ++i) {
    holders.emplace_back([&, i] {
      answers[i] = raw_exchange(
          d->port(), "POST /api/v1/jobs/1/cancel HTTP/1.1\r\nHost: x\r\nConnection: close\r\nAuthorization: Bearer " +
                         kKiosk + "\r\n\r\n");
    });
  }
  for (auto& t : holders) t.join();
  for (const std::string& a : answers) {
    EXPECT_EQ(a.rfind("HTTP/1.1 411", 0), 0u) << "answered 411 Length Required: " << a;
    EXPECT_NE(a.find("\"length_required\""), std::string::npos) << "with the documented code: " << a;
  }
  httplib::Client none = d->client("");
  EXPECT_EQ(get_json(none, "/healthz").status, 200) << "the daemon serves on";
}

using popcut::testing::post_mesh;

// examples/meshes/NAME.json was made by `popcut import NAME.* -o NAME.json --resolution 40 --thin-tops 1`:
// popcutd's import of the same file with the same options must give the very same model.
TEST_F(Popcutd, MeshesImportAndCutThroughTheApi) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  httplib::Client c = d->client(kKiosk);
  std::vector<std::int64_t> ids;
  for (const std::string mesh : {"house.obj", "arch.off", "tower.ply"}) {
    const std::string bytes = example("meshes/" + mesh);
    const Reply imported = post_mesh(c, "/api/v1/import", bytes, mesh, {{"resolution", "40"}, {"thin-tops", "1"}});
    ASSERT_EQ(imported.status, 200) << mesh << " imports: " << imported.body.dump();
    json got = imported.body["model"],
         want = json::parse(example("meshes/" + fs::path(mesh).stem().string() + ".json"));
    got.erase("name");
    want.erase("name");
    EXPECT_EQ(got, want) << mesh << ": popcutd's import equals popcut import's (examples/meshes/*.json)";
    const Reply r =
        post_mesh(c, "/api/v1/jobs", bytes, mesh,
                  {{"device", "sim-a"}, {"name", "mesh " + mesh}, {"resolution", "40"}, {"thin-tops", "1"}});
    ASSERT_EQ(r.status, 201) << mesh << " is queued: " << r.body.dump();
    EXPECT_EQ(r.body["name"], "mesh " + mesh) << "the job keeps its name";
    ids.push_back(r.body["id"].get<std::int64_t>());
  }
  const Reply faces =
      post_mesh(c, "/api/v1/jobs", example("meshes/house.obj"), "house.obj",
                {{"profile", "sim"}, {"resolution", "30"}, {"faces", "true"}, {"up", "+z"}, {"front", "-y"}});
  ASSERT_EQ(faces.status, 201) << "a face model that follows the silhouette is queued: " << faces.body.dump();
  EXPECT_EQ(faces.body["name"], "house") << "an unnamed mesh job is named after its file";
  ids.push_back(faces.body["id"].get<std::int64_t>());
  const Reply accented = post_mesh(c, "/api/v1/jobs", example("meshes/house.obj"), "maison d'été.obj",
                                   {{"device", "sim-a"}, {"resolution", "30"}});
  ASSERT_EQ(accented.status, 201) << "a file name in any script is fine: " << accented.body.dump();
  EXPECT_EQ(accented.body["name"], "maison d'été") << "and names the job";
  ids.push_back(accented.body["id"].get<std::int64_t>());
  for (std::int64_t id : ids) {
    ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); })) << "job " << id << " finishes; log:\n" << d->log();
    const json j = job(c, id);
    EXPECT_EQ(j["state"], "done") << "the imported mesh was cut: " << j.dump();
    EXPECT_EQ(j.value("sim_match", false), true) << "as planned: " << j.dump();
  }

  // Bad meshes and options: the importer's own message, the documented code (a bad field value is a
  // bad request, a fault inside the mesh a bad model), the option as field.
  struct Case {
    std::string content, filename;
    std::vector<std::pair<std::string, std::string>> fields;
    int status;
    std::string code, field, says;
  };
  const std::string house = example("meshes/house.obj");
  const std::vector<Case> cases = {
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n", "broken.off", {{"device", "sim-a"}}, 422, "bad_model", "mesh", "broken.off"},
      {"this is not a mesh\n", "notes.txt", {{"device", "sim-a"}}, 422, "bad_model", "mesh", "notes.txt"},
      // A place inside the mesh goes in the message; the field stays "mesh".
      {"v 0 0 0\nf 1 2 3\n", "bad.obj", {{"device", "sim-a"}}, 422, "bad_model", "mesh", "bad.obj"},
      {house, "", {{"device", "sim-a"}}, 400, "bad_request", "mesh", "file part"},
      {house,
       "house.obj",
       {{"device", "sim-a"}, {"resolution", "abc"}},
       400,
       "bad_request",
       "resolution",
       "not a whole number"},
      {house, "house.obj", {{"device", "sim-a"}, {"resolution", "5000"}}, 400, "bad_request", "resolution", "2048"},
      {house, "house.obj", {{"device", "sim-a"}, {"up", "sideways"}}, 400, "bad_request", "up", "not an axis"},
      {house,
       "house.obj",
       {{"device", "sim-a"}, {"up", "+z"}, {"front", "+z"}},
       400,
       "bad_request",
       "front",
       "perpendicular"},
      {house, "house.obj", {{"device", "sim-a"}, {"faces", "yes"}}, 400, "bad_request", "faces", "true or false"},
      {house,
       "house.obj",
       {{"device", "sim-a"}, {"resolution", "400"}},
       413,
       "model_too_complex",
       "resolution",
       "at most 1000000"},
      {house, "house.obj", {{"device", "sim-a"}, {"colour", "red"}}, 400, "bad_request", "colour", "unknown field"},
      // A repeated part is a malformed form, whichever part it is.
      {house,
       "house.obj",
       {{"device", "sim-a"}, {"resolution", "40"}, {"resolution", "50"}},
       400,
       "bad_request",
       "resolution",
       "given twice"},
      {house,
       "house.obj",
       {{"device", "sim-a"}, {"name", "a"}, {"name", "b"}},
       400,
       "bad_request",
       "name",
       "given twice"},
      {house, "../house.obj", {{"device", "sim-a"}}, 400, "bad_name", "mesh", "mesh file names"},
      {house, "maison\x01.obj", {{"device", "sim-a"}}, 400, "bad_name", "mesh", "mesh file names"},
      {house, "house.obj", {{"device", "sim-z"}, {"resolution", "40"}}, 422, "no_device", "device", "sim-z"},
      {std::string(2 << 20, ' '), "big.obj", {{"device", "sim-a"}}, 413, "too_large", "", "upload_bytes"},
  };
  for (const Case& k : cases) {
    const Reply r = post_mesh(c, "/api/v1/jobs", k.content, k.filename, k.fields);
    const json e = r.body.is_object() ? r.body.value("error", json::object()) : json::object();
    EXPECT_EQ(r.status, k.status) << k.filename << " " << json(k.fields).dump() << " -> " << r.body.dump();
    EXPECT_EQ(e.value("code", ""), k.code)
        << k.filename << " " << json(k.fields).dump() << ": documented code: " << r.body.dump();
    if (!k.field.empty()) {
      EXPECT_EQ(e.value("field", ""), k.field) << k.filename << ": the field at fault: " << r.body.dump();
    }
    EXPECT_NE(e.value("message", "").find(k.says), std::string::npos)
        << k.filename << ": the message says '" << k.says << "': " << r.body.dump();
  }
  httplib::Client none = d->client("");
  EXPECT_EQ(get_json(none, "/healthz").status, 200) << "the daemon still serves after every bad mesh";
}

TEST_F(Popcutd, MeshTriangleLimitComesFromTheConfig) {
  const auto d = start(dir_.write("few.toml",
                                  "[server]\ndata_dir = \"x\"\n[limits]\nmesh_triangles = 4\n"
                                  "[[device]]\nname = \"a\"\nprofile = \"" +
                                      kSrc +
                                      "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
                                      "[[token]]\nname = \"kiosk\"\ntoken = \"" +
                                      kKiosk + "\"\n"));
  httplib::Client c = d->client(kKiosk);
  const Reply r = post_mesh(c, "/api/v1/jobs", example("meshes/house.obj"), "house.obj", {{"device", "a"}});
  EXPECT_EQ(r.status, 413) << "over [limits] mesh_triangles: " << r.body.dump();
  EXPECT_EQ(r.body["error"].value("code", ""), "model_too_complex") << r.body.dump();
  EXPECT_NE(r.body["error"].value("message", "").find("at most 4"), std::string::npos)
      << "names the limit: " << r.body.dump();
}

// A job cut on a real (non-simulated) transport has nothing to compare its cut with: no sim_match.
TEST_F(Popcutd, SimMatchOnlyForSimulatedCutters) {
  const std::string out = (dir_.path() / "plotter.hpgl").string();
  const auto d = start(dir_.write("file.toml",
                                  "[server]\ndata_dir = \"x\"\n"
                                  "[[device]]\nname = \"f\"\nprofile = \"" +
                                      kSrc + "/configs/devices/generic-hpgl.toml\"\ntransport = \"file:" + out +
                                      "\"\n"
                                      "[[token]]\nname = \"kiosk\"\ntoken = \"" +
                                      kKiosk + "\"\n"));
  httplib::Client c = d->client(kKiosk);
  const std::int64_t id = submit(c, submission(example("voxel/box.json"), "device", "f", "to a file"));
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); })) << "the job finishes; log:\n" << d->log();
  const json j = job(c, id);
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_FALSE(j.contains("sim_match")) << "no sim_match for a file device: " << j.dump();
  EXPECT_NE(read_file(out).find("IN;"), std::string::npos) << "the HP-GL went to the file";
}

TEST_F(Popcutd, KioskTokensSeeOnlyTheirOwnJobs) {
  const auto d = start(slow_config(dir_, 0, 1));
  httplib::Client a = d->client(kKiosk);
  httplib::Client b = d->client("other-kiosk-0123456789");
  httplib::Client admin = d->client(kAdmin);
  const std::int64_t id = submit(a, submission(example("voxel/box.json"), "device", "slow", "mine"));
  EXPECT_EQ(get_json(b, "/api/v1/jobs/" + std::to_string(id)).status, 404) << "another kiosk cannot see the job";
  EXPECT_EQ(post_json(b, "/api/v1/jobs/" + std::to_string(id) + "/cancel", "").status, 404) << "nor cancel it";
  EXPECT_TRUE(get_json(b, "/api/v1/jobs").body["jobs"].empty()) << "nor list it";
  EXPECT_EQ(get_json(a, "/api/v1/jobs").body["jobs"].size(), 1u) << "its owner lists it";
  EXPECT_EQ(get_json(admin, "/api/v1/jobs/" + std::to_string(id)).status, 200) << "the admin sees it";
  ASSERT_TRUE(wait_until([&] { return final_state(job(a, id)); })) << "it finishes";
  const httplib::Result svg = a.Get(("/api/v1/jobs/" + std::to_string(id) + "/pattern.svg").c_str());
  ASSERT_TRUE(svg) << "pattern answered";
  EXPECT_NE(svg->body.find("<svg"), std::string::npos) << "the job's pattern is SVG";
  const httplib::Result png = a.Get(("/api/v1/jobs/" + std::to_string(id) + "/preview.png?angle=45").c_str());
  ASSERT_TRUE(png) << "preview answered";
  EXPECT_EQ(png->body.substr(1, 3), "PNG") << "the preview is a PNG";
}

TEST_F(Popcutd, DevicesShowAKioskOnlyItsOwnJobBeingCut) {
  const auto d = start(slow_config(dir_, 1.0, 20.0));
  httplib::Client a = d->client(kKiosk);
  httplib::Client b = d->client("other-kiosk-0123456789");
  httplib::Client admin = d->client(kAdmin);
  const std::int64_t id = submit(a, submission(example("voxel/castle.json"), "device", "slow", "long cut"));
  ASSERT_TRUE(wait_until([&] { return job(a, id)["state"] == "cutting"; })) << "the cut starts; log:\n" << d->log();
  const auto cutting_on_slow = [&](httplib::Client& c) {
    return get_json(c, "/api/v1/devices").body["devices"][0]["job"];
  };
  EXPECT_EQ(cutting_on_slow(a), id) << "its owner sees which job the device cuts";
  EXPECT_EQ(cutting_on_slow(admin), id) << "so does the admin";
  EXPECT_TRUE(cutting_on_slow(b).is_null())
      << "another kiosk sees the device busy, not the id of a job it may not open";
  EXPECT_EQ(get_json(b, "/api/v1/devices").body["devices"][0]["state"], "cutting")
      << "but it does see that it is cutting";
  EXPECT_EQ(post_json(a, "/api/v1/jobs/" + std::to_string(id) + "/cancel", "").status, 202)
      << "cancelled to end the test";
  ASSERT_TRUE(wait_until([&] { return final_state(job(a, id)); })) << "the cut stops";
}

TEST_F(Popcutd, BadConfigExitsTwoNamingTheKey) {
  const std::string cfg = dir_.write("bad.toml", "[server]\ndata_dir = \"x\"\nport = \"eighty\"\n");
  EXPECT_THROW(start(cfg), std::runtime_error) << "popcutd refuses the config";
  const std::string cmd = std::string(POPCUTD) + " --config " + cfg + " 2>" + (dir_.path() / "err").string();
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2) << "bad config is exit 2";
  EXPECT_NE(read_file((dir_.path() / "err").string()).find("bad.toml: [server] port: expected a whole number"),
            std::string::npos)
      << "the message names file, section and key: " << read_file((dir_.path() / "err").string());
}

// A second popcutd must not share a live one's data dir (it would mark the jobs being cut as
// interrupted and cut on the same devices) nor its port (SO_REUSEPORT would split the requests).
TEST_F(Popcutd, SecondDaemonOnTheSameDataDirOrPortExitsThree) {
  const std::string cfg = slow_config(dir_, 0, 1);
  auto first = start(cfg);
  const std::string err = (dir_.path() / "second.err").string();
  const auto run_second = [&](const std::string& data_dir, int port) {
    // Bounded: a second daemon that wrongly starts would otherwise serve forever.
    const std::string cmd = "timeout -s KILL 30 " + std::string(POPCUTD) + " --config " + cfg + " --data-dir " +
                            data_dir + " --port " + std::to_string(port) + " >/dev/null 2>" + err;
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  };
  EXPECT_EQ(run_second(data_, 0), 3) << "same data dir: " << read_file(err);
  EXPECT_NE(read_file(err).find("in use by another popcutd"), std::string::npos) << "says why: " << read_file(err);
  EXPECT_EQ(run_second((dir_.path() / "other-data").string(), first->port()), 3) << "same port: " << read_file(err);
  EXPECT_NE(read_file(err).find("cannot listen"), std::string::npos) << "says why: " << read_file(err);
  httplib::Client c = first->client(kKiosk);
  EXPECT_EQ(get_json(c, "/healthz").status, 200) << "the first daemon keeps serving";
}

}  // namespace

namespace {
using namespace popcut::testing::e2e;

TEST_F(PopcutClient, SubmitJobsCancelWithDocumentedExitCodes) {
  const auto d = start(slow_config(dir_, 1.0, 20.0));
  const std::string server = "--server http://127.0.0.1:" + std::to_string(d->port()) + " --token " + kKiosk;
  CliRun r = cli("submit " + kSrc + "/examples/voxel/castle.json --device slow --name castle --json " + server);
  ASSERT_EQ(r.code, 0) << "submit exits 0: " << r.err;
  const json job = json::parse(r.out);
  EXPECT_EQ(job["name"], "castle") << "--json prints the job";
  r = cli("jobs " + server);
  EXPECT_EQ(r.code, 0) << "jobs exits 0: " << r.err;
  EXPECT_NE(r.out.find("castle"), std::string::npos) << "jobs lists it: " << r.out;
  r = cli("cancel " + std::to_string(job["id"].get<int>()) + " " + server);
  EXPECT_EQ(r.code, 0) << "cancel exits 0: " << r.err;
  httplib::Client c = d->client(kKiosk);
  ASSERT_TRUE(wait_until([&] { return final_state(Popcutd::job(c, job["id"].get<std::int64_t>())); }))
      << "the job ends";
  EXPECT_EQ(Popcutd::job(c, job["id"].get<std::int64_t>())["state"], "cancelled") << "cancelled through the CLI";

  r = cli("cancel " + std::to_string(job["id"].get<int>()) + " " + server);
  EXPECT_EQ(r.code, 2) << "cancelling a cancelled job is refused: exit 2";
  EXPECT_NE(r.err.find("409 conflict"), std::string::npos) << "the daemon's code is shown: " << r.err;
  r = cli("cancel 4242 " + server);
  EXPECT_EQ(r.code, 2) << "unknown id: exit 2";
  EXPECT_NE(r.err.find("404 not_found"), std::string::npos) << "the daemon's code is shown: " << r.err;
  r = cli("submit " + kSrc + "/examples/voxel/castle.json --device nowhere " + server);
  EXPECT_EQ(r.code, 2) << "unknown device: exit 2";
  EXPECT_NE(r.err.find("no_device"), std::string::npos) << "named: " << r.err;
  r = cli("submit " + kSrc + "/README.md --device slow " + server);
  EXPECT_EQ(r.code, 2) << "a file that is not JSON: exit 2";
  r = cli("jobs --server http://127.0.0.1:" + std::to_string(d->port()) + " --token not-a-known-token-at-all");
  EXPECT_EQ(r.code, 2) << "wrong token: exit 2";
  EXPECT_NE(r.err.find("401 unauthorized"), std::string::npos) << "named: " << r.err;
  r = cli("jobs --server http://127.0.0.1:" + std::to_string(d->port()) + "/ --token " + kKiosk);
  EXPECT_EQ(r.code, 0) << "a trailing slash, as a browser shows the address, is fine: " << r.err;
  r = cli("jobs --server http://127.0.0.1:" + std::to_string(d->port()) + "/api --token " + kKiosk);
  EXPECT_EQ(r.code, 2) << "a path is refused, not ignored: " << r.err;
  const std::string deep = dir_.write("deep.json", R"({"format": "popcut.voxel.v1", "heights": )" +
                                                       std::string(100000, '[') + std::string(100000, ']') + "}");
  r = cli("submit " + deep + " --device slow " + server);
  EXPECT_EQ(r.code, 2) << "a model nested 100,000 deep is refused, not a crash: " << r.err;
  r = cli("submit " + kSrc + "/examples/voxel/box.json --device slow --name '' " + server);
  EXPECT_EQ(r.code, 2) << "an empty --name is refused as the API refuses it: " << r.err;
  r = cli("cancel abc " + server);
  EXPECT_EQ(r.code, 2) << "a job id that is not a number: exit 2";
  EXPECT_NE(r.err.find("'abc' is not a job id"), std::string::npos) << "said plainly: " << r.err;
  const int port = d->port();
  EXPECT_EQ(d->stop(SIGTERM), 0) << "daemon stopped";
  r = cli("jobs --server http://127.0.0.1:" + std::to_string(port) + " --token " + kKiosk);
  EXPECT_EQ(r.code, 3) << "no daemon: exit 3";
  EXPECT_NE(r.err.find("cannot reach popcutd"), std::string::npos) << "said so: " << r.err;
}

TEST_F(PopcutClient, SubmitsAMeshWithImportOptions) {
  const auto d = start(slow_config(dir_, 0, 1));
  const std::string server = "--server http://127.0.0.1:" + std::to_string(d->port()) + " --token " + kKiosk;
  for (const std::string mesh : {"house.obj", "arch.off", "tower.ply"}) {
    const CliRun r = cli("submit " + kSrc + "/examples/meshes/" + mesh +
                         " --device slow --resolution 30 --thin-tops 1 --wait --json " + server);
    ASSERT_EQ(r.code, 0) << mesh << ": submitted and cut, exit 0: " << r.err;
    const json j = json::parse(r.out);
    EXPECT_EQ(j["state"], "done") << mesh << " was cut: " << r.out;
  }
  const std::string broken = dir_.write("broken.off", "OFF\n3 1 0\n0 0 0\n");
  CliRun r = cli("submit " + broken + " --device slow " + server);
  EXPECT_EQ(r.code, 2) << "a malformed mesh: exit 2";
  EXPECT_NE(r.err.find("422 bad_model"), std::string::npos) << "the daemon's code is shown: " << r.err;
  EXPECT_NE(r.err.find("broken.off"), std::string::npos) << "the file is named: " << r.err;
  r = cli("submit " + kSrc + "/examples/meshes/house.obj --device slow --smooth 4 " + server);
  EXPECT_EQ(r.code, 2) << "an even --smooth: exit 2";
  EXPECT_NE(r.err.find("[smooth]"), std::string::npos) << "the option is named: " << r.err;
  r = cli("submit " + kSrc + "/examples/voxel/box.json --device slow --resolution 30 " + server);
  EXPECT_EQ(r.code, 2) << "an import option with a JSON model: exit 2";
  EXPECT_NE(r.err.find("--resolution is an import option"), std::string::npos) << "said so: " << r.err;
}

// Drawings go through submit as every command reads them: a card as its face model, a sheet
// (--as sheet) as its own lines; both are cut on the simulated cutter.
TEST_F(PopcutClient, SubmitsDrawingsAsCardsAndAsSheets) {
  const auto d = start(slow_config(dir_, 0, 1));
  const std::string server = "--server http://127.0.0.1:" + std::to_string(d->port()) + " --token " + kKiosk;
  CliRun r = cli("submit " + kSrc + "/examples/drawn/step.svg --device slow --wait --json " + server);
  ASSERT_EQ(r.code, 0) << "a drawn card is cut: " << r.err;
  EXPECT_EQ(json::parse(r.out)["state"], "done") << r.out;
  r = cli("submit " + kSrc + "/examples/drawn/box.svg --as sheet --device slow --wait --json " + server);
  ASSERT_EQ(r.code, 0) << "a drawn sheet is cut: " << r.err;
  const json box = json::parse(r.out);
  EXPECT_EQ(box["state"], "done") << r.out;
  httplib::Client c = d->client(kKiosk);
  const json job = Popcutd::job(c, box["id"].get<std::int64_t>());
  // The dieline's own cuts and scores, as `popcut cut box.svg --as sheet` plans them: 741 mm of
  // cut outline and 544 mm of creases.
  EXPECT_GT(job["strokes_total"].get<int>(), 10) << job.dump();
  EXPECT_EQ(job["strokes_sent"], job["strokes_total"]) << job.dump();
  EXPECT_GT(job["cut_mm"].get<double>(), 741 + 544 - 100) << job.dump();
  r = cli("submit " + kSrc + "/examples/drawn/box.svg --device slow " + server);
  EXPECT_EQ(r.code, 2) << "the box is no card: refused before it is sent";
  EXPECT_NE(r.err.find("--as sheet"), std::string::npos) << "and told how to send it: " << r.err;
  r = cli("submit " + kSrc + "/examples/drawn/box.svg --as paper --device slow " + server);
  EXPECT_EQ(r.code, 2) << "--as takes card or sheet";
}

// Something answers at --server, but not popcutd: exit 3 (cannot get the job through), not a crash.
TEST_F(PopcutClient, NonJsonAnswerExitsThree) {
  httplib::Server other;
  other.Get(".*", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("<html>a web server</html>", "text/html");
  });
  other.Post(".*", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("<html>a web server</html>", "text/html");
  });
  const int port = other.bind_to_any_port("127.0.0.1");
  std::thread serve([&] { other.listen_after_bind(); });
  const std::string server = "--server http://127.0.0.1:" + std::to_string(port) + " --token " + kKiosk;
  CliRun r = cli("jobs " + server);
  EXPECT_EQ(r.code, 3) << "a non-JSON answer to jobs: exit 3: " << r.err;
  EXPECT_NE(r.err.find("not JSON"), std::string::npos) << "says the answer is not JSON: " << r.err;
  r = cli("submit " + kSrc + "/examples/voxel/box.json --device a " + server);
  EXPECT_EQ(r.code, 3) << "a non-JSON answer to submit: exit 3: " << r.err;
  other.stop();
  serve.join();
}

}  // namespace
