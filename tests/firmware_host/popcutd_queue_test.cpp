// The queue: priority and `before` in the store and over PATCH /api/v1/jobs/N, Idempotency-Key, and the list's filters.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/wait.h>

#include <algorithm>
#include <string>
#include <vector>

#include "popcutd_process.h"
#include "store.h"

namespace {
using namespace popcut::daemon;
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::Reply;
using popcut::testing::TempDir;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kAdmin = "admin-change-me-0123456789";  // configs/popcutd.toml's tokens
const std::string kKiosk = "kiosk-change-me-0123456789";

NewJob job_for(const std::string& device, const std::string& name = "card") {
  return {"kiosk", name, device, "sim", "{}"};
}

// The order the device would take its ready jobs in: claims them all.
std::vector<std::int64_t> claim_order(JobStore& s, const std::string& device) {
  std::vector<std::int64_t> out;
  while (const std::optional<Job> j = s.claim_for_device(device, "sim")) out.push_back(j->id);
  return out;
}

void plan_all(JobStore& s) {
  while (const std::optional<Job> j = s.claim_for_planning()) s.set_planned(j->id, 10, 1.0);
}

class Queue : public ::testing::Test {
 protected:
  TempDir dir_{"popcut-queue"};
  std::string db() const { return (dir_.path() / "jobs.db").string(); }
};

TEST_F(Queue, PriorityComesFirstThenTheOrderOfSubmission) {
  JobStore s(db());
  const std::int64_t a = *s.insert(job_for("d"), 100), b = *s.insert(job_for("d"), 100),
                     c = *s.insert(job_for("d"), 100);
  ASSERT_EQ(s.reorder(c, {5, std::nullopt}), ReorderResult::moved);
  EXPECT_EQ(s.place_in_line(*s.get(c)), 0) << "the higher priority is ahead of older jobs";
  EXPECT_EQ(s.place_in_line(*s.get(a)), 1);
  EXPECT_EQ(s.place_in_line(*s.get(b)), 2);
  ASSERT_EQ(s.reorder(a, {-1, std::nullopt}), ReorderResult::moved);
  EXPECT_EQ(s.place_in_line(*s.get(a)), 2) << "a negative priority goes behind the default";
  plan_all(s);
  EXPECT_EQ(claim_order(s, "d"), (std::vector<std::int64_t>{c, b, a}));
}

TEST_F(Queue, BeforePutsAJobJustAheadOfAnotherAndTakesItsPriority) {
  JobStore s(db());
  std::vector<std::int64_t> ids;
  for (int i = 0; i < 4; ++i) ids.push_back(*s.insert(job_for("d"), 100));
  ASSERT_EQ(s.reorder(ids[1], {3, std::nullopt}), ReorderResult::moved);
  ASSERT_EQ(s.reorder(ids[3], {std::nullopt, ids[1]}), ReorderResult::moved);
  EXPECT_EQ(s.get(ids[3])->priority, 3) << "moved ahead of a priority-3 job, it is one";
  EXPECT_EQ(s.reorder(ids[2], {0, ids[1]}), ReorderResult::priority_mismatch);
  ASSERT_EQ(s.reorder(ids[0], {std::nullopt, ids[2]}), ReorderResult::moved) << "behind its old place";
  plan_all(s);
  EXPECT_EQ(claim_order(s, "d"), (std::vector<std::int64_t>{ids[3], ids[1], ids[0], ids[2]}));
}

TEST_F(Queue, ManyMovesToOneSpotKeepAnExactOrder) {
  JobStore s(db());
  std::vector<std::int64_t> ids;
  for (int i = 0; i < 80; ++i) ids.push_back(*s.insert(job_for("d"), 1000));
  // From the last, each job in turn goes just ahead of the second, behind the one moved before it:
  // halving one gap 78 times runs out of a double's bits, and the store spreads the ranks again.
  std::vector<std::int64_t> expected = {ids[0]};
  for (std::size_t i = ids.size() - 1; i >= 2; --i) {
    ASSERT_EQ(s.reorder(ids[i], {std::nullopt, ids[1]}), ReorderResult::moved) << i;
  }
  for (std::size_t i = ids.size() - 1; i >= 2; --i) expected.push_back(ids[i]);  // each just ahead of ids[1]
  expected.push_back(ids[1]);
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_EQ(s.place_in_line(*s.get(expected[i])), static_cast<int>(i));
  plan_all(s);
  EXPECT_EQ(claim_order(s, "d"), expected);
}

TEST_F(Queue, OnlyWaitingJobsMove) {
  JobStore s(db());
  const std::int64_t a = *s.insert(job_for("d"), 100), b = *s.insert(job_for("d"), 100);
  plan_all(s);
  ASSERT_TRUE(s.claim_for_device("d", "sim"));
  EXPECT_EQ(s.reorder(a, {2, std::nullopt}), ReorderResult::not_waiting);
  EXPECT_EQ(s.reorder(b, {std::nullopt, a}), ReorderResult::before_not_waiting);
  EXPECT_EQ(s.reorder(b, {std::nullopt, 999}), ReorderResult::before_not_found);
  EXPECT_EQ(s.reorder(999, {1, std::nullopt}), ReorderResult::not_found);
  EXPECT_EQ(s.get(b)->priority, 0) << "a refused move changes nothing";
}

TEST_F(Queue, AKeyReturnsItsFirstJobPerOwnerAndRefusesAnotherRequest) {
  JobStore s(db());
  NewJob nj = job_for("d");
  nj.idempotency_key = "k-1";
  nj.request_sha256 = "aaa";
  const SubmitResult first = s.submit(nj, 100);
  ASSERT_EQ(first.outcome, Submitted::created);
  const SubmitResult again = s.submit(nj, 100);
  EXPECT_EQ(again.outcome, Submitted::replayed);
  EXPECT_EQ(again.id, first.id);
  nj.request_sha256 = "bbb";
  EXPECT_EQ(s.submit(nj, 100).outcome, Submitted::key_reused);
  nj.owner = "someone-else";
  EXPECT_EQ(s.submit(nj, 100).outcome, Submitted::created) << "keys are each token's own";
  nj.idempotency_key.clear();
  EXPECT_EQ(s.submit(nj, 100).outcome, Submitted::created);
  EXPECT_EQ(s.submit(nj, 100).outcome, Submitted::created) << "without a key every submission is a job";
  EXPECT_EQ(s.count_submitted(), 4);
}

TEST_F(Queue, AReplayAnswersEvenWhenTheQueueIsFull) {
  JobStore s(db());
  NewJob nj = job_for("d");
  nj.idempotency_key = "k";
  const SubmitResult first = s.submit(nj, 1);
  ASSERT_EQ(first.outcome, Submitted::created);
  EXPECT_EQ(s.submit(nj, 1).outcome, Submitted::replayed) << "the retry finds its job, not a full queue";
  nj.idempotency_key = "k2";
  EXPECT_EQ(s.submit(nj, 1).outcome, Submitted::queue_full);
}

TEST_F(Queue, AnOlderDatabaseGetsTheQueueColumns) {
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(this->db().c_str(), &db), SQLITE_OK);
    const char* sql =
        "CREATE TABLE jobs (id INTEGER PRIMARY KEY AUTOINCREMENT, owner TEXT NOT NULL, name TEXT NOT NULL,"
        " target_device TEXT NOT NULL, target_profile TEXT NOT NULL, device TEXT NOT NULL DEFAULT '',"
        " state TEXT NOT NULL, error_code TEXT NOT NULL DEFAULT '', error_message TEXT NOT NULL DEFAULT '',"
        " strokes_total INTEGER NOT NULL DEFAULT 0, strokes_sent INTEGER NOT NULL DEFAULT 0,"
        " resume_from INTEGER NOT NULL DEFAULT 0, est_time_s REAL NOT NULL DEFAULT 0,"
        " created_at REAL NOT NULL, started_at REAL NOT NULL DEFAULT 0, finished_at REAL NOT NULL DEFAULT 0,"
        " cancel_requested INTEGER NOT NULL DEFAULT 0, sim_match INTEGER NOT NULL DEFAULT 0);"
        "INSERT INTO jobs (owner, name, target_device, target_profile, state, created_at) VALUES"
        " ('k', 'old', 'd', 'sim', 'queued', 1), ('k', 'older', 'd', 'sim', 'queued', 2);";
    ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  JobStore s(db());
  EXPECT_EQ(s.get(1)->priority, 0);
  EXPECT_EQ(s.get(2)->queue_rank, 2) << "the rank of a job never moved is its id";
  ASSERT_EQ(s.reorder(2, {std::nullopt, 1}), ReorderResult::moved);
  EXPECT_EQ(s.place_in_line(*s.get(2)), 0);
}

