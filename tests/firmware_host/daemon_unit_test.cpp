// popcutd's parts without processes: configuration checks, the job store's transitions, stroke-boundary encoding.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <set>

#include "config.h"
#include "cut_job.h"
#include "popcut/drivers/profile.h"
#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/io/model_io.h"
#include "popcutd_process.h"
#include "preview_cache.h"
#include "store.h"

namespace {
namespace fs = std::filesystem;
using namespace popcut;
using namespace popcut::daemon;

const std::string kSrc = POPCUT_SOURCE_DIR;

// The error a config text raises, or "" when it loads.
std::string config_error(const std::string& text) {
  try {
    parse_daemon_config(text, kSrc + "/configs/test.toml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kGood = R"(
[server]
data_dir = "/tmp/x"
[[device]]
name = "a"
profile = "devices/sim.toml"
transport = "sim"
[[token]]
name = "k"
token = "0123456789abcdef"
)";

TEST(DaemonConfig, SampleConfigLoads) {
  const DaemonConfig c = load_daemon_config(kSrc + "/configs/popcutd.toml");
  EXPECT_EQ(c.listen, "127.0.0.1") << "the sample listens on loopback only";
  ASSERT_EQ(c.devices.size(), 2u) << "the sample has two simulated cutters";
  EXPECT_EQ(c.devices[0].profile.name, "popcut simulated cutter") << "profiles load relative to the config file";
  EXPECT_EQ(c.tokens.size(), 2u) << "a kiosk and an admin token";
  EXPECT_EQ(c.tokens[1].role, Role::admin) << "the second token is the admin's";
  EXPECT_EQ(config_error(kGood), "") << "the minimal config loads";
  const DaemonConfig minimal = parse_daemon_config(kGood, kSrc + "/configs/test.toml");
  EXPECT_EQ(minimal.http_threads, 64) << "room for a classroom of kiosk tablets by default";
  EXPECT_EQ(minimal.header_timeout_s, 5) << "a request head is due within 5 s by default";
  EXPECT_EQ(minimal.keep_alive_timeout_s, 2) << "an idle kept-alive connection closes after 2 s by default";
}

TEST(DaemonConfig, ErrorsNameFileSectionAndKey) {
  struct Case {
    std::string text, expect;
  };
  const std::string good = kGood;
  const std::vector<Case> cases = {
      {good + "[bogus]\n", "[bogus]"},
      {"[server]\nport = \"80\"\n", "[server] port: expected a whole number"},
      {"[server]\nport = 70000\ndata_dir=\"/x\"\n", "[server] port: 70000 is out of range 0 to 65535"},
      {"[server]\nlisten = \"\"\n", "[server] listen"},
      {"[server]\nlisten = \"999.1.1.1\"\n", "[server] listen: \"999.1.1.1\" is not an IPv4 address"},
      {"[server]\nlisten = \"::g\"\n", "[server] listen: \"::g\" is not an IPv6 address"},
      {"[server]\nlisten = \"my host\"\n", "[server] listen: \"my host\" is neither"},
      {"[server]\ndata_dir = \"/x\"\nheader_timeout_s = 0\n", "[server] header_timeout_s: 0 is out of range 1 to 300"},
      {"[server]\ndata_dir = \"/x\"\nkeep_alive_timeout_s = 301\n",
       "[server] keep_alive_timeout_s: 301 is out of range 1 to 300"},
      {"[server]\ndata_dir = \"/x\"\nhttp_threads = 2000\n", "[server] http_threads: 2000 is out of range 1 to 1024"},
      {"[server]\nport = 1\n", "[server] data_dir: missing"},
      {"[server]\ndata_dir = \"/x\"\n[[token]]\nname=\"k\"\ntoken=\"0123456789abcdef\"\n", "no devices"},
      {"[server]\ndata_dir = \"/x\"\nspeed = 1\n" + good.substr(good.find("[[device]]")),
       "[server] speed: unknown key"},
      {good + "[[device]]\nname = \"a\"\nprofile = \"devices/sim.toml\"\ntransport = \"sim\"\n",
       "[device.1] name: \"a\" is used by another device"},
      {good + "[[device]]\nname = \"../b\"\nprofile = \"devices/sim.toml\"\ntransport = \"sim\"\n", "[device.1] name"},
      {good + "[[device]]\nname = \"b\"\nprofile = \"devices/sim.toml\"\ntransport = \"telnet:x\"\n",
       "[device.1] transport"},
      {good + "[[device]]\nname = \"b\"\nprofile = \"devices/none.toml\"\ntransport = \"sim\"\n", "none.toml"},
      {good + "[[device]]\nname = \"b\"\nprofile = \"devices/sim.toml\"\ntransport = \"file:x\"\nsim_slowdown = 2\n",
       "sim_* settings"},
      {good + "[[token]]\nname = \"j\"\ntoken = \"short\"\n", "[token.1] token: must be at least 16"},
      {good + "[[token]]\nname = \"j\"\ntoken = \"0123456789abcdef\"\n", "[token.1] token: the same secret"},
      {good + "[[token]]\nname = \"j\"\ntoken = \"0123456789abcdefg\"\nrole = \"root\"\n", "[token.1] role"},
      {good + "[limits]\nupload_bytes = 10\n", "[limits] upload_bytes: 10 is out of range"},
      {"[server\n", "line 1"},
  };
  for (const char* listen : {"0.0.0.0", "::1", "::", "localhost", "cutter-room.local"}) {
    std::string text = good;
    text.insert(text.find("data_dir"), std::string("listen = \"") + listen + "\"\n");
    EXPECT_EQ(config_error(text), "") << listen << " is a fine listen address";
  }
  for (const Case& c : cases) {
    const std::string e = config_error(c.text);
    EXPECT_NE(e.find("test.toml"), std::string::npos) << "the error names the file: " << e << "\nfor:\n" << c.text;
    EXPECT_NE(e.find(c.expect), std::string::npos) << "expected '" << c.expect << "' in: " << e << "\nfor:\n" << c.text;
  }
}

TEST(DaemonConfig, SafeNames) {
  for (const char* ok : {"card", "my card 2", "a-b_c.d"}) EXPECT_TRUE(is_safe_name(ok)) << ok << " is a fine name";
  for (const char* bad : {"", "..", "../etc/passwd", "a/b", ".hidden", "a\\b", "x..y", " lead", "a;rm", "%2e%2e"}) {
    EXPECT_FALSE(is_safe_name(bad)) << "'" << bad << "' must be refused";
  }
  EXPECT_FALSE(is_safe_name(std::string(65, 'a'))) << "names are at most 64 bytes";
  for (const char* ok : {"card", "Castle gatehouse (Fig. 3)", "café 中", "城", "\xf0\x9f\x8f\xb0 castle"}) {
    EXPECT_TRUE(is_job_label(ok)) << ok << " is a fine job name";
  }
  std::string castles;
  for (int i = 0; i < 64; ++i) castles += "\xe5\x9f\x8e";  // 城, three bytes
  EXPECT_TRUE(is_job_label(castles)) << "64 characters of three bytes each: the limit counts characters";
  EXPECT_FALSE(is_job_label(castles + "\xe5\x9f\x8e")) << "65 characters are too many";
  // A model's name longer than that names its job shortened, at a character, with an ellipsis.
  EXPECT_EQ(job_label_from(castles), castles) << "a label is kept as it is";
  const std::string shortened = job_label_from(castles + "\xe5\x9f\x8e");
  EXPECT_EQ(shortened, castles.substr(0, 63 * 3) + "\u2026") << "63 characters and an ellipsis";
  EXPECT_TRUE(is_job_label(shortened));
  EXPECT_EQ(job_label_from(std::string(62, 'a') + " " + std::string(10, 'b')), std::string(62, 'a') + "\u2026")
      << "no blank before the ellipsis";
  EXPECT_EQ(job_label_from("a/b"), "") << "a path is no label however short";
  EXPECT_EQ(job_label_from(std::string(70, 'a') + "\x01"), std::string(63, 'a') + "\u2026")
      << "what is cut off is not shown";
  for (const std::string& bad :
       {std::string(), std::string(65, 'a'), std::string(" lead"), std::string("trail "), std::string("a\x01") + "b",
        std::string("tab\there"), std::string("rlo\xe2\x80\xae"), std::string("bad \xff utf8"),
        std::string("overlong \xc0\xaf"), std::string("nbsp\xc2\xa0"), std::string("\xe3\x80\x80ideographic space"),
        std::string("alm\xd8\x9c"),
        std::string("\xef\xbb\xbf"
                    "bom"),
        std::string("cut \xe5\x9f"), std::string("a/b"), std::string("../x"), std::string(".hidden"),
        std::string("a\\b"), std::string("c1 \xc2\x85")}) {
    EXPECT_FALSE(is_job_label(bad)) << "'" << bad << "' must be refused as a job name";
  }
}

class Store : public ::testing::Test {
 protected:
  popcut::testing::TempDir dir_{"popcut-store"};
  std::string db() const { return (dir_.path() / "jobs.db").string(); }
  static NewJob job(const std::string& device, const std::string& profile = "sim") {
    return {"kiosk", "card", device, profile, "{}"};
  }
};

TEST_F(Store, StrokesExecutedIsKeptPerCutAndAddedToAnOlderDatabase) {
  {  // A database written before strokes_executed existed.
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(db().c_str(), &raw), SQLITE_OK);
    const char* old_schema =
        "CREATE TABLE jobs (id INTEGER PRIMARY KEY AUTOINCREMENT, owner TEXT NOT NULL, name TEXT NOT NULL,"
        " target_device TEXT NOT NULL, target_profile TEXT NOT NULL, device TEXT NOT NULL DEFAULT '',"
        " state TEXT NOT NULL, error_code TEXT NOT NULL DEFAULT '', error_message TEXT NOT NULL DEFAULT '',"
        " strokes_total INTEGER NOT NULL DEFAULT 0, strokes_sent INTEGER NOT NULL DEFAULT 0,"
        " resume_from INTEGER NOT NULL DEFAULT 0, est_time_s REAL NOT NULL DEFAULT 0,"
        " created_at REAL NOT NULL, started_at REAL NOT NULL DEFAULT 0, finished_at REAL NOT NULL DEFAULT 0,"
        " cancel_requested INTEGER NOT NULL DEFAULT 0, sim_match INTEGER NOT NULL DEFAULT 0);"
        "INSERT INTO jobs (owner, name, target_device, target_profile, state, created_at) VALUES ('k', 'old', 'dev1', "
        "'sim', 'done', 1);";
    ASSERT_EQ(sqlite3_exec(raw, old_schema, nullptr, nullptr, nullptr), SQLITE_OK) << sqlite3_errmsg(raw);
    sqlite3_close(raw);
  }
  JobStore s(db());
  EXPECT_FALSE(s.get(1)->strokes_executed.has_value()) << "an old job's executed strokes are unknown";
  EXPECT_FALSE(s.get(1)->resume_point.has_value()) << "an old job shows no resume point";
  const std::int64_t a = *s.insert(job("dev1"), 100);
  ASSERT_EQ(s.claim_for_planning()->id, a);
  s.set_planned(a, 10, 5.0);
  ASSERT_TRUE(s.claim_for_device("dev1", "sim").has_value());
  s.set_progress(a, 7);
  s.set_executed(a, 3);
  s.finish(a, JobState::interrupted, "device_error", "stopped");
  EXPECT_EQ(s.get(a)->strokes_executed, std::optional<std::int64_t>(3)) << "the cut's executed strokes are kept";
  EXPECT_EQ(s.get(a)->resume_from, 7) << "resume stays at the strokes certainly received";
  EXPECT_FALSE(s.get(a)->resume_point.has_value()) << "not resumed yet";
  ASSERT_EQ(s.resume(a, ResumePoint::executed), ResumeResult::resumed);
  EXPECT_EQ(s.get(a)->resume_from, 3) << "resumed after the executed strokes";
  EXPECT_EQ(s.get(a)->strokes_sent, 3) << "a power-cycled device holds nothing beyond them";
  EXPECT_EQ(s.get(a)->resume_point, std::optional<ResumePoint>(ResumePoint::executed)) << "the choice is kept";
  ASSERT_TRUE(s.claim_for_device("dev1", "sim").has_value());
  EXPECT_FALSE(s.get(a)->strokes_executed.has_value()) << "a new cut starts with executed unknown";
  EXPECT_EQ(s.get(a)->strokes_sent, 3) << "the new run counts from where it starts";
  // Killed before the device confirmed a stroke of the new run: it resumes where that run began.
  s.set_executed(a, std::nullopt);
  s.finish(a, JobState::interrupted, "interrupted", "killed");
  EXPECT_EQ(s.get(a)->resume_from, 3) << "not at the strokes the earlier run had sent";
  EXPECT_EQ(s.resume(a, ResumePoint::executed), ResumeResult::executed_unknown)
      << "no executed point is known for this run";
  EXPECT_EQ(s.get(a)->state, JobState::interrupted) << "a refused resume changes nothing";
  EXPECT_EQ(s.resume(a, ResumePoint::received), ResumeResult::resumed);
  EXPECT_EQ(s.get(a)->resume_point, std::optional<ResumePoint>(ResumePoint::received));
  EXPECT_EQ(s.resume(a, ResumePoint::received), ResumeResult::not_interrupted) << "a ready job does not resume again";
}

TEST_F(Store, TransitionsAreGuardedAndSurviveReopen) {
  std::int64_t a = 0, b = 0, c = 0;
  {
    JobStore s(db());
    a = *s.insert(job("dev1"), 100);
    b = *s.insert(job(""), 100);
    c = *s.insert(job("dev2"), 100);
    EXPECT_EQ(s.claim_for_planning()->id, a) << "planning takes the oldest queued job";
    s.set_planned(a, 10, 5.0);
    EXPECT_FALSE(s.claim_for_device("dev2", "other").has_value())
        << "dev2 with another profile may not take a job for dev1";
    const std::optional<Job> got = s.claim_for_device("dev1", "sim");
    ASSERT_TRUE(got.has_value()) << "dev1 takes its ready job";
    EXPECT_EQ(got->state, JobState::cutting) << "claimed jobs are cutting";
    s.set_progress(a, 4);
    EXPECT_EQ(s.claim_for_planning()->id, b) << "the next queued job is planned";
    // A crash here: a is cutting (4 strokes sent), b is planning.
  }
  JobStore s(db());
  const JobStore::Recovered r = s.recover();
  EXPECT_EQ(r.interrupted, 1) << "the cutting job is interrupted";
  EXPECT_EQ(r.requeued, 1) << "the planning job goes back to the queue";
  const Job ja = *s.get(a);
  EXPECT_EQ(ja.state, JobState::interrupted) << "a cutting job becomes interrupted after a crash";
  EXPECT_EQ(ja.strokes_sent, 4) << "strokes fully sent survive the crash";
  EXPECT_EQ(ja.resume_from, 4) << "it will resume at the first stroke not fully sent";
  EXPECT_EQ(s.get(b)->state, JobState::queued) << "a planning job goes back to the queue";
  EXPECT_FALSE(s.claim_for_device("dev1", "sim").has_value()) << "an interrupted job is not cut again unasked";
  EXPECT_EQ(s.resume(a), ResumeResult::resumed) << "an interrupted job resumes when asked";
  EXPECT_EQ(s.resume(a), ResumeResult::not_interrupted) << "a ready job cannot resume again";
  EXPECT_EQ(s.claim_for_device("dev1", "sim")->id, a) << "the resumed job is ready for its device";
  EXPECT_EQ(s.cancel(a), CancelResult::requested) << "cancelling a cutting job asks the worker";
  EXPECT_TRUE(s.cancel_requested(a)) << "the request is recorded";
  s.finish(a, JobState::cancelled, "", "");
  EXPECT_EQ(s.cancel(a), CancelResult::already_final) << "a cancelled job stays cancelled";
  EXPECT_EQ(s.cancel(c), CancelResult::cancelled) << "a queued job is cancelled at once";
  EXPECT_EQ(s.cancel(999), CancelResult::not_found) << "unknown ids are reported";
  s.finish(c, JobState::done, "", "");
  EXPECT_EQ(s.get(c)->state, JobState::cancelled) << "finish never overwrites a job that is not planning or cutting";
}

TEST_F(Store, QueueLengthLimit) {
  JobStore s(db());
  EXPECT_TRUE(s.insert(job("d"), 2).has_value()) << "first job fits";
  EXPECT_TRUE(s.insert(job("d"), 2).has_value()) << "second job fits";
  EXPECT_FALSE(s.insert(job("d"), 2).has_value()) << "a third unfinished job exceeds queue_length 2";
  s.cancel(1);
  EXPECT_TRUE(s.insert(job("d"), 2).has_value()) << "finished jobs do not count against the queue";
}

// A job for a profile, cut on sim-a and interrupted, holds a half-cut sheet on sim-a: resumed,
// only sim-a takes it, however long sim-b sits idle, across a reopen too; its place in line and
// forecast count it as sim-a's. (sim-b used to take it and finish the card on a blank sheet.)
TEST_F(Store, AResumedJobIsCutOnlyOnTheDeviceHoldingItsSheet) {
  std::int64_t a = 0;
  {
    JobStore s(db());
    a = *s.insert(job(""), 100);
    ASSERT_EQ(s.claim_for_planning()->id, a);
    s.set_planned(a, 10, 5.0);
    ASSERT_EQ(s.claim_for_device("sim-a", "sim")->id, a);
    s.set_progress(a, 6);
    s.finish(a, JobState::interrupted, "interrupted", "stopped");
    EXPECT_EQ(s.get(a)->bound_device(), "sim-a") << "interrupted, it is bound to the device holding its sheet";
  }
  JobStore s(db());
  ASSERT_EQ(s.resume(a), ResumeResult::resumed);
  EXPECT_EQ(s.get(a)->bound_device(), "sim-a") << "resumed and waiting, still bound";
  const std::int64_t later = *s.insert(job(""), 100);
  ASSERT_EQ(s.claim_for_planning()->id, later);
  s.set_planned(later, 10, 5.0);
  EXPECT_EQ(s.place_in_line(*s.get(later)), 1)
      << "a job for any sim device may wait behind the bound one (both may take sim-a)";
  const std::int64_t for_b = *s.insert(job("sim-b"), 100);
  EXPECT_EQ(s.place_in_line(*s.get(for_b)), 1)
      << "a job naming sim-b waits behind the later one only, not the one bound to sim-a";
  bool bound_forecast = false;
  for (const WaitingJob& w : s.waiting()) {
    if (w.id == a) bound_forecast = w.targets.device == "sim-a";
  }
  EXPECT_TRUE(bound_forecast) << "the forecast plays it forward on sim-a";
  const std::optional<Job> b = s.claim_for_device("sim-b", "sim");
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->id, later) << "sim-b takes the later job, never the half-cut one";
  EXPECT_FALSE(s.claim_for_device("sim-b", "sim").has_value()) << "and nothing else";
  const std::optional<Job> on_a = s.claim_for_device("sim-a", "sim");
  ASSERT_TRUE(on_a.has_value());
  EXPECT_EQ(on_a->id, a) << "sim-a finishes its sheet";
  EXPECT_EQ(on_a->resume_from, 6);
}

// The reviewer's case: sim-a and sim-b (profile sim), jobs X (sim-a), Y (profile sim), Z (sim-b), W (sim-a).
TEST_F(Store, PlaceInLineCountsOnlyJobsThatMayTakeTheSameDevice) {
  JobStore s(db());
  const std::int64_t x = *s.insert(job("sim-a"), 100), y = *s.insert(job(""), 100), z = *s.insert(job("sim-b"), 100),
                     w = *s.insert(job("sim-a"), 100);
  EXPECT_EQ(s.place_in_line(*s.get(x)), 0) << "X is first";
  EXPECT_EQ(s.place_in_line(*s.get(y)), 1) << "Y (any sim device) waits behind X";
  EXPECT_EQ(s.place_in_line(*s.get(z)), 1) << "Z (sim-b) waits behind Y only: X can only go to sim-a";
  EXPECT_EQ(s.place_in_line(*s.get(w)), 2) << "W (sim-a) waits behind X and Y, not Z";
  EXPECT_EQ(s.place_in_line(*s.get(*s.insert(job("", "other"), 100))), 0)
      << "another profile's job waits for none of them";
  EXPECT_EQ(s.waiting().size(), 5u) << "every waiting job is played forward for eta_s";
}

TEST(Forecast, FollowsTheWorkersThroughTheQueue) {
  const auto devices = [](double a_busy_s, double b_busy_s) {
    return std::vector<ForecastDevice>{{"a", "sim", 1, a_busy_s}, {"b", "sim", 1, b_busy_s}};
  };
  // X (a, 10 s), Y (any sim, 7 s), Z (b, 5 s), W (a, 5 s); a cuts a job with 3 s left, b is idle.
  const std::vector<WaitingJob> queue{
      {1, {"a", "sim"}, 10}, {2, {"", "sim"}, 7}, {3, {"b", "sim"}, 5}, {4, {"a", "sim"}, 5}};
  auto done = forecast_done_s(queue, devices(3, 0));
  EXPECT_DOUBLE_EQ(done.at(1), 3 + 10) << "X after the cut in progress on a";
  EXPECT_DOUBLE_EQ(done.at(2), 7) << "Y goes to b, free at once";
  EXPECT_DOUBLE_EQ(done.at(3), 7 + 5) << "Z follows Y on b";
  EXPECT_DOUBLE_EQ(done.at(4), 3 + 10 + 5) << "W follows X on a; Z, for b only, does not delay it";
  // A profile job takes whichever device frees first.
  done = forecast_done_s({{9, {"", "sim"}, 5}}, devices(30, 2));
  EXPECT_DOUBLE_EQ(done.at(9), 2 + 5) << "b is free after 2 s";
  // A simulated cutter at a twentieth of real time cuts a 10 s plan in 0.5 s.
  done = forecast_done_s({{9, {"a", "sim"}, 10}}, {{"a", "sim", 0.05, 0}});
  EXPECT_DOUBLE_EQ(done.at(9), 0.5) << "the device's time factor applies";
  EXPECT_EQ(forecast_done_s({{9, {"a", "sim"}, 5}}, {{"b", "sim", 1, 0}}).count(9), 0u)
      << "a paused (not taking work): no estimate";
  EXPECT_EQ(forecast_done_s({{9, {"", "other"}, 5}}, devices(0, 0)).count(9), 0u)
      << "no device with its profile: no estimate";
}

TEST(Forecast, ACutInProgressHasLeftWhatIsUnsentOrNotYetElapsed) {
  Job j;
  j.est_time_s = 10;
  j.strokes_total = 10;
  j.strokes_sent = 10;  // a small job: all of it in the device's buffer at once
  EXPECT_DOUBLE_EQ(cut_left_s(j, 1, 100, 103), 7) << "sent whole after 3 s of a 10 s cut: 7 s left, not 0";
  j.strokes_sent = 5;
  EXPECT_DOUBLE_EQ(cut_left_s(j, 1, 100, 101), 9) << "1 s in: the estimate's 9 s beats the unsent half";
  EXPECT_DOUBLE_EQ(cut_left_s(j, 1, 100, 108), 5) << "slower than planned: the unsent half still has 5 s";
  j.strokes_sent = 10;
  EXPECT_DOUBLE_EQ(cut_left_s(j, 1, 100, 120), 0) << "past the estimate with everything sent: 0, not negative";
  j.resume_from = 6;
  j.strokes_sent = 6;
  EXPECT_DOUBLE_EQ(cut_left_s(j, 2, 100, 100), 8) << "resumed at stroke 6, at half speed: 4 planned s take 8";
}

StrokePlan castle_plan(const drivers::DeviceProfile& p) {
  const Pattern pattern = make_pattern(parse_model(read_text_file(kSrc + "/examples/voxel/castle.json"), "castle"));
  return plan_strokes(pattern, p.plan);
}

TEST(CutJob, PlanJsonRoundTrips) {
  const drivers::DeviceProfile p = drivers::load_profile(kSrc + "/configs/devices/sim.toml");
  const StrokePlan plan = castle_plan(p);
  const StrokePlan back = plan_from_json(plan_to_json(plan), "plan.json");
  EXPECT_EQ(back.sheet, plan.sheet) << "sheet survives";
  EXPECT_EQ(back.strokes, plan.strokes) << "strokes survive bit for bit";
  EXPECT_EQ(encode_job(back, p.dialect, p.tools, 7).bytes, encode_job(plan, p.dialect, p.tools, 7).bytes)
      << "a resumed job re-read from its file sends the same bytes";
  EXPECT_THROW(plan_from_json("{\"format\":\"x\"}", "p"), Error) << "a foreign file is refused";
}

}  // namespace

namespace {

TEST(PreviewCache, DropsTheLeastRecentlyUsedUnderItsByteCap) {
  popcut::daemon::PreviewCache cache(100);     // bytes of keys and pictures together
  cache.put("a", std::string(39, 'A'));        // 40 bytes
  cache.put("b", std::string(39, 'B'));        // 80
  ASSERT_TRUE(cache.get("a")) << "a is held";  // a is now the most recent
  cache.put("c", std::string(39, 'C'));        // 120 > 100: b, the least recently used, goes
  EXPECT_FALSE(cache.get("b")) << "the least recently used picture was dropped";
  EXPECT_EQ(cache.get("a").value_or(""), std::string(39, 'A')) << "the recently used one stays";
  EXPECT_EQ(cache.get("c").value_or(""), std::string(39, 'C')) << "the new one is held";
  cache.put("d", std::string(200, 'D'));
  EXPECT_FALSE(cache.get("d")) << "a picture larger than the whole cap is not held";
  EXPECT_TRUE(cache.get("a") && cache.get("c")) << "and it did not push the others out";
  popcut::daemon::PreviewCache none(0);
  none.put("x", "y");
  EXPECT_FALSE(none.get("x")) << "a cap of 0 holds nothing";
}

}  // namespace
