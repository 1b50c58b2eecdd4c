// Shop statistics: job_stats on crafted SQLite stores, the per-run cutting time the store keeps, and GET /api/v1/stats.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <ctime>
#include <string>

#include "popcutd_process.h"
#include "stats.h"
#include "store.h"

namespace {
using namespace popcut::daemon;
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::TempDir;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kAdmin = "admin-change-me-0123456789";  // configs/popcutd.toml's tokens
const std::string kKiosk = "kiosk-change-me-0123456789";

// Local time (the TZ the test runs in, as popcutd counts days): day `day_offset` from 2026-12-02.
double local_s(int day_offset, int hour, int minute = 0) {
  std::tm tm{};
  tm.tm_year = 2026 - 1900;
  tm.tm_mon = 11;
  tm.tm_mday = 2 + day_offset;
  tm.tm_hour = hour;
  tm.tm_min = minute;
  tm.tm_isdst = -1;
  return static_cast<double>(std::mktime(&tm));
}

void sql(const std::string& path, const std::string& statements) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* err = nullptr;
  const int rc = sqlite3_exec(db, statements.c_str(), nullptr, nullptr, &err);
  const std::string msg = err ? err : "";
  sqlite3_free(err);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << msg << " in " << statements;
}

// One crafted job row: state, device, created, finished, last cut, cutting time of ended runs, current run start.
std::string row(const std::string& state, const std::string& device, double created, double finished, double last_cut,
                double cutting_s, double run_started = 0) {
  return "INSERT INTO jobs (owner, name, target_device, target_profile, device, state, created_at, started_at,"
         " finished_at, last_cut_at, cutting_s, run_started_at) VALUES ('k', 'card', '', 'sim', '" +
         device + "', '" + state + "', " + std::to_string(created) + ", " + std::to_string(created) + ", " +
         std::to_string(finished) + ", " + std::to_string(last_cut) + ", " + std::to_string(cutting_s) + ", " +
         std::to_string(run_started) + ");";
}

class Stats : public ::testing::Test {
 protected:
  TempDir dir_{"popcut-stats"};
  std::string db() const { return (dir_.path() / "jobs.db").string(); }
};

TEST_F(Stats, CountsJobsPerLocalDayAndCuttingTimePerDevice) {
  { JobStore create(db()); }  // today's schema, then rows as a day of work would leave them
  const double now = local_s(0, 15);
  sql(db(), row("done", "sim-a", local_s(0, 9), local_s(0, 10), local_s(0, 10), 600) +
                row("failed", "sim-a", local_s(-1, 9), local_s(-1, 11), local_s(-1, 11), 30) +
                row("cancelled", "", local_s(0, 8), local_s(0, 8, 5), 0, 0) +              // cancelled while waiting
                row("done", "sim-a", local_s(-5, 9), local_s(0, 1), local_s(0, 1), 120) +  // queued long before
                row("cutting", "sim-b", local_s(0, 14), 0, local_s(0, 14, 58), 300, now - 120) +
                row("interrupted", "sim-b", local_s(-1, 20), 0, local_s(-1, 21), 50) +
                row("done", "old-cutter", local_s(-2, 9), local_s(-2, 10), local_s(-2, 10), 10) +
                row("done", "sim-a", local_s(-4, 9), local_s(-4, 10), local_s(-4, 10), 999) +  // before the window
                row("queued", "", local_s(0, 14, 30), 0, 0, 0));
  JobStore s(db());
  const double since = stats_window_start(3, now);
  EXPECT_EQ(since, local_s(-2, 0)) << "the window starts at local midnight two days back";
  const StatsReport r = job_stats(s.stats_rows(since), 3, now, {"sim-a", "sim-b", "sim-c"});
  ASSERT_EQ(r.days.size(), 3u);
  EXPECT_EQ(r.days[0].date, "2026-11-30");
  EXPECT_EQ(r.days[2].date, "2026-12-02") << "oldest first, today last";
  EXPECT_EQ(r.days[2].submitted, 4) << "created today: the done, the cancelled, the cutting and the queued job";
  EXPECT_EQ(r.days[2].done, 2) << "finished today, one of them queued five days ago";
  EXPECT_EQ(r.days[2].cancelled, 1);
  EXPECT_EQ(r.days[2].failed, 0);
  EXPECT_EQ(r.days[1].submitted, 2);
  EXPECT_EQ(r.days[1].failed, 1);
  EXPECT_EQ(r.days[0].done, 1) << "the removed cutter's job still counts for its day";
  ASSERT_EQ(r.devices.size(), 4u) << "every configured cutter, then the one only in the history";
  EXPECT_EQ(r.devices[0].name, "sim-a");
  EXPECT_EQ(r.devices[0].jobs, 3);
  EXPECT_EQ(r.devices[0].done, 2);
  EXPECT_EQ(r.devices[0].failed, 1);
  EXPECT_DOUBLE_EQ(r.devices[0].cutting_s, 750) << "600 + 30 + 120; the job before the window is not counted";
  ASSERT_TRUE(r.devices[0].failure_rate.has_value());
  EXPECT_NEAR(*r.devices[0].failure_rate, 1.0 / 3, 1e-9) << "failed / (done + failed)";
  EXPECT_EQ(r.devices[1].name, "sim-b");
  EXPECT_EQ(r.devices[1].jobs, 0) << "neither of its jobs has ended";
  EXPECT_NEAR(r.devices[1].cutting_s, 300 + 120 + 50, 1e-6)
      << "ended runs, the run in progress up to now, the interrupted job";
  EXPECT_FALSE(r.devices[1].failure_rate.has_value()) << "no rate without an ended job";
  EXPECT_EQ(r.devices[2].name, "sim-c");
  EXPECT_EQ(r.devices[2].cutting_s, 0) << "a configured cutter with no work is listed with zeros";
  EXPECT_EQ(r.devices[3].name, "old-cutter");
  EXPECT_FALSE(r.devices[3].configured);
  EXPECT_EQ(r.devices[3].jobs, 1);
}