// Over HTTP, with the device paused so that the jobs wait where the test puts them.
class QueueHttp : public ::testing::Test {
 protected:
  TempDir dir_{"popcut-queue-http"};
  PopcutdProcess d_{POPCUTD, kSrc + "/configs/popcutd.toml", (dir_.path() / "data").string()};
  httplib::Client admin_ = d_.client(kAdmin);
  httplib::Client kiosk_ = d_.client(kKiosk);
  const std::string model_ = popcut::testing::read_file(kSrc + "/examples/voxel/pyramid.json");

  std::int64_t submit(const std::string& name) {
    const Reply r =
        post_json(kiosk_, "/api/v1/jobs", R"({"device": "sim-a", "name": ")" + name + R"(", "model": )" + model_ + "}");
    EXPECT_EQ(r.status, 201) << r.body.dump();
    return r.body.value("id", std::int64_t{0});
  }
  Reply patch(httplib::Client& c, std::int64_t id, const std::string& body) {
    const httplib::Result r = c.Patch("/api/v1/jobs/" + std::to_string(id), body, "application/json");
    if (!r) return {0, json()};
    return {r->status, json::parse(r->body, nullptr, false)};
  }
  int place(std::int64_t id) { return get_json(admin_, "/api/v1/jobs/" + std::to_string(id)).body["place_in_line"]; }
};

TEST_F(QueueHttp, AnAdminReordersAndTheDeviceCutsInTheNewOrder) {
  ASSERT_EQ(post_json(admin_, "/api/v1/devices/sim-a/pause", "").status, 200);
  const std::int64_t a = submit("a"), b = submit("b"), c = submit("c");
  Reply r = patch(admin_, c, R"({"before": )" + std::to_string(a) + "}");
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_EQ(r.body["place_in_line"], 0);
  EXPECT_EQ(place(a), 1);
  r = patch(admin_, b, R"({"priority": 10})");
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_EQ(r.body["priority"], 10);
  EXPECT_EQ(place(b), 0);
  EXPECT_EQ(place(c), 1);
  EXPECT_EQ(place(a), 2);
  // A device takes the first planned job in this order; all are, before it may take any.
  for (const std::int64_t id : {a, b, c}) {
    const std::string path = "/api/v1/jobs/" + std::to_string(id);
    ASSERT_TRUE(popcut::testing::wait_until([&] { return get_json(admin_, path).body["state"] == "ready"; }, 300));
  }
  ASSERT_EQ(post_json(admin_, "/api/v1/devices/sim-a/resume", "").status, 200);
  for (const std::int64_t id : {b, c, a}) {
    const std::string path = "/api/v1/jobs/" + std::to_string(id);
    ASSERT_TRUE(popcut::testing::wait_until([&] { return get_json(admin_, path).body["state"] == "done"; }, 300));
  }
  // The API rounds its times; the database holds them whole.
  JobStore store((dir_.path() / "data" / "jobs.db").string());
  std::vector<std::int64_t> by_start;
  for (const Job& j : store.list({})) by_start.push_back(j.id);
  std::sort(by_start.begin(), by_start.end(),
            [&](std::int64_t x, std::int64_t y) { return store.get(x)->started_at < store.get(y)->started_at; });
  EXPECT_EQ(by_start, (std::vector<std::int64_t>{b, c, a})) << "cut in the order the admin set";
  r = patch(admin_, a, R"({"priority": 1})");
  EXPECT_EQ(r.status, 409) << "a done job has no place in the queue";
}