TEST_F(Stats, ADayWindowHoldsOnlyToday) {
  { JobStore create(db()); }
  sql(db(), row("done", "sim-a", local_s(-1, 23, 59), local_s(0, 0, 1), local_s(0, 0, 1), 60));
  JobStore s(db());
  const double now = local_s(0, 0, 30);
  const StatsReport r = job_stats(s.stats_rows(stats_window_start(1, now)), 1, now, {"sim-a"});
  ASSERT_EQ(r.days.size(), 1u);
  EXPECT_EQ(r.days[0].submitted, 0) << "submitted yesterday, a minute before midnight";
  EXPECT_EQ(r.days[0].done, 1) << "done today";
  EXPECT_DOUBLE_EQ(r.devices[0].cutting_s, 60);
}

// A resumed job's cutting time is the sum of its runs: the hours it sat interrupted are not in it,
// and a run cut short by a crash counts up to its last confirmed stroke.
TEST_F(Stats, ARunsTimeIsAddedAsItEndsAndTheGapBetweenRunsIsNot) {
  std::int64_t id = 0;
  {
    JobStore s(db());
    id = *s.insert({"kiosk", "card", "dev1", "sim", "{}"}, 100);
    s.claim_for_planning();
    s.set_planned(id, 10, 5.0);
    ASSERT_TRUE(s.claim_for_device("dev1", "sim"));
    const double now = unix_now_s();
    // The run began 100 s ago (as if the cut had taken that long), the job hours ago.
    sql(db(), "UPDATE jobs SET run_started_at=" + std::to_string(now - 100) +
                  ", started_at=" + std::to_string(now - 7200) + " WHERE id=" + std::to_string(id));
    s.set_progress(id, 4);
    s.finish(id, JobState::interrupted, "interrupted", "SIGTERM");
    EXPECT_NEAR(s.stats_rows(0).at(0).cutting_s, 100, 2) << "the first run";
    ASSERT_EQ(s.resume(id), ResumeResult::resumed);
    ASSERT_TRUE(s.claim_for_device("dev1", "sim"));
    // The second run began 30 s ago; its last confirmed stroke 10 s ago; then popcutd is killed.
    const double later = unix_now_s();
    s.set_progress(id, 6);
    sql(db(), "UPDATE jobs SET run_started_at=" + std::to_string(later - 30) +
                  ", last_cut_at=" + std::to_string(later - 10) + " WHERE id=" + std::to_string(id));
  }
  JobStore s(db());
  EXPECT_EQ(s.recover().interrupted, 1);
  EXPECT_NEAR(s.stats_rows(0).at(0).cutting_s, 120, 2) << "100 s, then 20 s up to the last confirmed stroke";
  ASSERT_EQ(s.resume(id), ResumeResult::resumed);
  ASSERT_TRUE(s.claim_for_device("dev1", "sim"));
  sql(db(), "UPDATE jobs SET run_started_at=" + std::to_string(unix_now_s() - 40) + " WHERE id=" + std::to_string(id));
  s.finish(id, JobState::done, "", "");
  const StatsRow r = s.stats_rows(0).at(0);
  EXPECT_NEAR(r.cutting_s, 160, 2) << "three runs; not the two hours since the job first started";
  EXPECT_EQ(r.state, JobState::done);
  EXPECT_EQ(r.device, "dev1");
}