TEST_F(QueueHttp, EveryBadMoveIsRefusedWithItsField) {
  ASSERT_EQ(post_json(admin_, "/api/v1/devices/sim-a/pause", "").status, 200);
  const std::int64_t a = submit("a"), b = submit("b");
  const auto field = [&](const std::string& body) {
    const Reply r = patch(admin_, a, body);
    return std::to_string(r.status) + " " + r.body["error"].value("field", std::string("-"));
  };
  EXPECT_EQ(field(R"({"priority": 2.5})"), "400 priority");
  EXPECT_EQ(field(R"({"priority": 101})"), "400 priority");
  EXPECT_EQ(field(R"({"priority": 18446744073709551615})"), "400 priority");
  EXPECT_EQ(field(R"({"priority": "high"})"), "400 priority");
  EXPECT_EQ(field(R"({"before": 0})"), "400 before");
  EXPECT_EQ(field(R"({"before": )" + std::to_string(a) + "}"), "400 before") << "ahead of itself";
  EXPECT_EQ(field(R"({"before": 99999})"), "400 before");
  EXPECT_EQ(field(R"({"after": 1})"), "400 after");
  EXPECT_EQ(field(R"({})"), "400 priority");
  EXPECT_EQ(patch(admin_, a, "[1]").status, 400);
  EXPECT_EQ(patch(kiosk_, a, R"({"priority": 1})").status, 403) << "moving jobs is an admin's";
  EXPECT_EQ(patch(admin_, 99999, R"({"priority": 1})").status, 404);
  ASSERT_EQ(patch(admin_, b, R"({"priority": 4})").status, 200);
  EXPECT_EQ(field(R"({"priority": 1, "before": )" + std::to_string(b) + "}"), "400 priority");
  EXPECT_EQ(place(a), 1) << "nothing refused moved it";
  const httplib::Result put = admin_.Put("/api/v1/jobs/" + std::to_string(a), "{}", "application/json");
  ASSERT_TRUE(put);
  EXPECT_EQ(put->status, 405);
  EXPECT_EQ(put->get_header_value("Allow"), "GET, HEAD, PATCH");
}

TEST_F(QueueHttp, ARetriedSubmissionWithItsKeyIsOneJob) {
  ASSERT_EQ(post_json(admin_, "/api/v1/devices/sim-a/pause", "").status, 200);
  const std::string body = R"({"device": "sim-a", "name": "once", "model": )" + model_ + "}";
  const httplib::Headers key = {{"Idempotency-Key", "9b2f4c1e-6f0a-4c55-9d7e-0c1f2a3b4c5d"}};
  const httplib::Result first = kiosk_.Post("/api/v1/jobs", key, body, "application/json");
  ASSERT_TRUE(first);
  ASSERT_EQ(first->status, 201) << first->body;
  const httplib::Result again = kiosk_.Post("/api/v1/jobs", key, body, "application/json");
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200);
  EXPECT_EQ(again->get_header_value("Idempotent-Replayed"), "true");
  EXPECT_EQ(json::parse(again->body)["id"], json::parse(first->body)["id"]);
  const std::string other = R"({"device": "sim-a", "name": "another", "model": )" + model_ + "}";
  const httplib::Result reused = kiosk_.Post("/api/v1/jobs", key, other, "application/json");
  ASSERT_TRUE(reused);
  EXPECT_EQ(reused->status, 422);
  EXPECT_EQ(json::parse(reused->body)["error"]["field"], "Idempotency-Key");
  const std::vector<std::string> bad_keys = {"has space", "cl\xc3\xa9", std::string(256, 'k')};
  for (const std::string& bad : bad_keys) {
    const httplib::Result r = kiosk_.Post("/api/v1/jobs", {{"Idempotency-Key", bad}}, body, "application/json");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << "'" << bad.substr(0, 20) << "'";
  }
  const Reply list = get_json(admin_, "/api/v1/jobs");
  EXPECT_EQ(list.body["jobs"].size(), 1u) << "one job for three tries of one key and the refused ones";
}

TEST_F(QueueHttp, TheListFiltersByStateDeviceAndTime) {
  const std::int64_t done = submit("first");
  const std::string path = "/api/v1/jobs/" + std::to_string(done);
  ASSERT_TRUE(popcut::testing::wait_until([&] { return get_json(admin_, path).body["state"] == "done"; }, 300));
  const double finished = get_json(admin_, path).body["finished_at"];
  ASSERT_EQ(post_json(admin_, "/api/v1/devices/sim-a/pause", "").status, 200);
  const std::int64_t waiting = submit("second");
  const auto ids = [&](const std::string& query) {
    std::vector<std::int64_t> out;
    const Reply r = get_json(admin_, "/api/v1/jobs?" + query);
    EXPECT_EQ(r.status, 200) << query << " " << r.body.dump();
    for (const json& j : r.body["jobs"]) out.push_back(j["id"]);
    return out;
  };
  EXPECT_EQ(ids("state=done"), std::vector<std::int64_t>{done});
  EXPECT_EQ(ids("state=done,queued,planning,ready"), (std::vector<std::int64_t>{waiting, done}));
  EXPECT_EQ(ids("device=sim-a"), (std::vector<std::int64_t>{waiting, done}));
  EXPECT_TRUE(ids("device=sim-b").empty());
  EXPECT_EQ(ids("since=" + std::to_string(static_cast<long long>(finished) + 3600)).size(), 0u);
  EXPECT_EQ(ids("state=done&since=" + std::to_string(static_cast<long long>(finished) - 1)),
            std::vector<std::int64_t>{done});
  const std::vector<std::string> bad_queries = {"state=finished", "state=", "since=-5", "since=yesterday",
                                                "device=../x"};
  for (const std::string& bad : bad_queries) {
    const Reply r = get_json(admin_, "/api/v1/jobs?" + bad);
    EXPECT_EQ(r.status, 400) << bad;
    EXPECT_EQ(r.body["error"]["field"], bad.substr(0, bad.find('='))) << bad;
  }
}

// The same through the popcut binary: submit with a key, move, and the list's filters.
TEST_F(QueueHttp, TheCliSubmitsOnceMovesAndFilters) {
  ASSERT_EQ(post_json(admin_, "/api/v1/devices/sim-a/pause", "").status, 200);
  const std::string out = (dir_.path() / "cli.out").string();
  const auto cli = [&](const std::string& args, const std::string& token) {
    const std::string cmd = std::string(POPCUT_CLI) + " " + args +
                            " --json --server http://127.0.0.1:" + std::to_string(d_.port()) + " --token " + token +
                            " >" + out + " 2>/dev/null";
    const int status = std::system(cmd.c_str());
    return std::pair{WIFEXITED(status) ? WEXITSTATUS(status) : -1, popcut::testing::read_file(out)};
  };
  const std::string keyed = "submit " + kSrc + "/examples/voxel/pyramid.json --device sim-a --idempotency-key ord-7";
  const auto [code1, first] = cli(keyed, kKiosk);
  ASSERT_EQ(code1, 0) << first;
  const auto [code2, again] = cli(keyed, kKiosk);
  ASSERT_EQ(code2, 0) << again;
  const std::int64_t a = json::parse(first)["id"];
  EXPECT_EQ(json::parse(again)["id"], a) << "the same key, the same job";
  const std::int64_t b = submit("b");
  const auto [moved, moved_out] = cli("move " + std::to_string(b) + " --before " + std::to_string(a), kAdmin);
  ASSERT_EQ(moved, 0) << moved_out;
  EXPECT_EQ(json::parse(moved_out)["place_in_line"], 0);
  EXPECT_EQ(cli("move " + std::to_string(a) + " --priority 1", kKiosk).first, 2) << "the kiosk token may not";
  EXPECT_EQ(cli("move " + std::to_string(a), kAdmin).first, 2) << "a move needs --priority or --before";
  const auto [listed, list] = cli("jobs --state queued,planning,ready --device sim-a --since 1h", kAdmin);
  ASSERT_EQ(listed, 0) << list;
  EXPECT_EQ(json::parse(list)["jobs"].size(), 2u) << list;
  EXPECT_EQ(json::parse(cli("jobs --state done", kAdmin).second)["jobs"].size(), 0u);
  EXPECT_EQ(cli("jobs --since yesterday", kAdmin).first, 2);
}