TEST_F(Stats, AnOlderDatabaseGetsTheCuttingTimeOfItsSingleRunJobs) {
  sql(db(),
      "CREATE TABLE jobs (id INTEGER PRIMARY KEY AUTOINCREMENT, owner TEXT NOT NULL, name TEXT NOT NULL,"
      " target_device TEXT NOT NULL, target_profile TEXT NOT NULL, device TEXT NOT NULL DEFAULT '',"
      " state TEXT NOT NULL, error_code TEXT NOT NULL DEFAULT '', error_message TEXT NOT NULL DEFAULT '',"
      " strokes_total INTEGER NOT NULL DEFAULT 0, strokes_sent INTEGER NOT NULL DEFAULT 0,"
      " resume_from INTEGER NOT NULL DEFAULT 0, est_time_s REAL NOT NULL DEFAULT 0,"
      " created_at REAL NOT NULL, started_at REAL NOT NULL DEFAULT 0, finished_at REAL NOT NULL DEFAULT 0,"
      " cancel_requested INTEGER NOT NULL DEFAULT 0, sim_match INTEGER NOT NULL DEFAULT 0, strokes_executed INTEGER,"
      " resume_point TEXT, material TEXT NOT NULL DEFAULT '');"
      "INSERT INTO jobs (owner, name, target_device, target_profile, device, state, created_at, started_at, "
      "finished_at)"
      " VALUES ('k', 'one run', '', 'sim', 'a', 'done', 90, 100, 160);"
      "INSERT INTO jobs (owner, name, target_device, target_profile, device, state, created_at, started_at, "
      "finished_at,"
      " resume_point) VALUES ('k', 'resumed', '', 'sim', 'a', 'done', 90, 100, 9000, 'received');"
      "INSERT INTO jobs (owner, name, target_device, target_profile, state, created_at, finished_at)"
      " VALUES ('k', 'never cut', '', 'sim', 'cancelled', 90, 95);");
  JobStore s(db());
  const std::vector<StatsRow> rows = s.stats_rows(0);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_DOUBLE_EQ(rows[0].cutting_s, 60) << "one run, from started_at to finished_at";
  EXPECT_DOUBLE_EQ(rows[0].last_cut_at, 160);
  EXPECT_DOUBLE_EQ(rows[1].cutting_s, 0) << "a resumed job's runs were not recorded: not guessed from its span";
  EXPECT_DOUBLE_EQ(rows[2].cutting_s, 0) << "never cut";
}

TEST(StatsHttp, AnswersTheAdminAndRefusesBadDays) {
  TempDir dir("popcut-stats-http");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  httplib::Client admin = d.client(kAdmin);
  const std::string model = popcut::testing::read_file(kSrc + "/examples/voxel/pyramid.json");
  const popcut::testing::Reply sub =
      popcut::testing::post_json(admin, "/api/v1/jobs", R"({"device": "sim-a", "model": )" + model + "}");
  ASSERT_EQ(sub.status, 201) << sub.body.dump();
  const std::string job = "/api/v1/jobs/" + std::to_string(sub.body["id"].get<int>());
  ASSERT_TRUE(popcut::testing::wait_until([&] { return get_json(admin, job).body["state"] == "done"; }, 120));
  const popcut::testing::Reply r = get_json(admin, "/api/v1/stats?days=2");
  ASSERT_EQ(r.status, 200) << r.body.dump();
  ASSERT_EQ(r.body["days"].size(), 2u);
  const json today = r.body["days"][1];
  EXPECT_EQ(today["jobs"], 1);
  EXPECT_EQ(today["done"], 1);
  EXPECT_EQ(today["failed"], 0);
  ASSERT_EQ(r.body["devices"].size(), 2u) << r.body.dump();
  EXPECT_EQ(r.body["devices"][0]["name"], "sim-a");
  EXPECT_EQ(r.body["devices"][0]["jobs"], 1);
  EXPECT_EQ(r.body["devices"][0]["failure_rate"], 0.0);
  EXPECT_GE(r.body["devices"][0]["cutting_s"].get<double>(), 0.0);
  EXPECT_EQ(r.body["devices"][1]["jobs"], 0);
  EXPECT_TRUE(r.body["devices"][1]["failure_rate"].is_null()) << "no rate without a job";
  EXPECT_EQ(get_json(admin, "/api/v1/stats").body["days"].size(), 7u) << "a week by default";
  EXPECT_EQ(get_json(admin, "/api/v1/stats?days=366").status, 200);
  for (const char* bad : {"0", "367", "-1", "7.5", "", "x", "0007", "1e2"}) {
    const popcut::testing::Reply b = get_json(admin, std::string("/api/v1/stats?days=") + bad);
    EXPECT_EQ(b.status, 400) << "days=" << bad;
    EXPECT_EQ(b.body["error"].value("field", ""), "days") << "days=" << bad << ": " << b.body.dump();
  }
  EXPECT_EQ(get_json(admin, "/api/v1/stats?days=1&days=2").status, 400) << "days given twice";
  EXPECT_EQ(get_json(admin, "/api/v1/stats?day=1").status, 400) << "a parameter it does not take";
  httplib::Client kiosk = d.client(kKiosk);
  const popcut::testing::Reply k = get_json(kiosk, "/api/v1/stats");
  EXPECT_EQ(k.status, 403);
  EXPECT_EQ(k.body["error"]["code"], "forbidden");
  httplib::Client nobody = d.client("");
  EXPECT_EQ(get_json(nobody, "/api/v1/stats").status, 401);
  // The operator page's files come without a token; the page asks for it.
  for (const auto& [path, type] : {std::pair{"/operator", "text/html"},
                                   {"/operator/app.js", "text/javascript"},
                                   {"/operator/app.css", "text/css"}}) {
    const httplib::Result page = nobody.Get(path);
    ASSERT_TRUE(page) << path;
    EXPECT_EQ(page->status, 200) << path;
    EXPECT_EQ(page->get_header_value("Content-Type").rfind(type, 0), 0u) << path;
  }
}

}  // namespace