// copies: the cards nested on one sheet of the device, planned and cut as one job; more than a sheet holds, on more.
TEST_F(QueueHttp, CopiesAreNestedOnOneSheetAndCutAsPlanned) {
  const auto submit_copies = [&](const std::string& copies) {
    return post_json(kiosk_, "/api/v1/jobs",
                     R"({"device": "sim-a", "copies": )" + copies + R"(, "model": )" + model_ + "}");
  };
  const std::int64_t one = submit("one");
  const Reply three = submit_copies("3");
  ASSERT_EQ(three.status, 201) << three.body.dump();
  EXPECT_EQ(three.body["copies"], 3);
  std::vector<json> done;
  for (const std::int64_t id : {one, three.body["id"].get<std::int64_t>()}) {
    const std::string path = "/api/v1/jobs/" + std::to_string(id);
    ASSERT_TRUE(popcut::testing::wait_until([&] { return get_json(admin_, path).body["state"] == "done"; }, 300));
    done.push_back(get_json(admin_, path).body);
  }
  EXPECT_EQ(done[1]["strokes_total"], 3 * done[0]["strokes_total"].get<int>());
  EXPECT_TRUE(done[1]["sim_match"].get<bool>()) << "the simulator cut exactly the nested plan";
  EXPECT_NEAR(done[1]["cut_mm"].get<double>(), 3 * done[0]["cut_mm"].get<double>(), 1.0);
  // How many the sim profile's area holds, as popcut plan says.
  const std::string out = (dir_.path() / "plan.json").string();
  ASSERT_EQ(std::system((std::string(POPCUT_CLI) + " plan " + kSrc + "/examples/voxel/pyramid.json --profile " + kSrc +
                         "/configs/devices/sim.toml -o /dev/null --json >" + out)
                            .c_str()),
            0);
  const int fit = json::parse(popcut::testing::read_file(out))["copies"]["fit"];
  // One more than a sheet holds: two sheets (popcutd_copies_test.cpp cuts such a job).
  const Reply two_sheets = submit_copies(std::to_string(fit + 1));
  ASSERT_EQ(two_sheets.status, 201) << two_sheets.body.dump();
  const std::string two = "/api/v1/jobs/" + std::to_string(two_sheets.body["id"].get<std::int64_t>());
  ASSERT_TRUE(popcut::testing::wait_until([&] { return get_json(admin_, two).body["sheets"] == 2; }, 120))
      << "planned as two sheets: " << get_json(admin_, two).body.dump();
  EXPECT_EQ(post_json(admin_, two + "/cancel", "").status / 100, 2);
  const std::vector<std::string> bad_copies = {"0", "1001", "2.5", "\"3\""};
  for (const std::string& bad : bad_copies) {
    const Reply r = submit_copies(bad);
    EXPECT_EQ(r.status, 400) << bad;
    EXPECT_EQ(r.body["error"]["field"], "copies") << bad;
  }
}

}  // namespace
