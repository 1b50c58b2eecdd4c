// Webhooks and wear without popcutd: [[notify]] and blade_life_m checks, HMAC, the Notifier's queue against a loopback
// receiver, wear counts, the store's counters.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>

#include "config.h"
#include "daemon.h"
#include "notifier.h"
#include "popcut/error.h"
#include "popcutd_process.h"
#include "store.h"
#include "wear.h"

namespace {
namespace fs = std::filesystem;
using namespace popcut;
using namespace popcut::daemon;

const std::string kSrc = POPCUT_SOURCE_DIR;

const std::string kBase = R"(
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

DaemonConfig parse(const std::string& extra) { return parse_daemon_config(kBase + extra, kSrc + "/configs/test.toml"); }

// The error the config raises, or "" when it loads.
std::string error_of(const std::string& extra) {
  try {
    parse(extra);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(NotifyConfig, ReadsUrlEventsSecretAndDefaults) {
  const DaemonConfig c = parse(R"(
[[notify]]
url = "http://127.0.0.1:9000/hooks/popcut?shop=1"
events = ["job_done", "blade_worn"]
secret = "0123456789abcdef"
timeout_s = 2.5
retries = 1
[[notify]]
url = "http://[::1]/x"
)");
  ASSERT_EQ(c.notify.size(), 2u);
  EXPECT_EQ(c.notify[0].origin, "http://127.0.0.1:9000");
  EXPECT_EQ(c.notify[0].path, "/hooks/popcut?shop=1");
  EXPECT_EQ(c.notify[0].events, (std::vector<EventKind>{EventKind::job_done, EventKind::blade_worn}));
  EXPECT_EQ(c.notify[0].secret, "0123456789abcdef");
  EXPECT_DOUBLE_EQ(c.notify[0].timeout_s, 2.5);
  EXPECT_EQ(c.notify[0].retries, 1);
  EXPECT_EQ(c.notify[1].origin, "http://[::1]:80");
  EXPECT_EQ(c.notify[1].path, "/x");
  EXPECT_EQ(c.notify[1].events.size(), kEventKindNames.entries.size()) << "every event when none are named";
  EXPECT_EQ(c.notify[1].secret, "") << "no secret: no signature";
  EXPECT_EQ(c.notify[1].retries, 3);
  EXPECT_DOUBLE_EQ(c.notify[1].timeout_s, 5);
  EXPECT_TRUE(parse("").notify.empty());
}

TEST(NotifyConfig, RefusesBadEntriesNamingTheKey) {
  const auto refused = [](const std::string& entry, const std::string& key, const std::string& says) {
    const std::string e = error_of("[[notify]]\n" + entry + "\n");
    EXPECT_NE(e.find("[notify.0] " + key), std::string::npos) << entry << " -> " << e;
    EXPECT_NE(e.find(says), std::string::npos) << entry << " -> " << e;
    EXPECT_NE(e.find("test.toml"), std::string::npos) << "the file is named: " << e;
  };
  refused("events = [\"job_done\"]", "url", "missing");
  refused("url = \"ftp://x/y\"", "url", "expected http://");
  refused("url = \"127.0.0.1:9000/x\"", "url", "expected http://");
  refused("url = \"http:///x\"", "url", "no host");
  refused("url = \"http://h:0/x\"", "url", "1 to 65535");
  refused("url = \"http://h:70000/x\"", "url", "1 to 65535");
  refused("url = \"http://h:/x\"", "url", "1 to 65535");
  refused("url = \"http://u:p@h/x\"", "url", "user:password");
  refused("url = \"http://h/a b\"", "url", "%-encoded");
  refused("url = \"http://h/x#frag\"", "url", "fragment");
  refused("url = \"http://[::1/x\"", "url", "closing ']'");
  refused("url = \"http://[zz]/x\"", "url", "not an IPv6 address");
  refused("url = \"http://h/x\"\nevents = [\"job_dun\"]", "events",
          "\"job_dun\" is not an event (known: job_done, job_failed, job_interrupted, awaiting_sheet, device_error, "
          "blade_worn, job_paused)");
  refused("url = \"http://h/x\"\nevents = [3]", "events", "expected strings");
  refused("url = \"http://h/x\"\nevents = []", "events", "empty");
  refused("url = \"http://h/x\"\nevents = [\"job_done\", \"job_done\"]", "events", "twice");
  refused("url = \"http://h/x\"\nevents = \"job_done\"", "events", "expected an array");
  refused("url = \"http://h/x\"\nsecret = \"short\"", "secret", "at least 16");
  refused("url = \"http://h/x\"\ntimeout_s = 0", "timeout_s", "out of range");
  refused("url = \"http://h/x\"\nretries = -1", "retries", "out of range");
  refused("url = \"http://h/x\"\nretries = 21", "retries", "out of range");
  refused("url = \"http://h/x\"\nca_file = \"devices/sim.toml\"", "ca_file", "https:// URLs only");
  refused("url = \"https://h/x\"\nca_file = \"no-such.pem\"", "ca_file", "is not a file");
  refused("url = \"http://h/x\"\nsecrets = \"0123456789abcdef\"", "secrets", "unknown key");
  EXPECT_NE(error_of("[notify]\nurl = \"http://h/x\"\n").find("expected [[notify]] tables"), std::string::npos);
}

TEST(NotifyConfig, HttpsIsTakenWithTheSystemsOrAGivenCa) {
  // Debian builds cpp-httplib with OpenSSL (CPPHTTPLIB_OPENSSL_SUPPORT in its pkg-config flags).
  const DaemonConfig c = parse("[[notify]]\nurl = \"https://hooks.example.org/p\"\n");
  EXPECT_EQ(c.notify[0].origin, "https://hooks.example.org:443");
  const DaemonConfig ca = parse("[[notify]]\nurl = \"https://h/p\"\nca_file = \"devices/sim.toml\"\n");
  EXPECT_EQ(ca.notify[0].ca_file, kSrc + "/configs/devices/sim.toml") << "resolved beside the config file";
}

TEST(BladeLife, OptionalPositiveMetres) {
  EXPECT_FALSE(parse("").devices[0].blade_life_m.has_value());
  const std::string with = "blade_life_m = 250\n";
  const std::string text = kBase;
  const std::string cfg = text.substr(0, text.find("[[token]]")) + with + text.substr(text.find("[[token]]"));
  EXPECT_DOUBLE_EQ(*parse_daemon_config(cfg, kSrc + "/configs/test.toml").devices[0].blade_life_m, 250);
  const std::string bad =
      text.substr(0, text.find("[[token]]")) + "blade_life_m = 0\n" + text.substr(text.find("[[token]]"));
  try {
    parse_daemon_config(bad, kSrc + "/configs/test.toml");
    ADD_FAILURE() << "blade_life_m = 0 loads";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("[device.0] blade_life_m"), std::string::npos) << e.what();
  }
}

TEST(NotifySignature, HmacSha256MatchesRfc4231) {
  // RFC 4231 test case 2.
  EXPECT_EQ(hmac_sha256_hex("Jefe", "what do ya want for nothing?"),
            "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
  EXPECT_EQ(delivery_id().size(), 32u);
  EXPECT_NE(delivery_id(), delivery_id());
}

TEST(NotifyRetry, BackoffDoublesToACapAndOnlyRetriableAnswersRetry) {
  EXPECT_DOUBLE_EQ(retry_delay_s(1), 0.5);
  EXPECT_DOUBLE_EQ(retry_delay_s(2), 1);
  EXPECT_DOUBLE_EQ(retry_delay_s(3), 2);
  EXPECT_DOUBLE_EQ(retry_delay_s(20), 30);
  for (int s : {0, 408, 429, 500, 502, 503}) EXPECT_TRUE(worth_retrying(s)) << s;
  for (int s : {301, 400, 401, 403, 404, 410}) EXPECT_FALSE(worth_retrying(s)) << s;
}

TEST(NotifyBody, CarriesEventTimeJobAndDevice) {
  const nlohmann::json b = nlohmann::json::parse(event_body({EventKind::blade_worn, 12.5, nullptr, {{"name", "a"}}}));
  EXPECT_EQ(b["event"], "blade_worn");
  EXPECT_EQ(b["at"], 12.5);
  EXPECT_TRUE(b["job"].is_null());
  EXPECT_EQ(b["device"]["name"], "a");
}

TEST(NotifyOutcome, EventsFollowTheCommittedState) {
  Job j;
  j.state = JobState::done;
  EXPECT_EQ(outcome_events(j), std::vector<EventKind>{EventKind::job_done});
  j.state = JobState::interrupted;
  j.error_code = "interrupted";
  EXPECT_EQ(outcome_events(j), std::vector<EventKind>{EventKind::job_interrupted});
  j.error_code = "device_error";
  EXPECT_EQ(outcome_events(j), (std::vector<EventKind>{EventKind::job_interrupted, EventKind::device_error}));
  j.state = JobState::failed;
  EXPECT_EQ(outcome_events(j), (std::vector<EventKind>{EventKind::job_failed, EventKind::device_error}));
  j.state = JobState::cancelled;
  j.error_code = "cancelled";
  EXPECT_TRUE(outcome_events(j).empty()) << "a cancel was asked for";
}

// A loopback receiver whose handler can be held: what the Notifier's queue does behind a hanging endpoint.
class HeldReceiver {
 public:
  HeldReceiver() {
    server_.Post("/hook", [this](const httplib::Request& req, httplib::Response& res) {
      std::unique_lock lock(m_);
      bodies_.push_back(req.body);
      cv_.notify_all();
      cv_.wait(lock, [&] { return !held_; });
      res.set_content("ok", "text/plain");
    });
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }
  ~HeldReceiver() {
    release();
    server_.stop();
    thread_.join();
  }
  int port() const { return port_; }
  void release() {
    std::lock_guard lock(m_);
    held_ = false;
    cv_.notify_all();
  }
  std::vector<std::string> bodies() {
    std::lock_guard lock(m_);
    return bodies_;
  }

 private:
  httplib::Server server_;
  std::thread thread_;
  int port_ = 0;
  std::mutex m_;
  std::condition_variable cv_;
  bool held_ = true;
  std::vector<std::string> bodies_;
};

NotifyConfig endpoint(int port, std::vector<EventKind> events) {
  NotifyConfig n;
  n.url = "http://127.0.0.1:" + std::to_string(port) + "/hook";
  n.origin = "http://127.0.0.1:" + std::to_string(port);
  n.path = "/hook";
  n.events = std::move(events);
  n.timeout_s = 30;
  n.retries = 0;
  return n;
}

Event job_event(int id) { return {EventKind::job_done, 1, {{"id", id}}, nullptr}; }

TEST(Notifier, AFullQueueDropsTheOldestAndEmitNeverWaits) {
  HeldReceiver r;
  {
    Notifier n({endpoint(r.port(), {EventKind::job_done})}, 2);
    n.emit(job_event(1));  // taken by the sender thread, held by the receiver
    ASSERT_TRUE(popcut::testing::wait_until([&] { return r.bodies().size() == 1; }, 30));
    // While the receiver holds the first, every emit returns: 2, 3, 4, 5 queue and drop.
    for (int id = 2; id <= 5; ++id) n.emit(job_event(id));
    n.emit({EventKind::blade_worn, 1, nullptr, nullptr});  // not subscribed: never queued
    EXPECT_FALSE(n.wants(EventKind::blade_worn));
    EXPECT_EQ(n.counts().dropped, 2u) << "2 and 3 dropped for 4 and 5";
    r.release();
    ASSERT_TRUE(popcut::testing::wait_until([&] { return n.counts().delivered == 3; }, 30));
    EXPECT_EQ(n.counts().failures, 0u);
  }
  const std::vector<std::string> got = r.bodies();
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(nlohmann::json::parse(got[0])["job"]["id"], 1);
  EXPECT_EQ(nlohmann::json::parse(got[1])["job"]["id"], 4) << "the oldest waiting were dropped";
  EXPECT_EQ(nlohmann::json::parse(got[2])["job"]["id"], 5);
}

TEST(Notifier, StoppingCutsOffAHangingReceiver) {
  HeldReceiver r;
  std::optional<Notifier> n;
  n.emplace(std::vector<NotifyConfig>{endpoint(r.port(), {EventKind::job_done})});
  n->emit(job_event(1));
  n->emit(job_event(2));
  ASSERT_TRUE(popcut::testing::wait_until([&] { return r.bodies().size() == 1; }, 30));
  n.reset();  // returns after the stop grace (5 s) although the receiver holds on for 30 s
  EXPECT_EQ(r.bodies().size(), 1u);
}

TEST(Notifier, ADownReceiverIsAFailureAfterItsRetries) {
  // A port nothing listens on: bound a moment ago, never listened on, closed.
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ASSERT_EQ(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len), 0);
  ::close(fd);
  NotifyConfig c = endpoint(ntohs(a.sin_port), {EventKind::job_done});
  c.retries = 2;
  Notifier n({c});
  n.emit(job_event(1));
  ASSERT_TRUE(popcut::testing::wait_until([&] { return n.counts().failures == 1; }, 30));
  EXPECT_EQ(n.counts().delivered, 0u);
}

// https: a receiver with a self-signed certificate made by the openssl command is trusted through
// ca_file, and refused (a failure, nothing received) with the system's CAs.
TEST(Notifier, HttpsVerifiesTheReceiversCertificate) {
  popcut::testing::TempDir dir("notify-tls");
  const std::string key = (dir.path() / "key.pem").string(), cert = (dir.path() / "cert.pem").string();
  const std::string cmd =
      "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=127.0.0.1 -addext "
      "subjectAltName=IP:127.0.0.1 -keyout " +
      key + " -out " + cert + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  httplib::SSLServer server(cert.c_str(), key.c_str());
  ASSERT_TRUE(server.is_valid());
  std::atomic<int> received{0};
  server.Post("/hook", [&](const httplib::Request&, httplib::Response& res) {
    ++received;
    res.status = 204;
  });
  const int port = server.bind_to_any_port("127.0.0.1");
  std::thread t([&] { server.listen_after_bind(); });
  NotifyConfig c = endpoint(port, {EventKind::job_done});
  c.origin = "https://127.0.0.1:" + std::to_string(port);
  c.timeout_s = 10;
  {
    Notifier untrusted({c});
    untrusted.emit(job_event(1));
    EXPECT_TRUE(popcut::testing::wait_until([&] { return untrusted.counts().failures == 1; }, 30));
    EXPECT_EQ(received, 0) << "a certificate nobody vouches for is refused before the body goes out";
  }
  c.ca_file = cert;
  {
    Notifier trusted({c});
    trusted.emit(job_event(2));
    EXPECT_TRUE(popcut::testing::wait_until([&] { return trusted.counts().delivered == 1; }, 30));
    EXPECT_EQ(received, 1);
  }
  server.stop();
  t.join();
}

// Two cut strokes (10 mm, 5 mm), a score (3 mm), a perforation (4 mm) and an outline (8 mm).
StrokePlan wear_plan() {
  StrokePlan p;
  p.strokes = {{PlanKind::cut, {{0, 0}, {10, 0}}},
               {PlanKind::valley, {{0, 1}, {3, 1}}},
               {PlanKind::mountain, {{0, 2}, {4, 2}}},
               {PlanKind::cut, {{0, 3}, {3, 3}, {3, 5}}},
               {PlanKind::outline, {{0, 4}, {8, 4}}}};
  return p;
}

TEST(Wear, CountsByModeOverTheStrokesOfARun) {
  std::array<KindPlan, 4> kinds{};
  kinds[index_of(PlanKind::valley)].mode = ToolMode::score;
  kinds[index_of(PlanKind::mountain)].mode = ToolMode::perforate;
  const Wear all = wear_of(wear_plan(), kinds, 1, 5);
  EXPECT_DOUBLE_EQ(all.cut_mm, 10 + 5 + 8);
  EXPECT_DOUBLE_EQ(all.score_mm, 3);
  EXPECT_DOUBLE_EQ(all.perforate_mm, 4);
  EXPECT_EQ(all.knife_down_strokes, 5);
  const Wear resumed = wear_of(wear_plan(), kinds, 4, 5);
  EXPECT_DOUBLE_EQ(resumed.cut_mm, 5 + 8) << "a resumed run counts its own strokes only";
  EXPECT_EQ(resumed.knife_down_strokes, 2);
  EXPECT_EQ(wear_of(wear_plan(), kinds, 3, 2).knife_down_strokes, 0) << "nothing sent";
  EXPECT_EQ(wear_of(wear_plan(), kinds, 1, 99).knife_down_strokes, 5) << "never past the plan";
}

TEST(Wear, ARunIsCreditedWithWhatTheDeviceCertainlyTook) {
  CutOutcome out;
  out.kind = CutOutcome::Kind::complete;
  out.last_stroke_sent = 9;
  EXPECT_EQ(wear_counted_through(out, 4), 9u);
  out.kind = CutOutcome::Kind::stopped;
  out.last_stroke_sent = 7;
  out.last_stroke_executed = 5;
  EXPECT_EQ(wear_counted_through(out, 4), 5u) << "executed, when the device said";
  out.last_stroke_executed.reset();
  EXPECT_EQ(wear_counted_through(out, 4), 7u) << "else what it certainly received";
  out.last_stroke_sent = 0;
  EXPECT_EQ(wear_counted_through(out, 4), 3u) << "nothing of this run: the strokes before it";
}

TEST(WearStore, AddsPerRunMarksWornOnceResetsAndSurvivesReopening) {
  popcut::testing::TempDir dir("wear-store");
  const std::string db = (dir.path() / "jobs.db").string();
  std::int64_t id = 0;
  {
    JobStore s(db);
    id = *s.insert({"k", "card", "a", "sim", "{}"}, 100);
    const auto first = s.add_run_wear(id, "a", {600, 10, 0, 4}, 1.0);
    EXPECT_FALSE(first.newly_worn);
    EXPECT_DOUBLE_EQ(first.device.blade.cut_mm, 600);
    EXPECT_GT(first.device.since_s, 0);
    const auto second = s.add_run_wear(id, "a", {500, 0, 2, 3}, 1.0);
    EXPECT_TRUE(second.newly_worn) << "1100 mm passes 1 m";
    EXPECT_FALSE(s.add_run_wear(id, "a", {1, 0, 0, 1}, 1.0).newly_worn) << "raised once";
    EXPECT_EQ(s.get(id)->knife_down_strokes, 8);
    EXPECT_DOUBLE_EQ(s.get(id)->cut_mm, 1101);
  }
  JobStore s(db);
  DeviceWear w = s.device_wear("a");
  EXPECT_DOUBLE_EQ(w.blade.cut_mm, 1101);
  EXPECT_DOUBLE_EQ(w.blade.score_mm, 10);
  EXPECT_DOUBLE_EQ(w.blade.perforate_mm, 2);
  EXPECT_EQ(w.blade.knife_down_strokes, 8);
  EXPECT_GT(w.worn_at_s, 0);
  EXPECT_TRUE(blade_worn(w, 1.0));
  EXPECT_FALSE(blade_worn(w, std::nullopt));
  w = s.reset_blade("a");
  EXPECT_DOUBLE_EQ(w.blade.cut_mm, 0);
  EXPECT_EQ(w.worn_at_s, 0);
  EXPECT_DOUBLE_EQ(w.lifetime.cut_mm, 1101) << "the device's life goes on";
  EXPECT_EQ(w.lifetime.knife_down_strokes, 8);
  EXPECT_TRUE(s.add_run_wear(id, "a", {1000, 0, 0, 1}, 1.0).newly_worn) << "a new blade wears out again";
  EXPECT_EQ(s.device_wear("b").since_s, 0) << "a device never counted";
}

// Killed after a run's wear was added and before its outcome was recorded: the restart does not
// count that run a second time; a run killed before its wear was added is counted at the restart.
TEST(WearStore, ARunKilledAfterItsWearWasAddedIsNotCountedAgain) {
  popcut::testing::TempDir dir("wear-crash");
  JobStore s((dir.path() / "jobs.db").string());
  const auto cutting = [&] {
    const std::int64_t id = *s.insert({"k", "card", "a", "sim", "{}"}, 100);
    EXPECT_EQ(s.claim_for_planning()->id, id);
    s.set_planned(id, 8, 5.0);
    EXPECT_EQ(s.claim_for_device("a", "sim")->id, id);
    s.set_progress(id, 8);
    return id;
  };
  const std::int64_t counted = cutting();
  s.add_run_wear(counted, "a", {420, 0, 0, 8}, std::nullopt);
  const std::int64_t uncounted = cutting();
  const auto recovered = s.recover([](const Job&) { return Wear{420, 0, 0, 8}; });
  EXPECT_EQ(recovered.interrupted, 2);
  EXPECT_EQ(s.get(counted)->knife_down_strokes, 8) << "once, not twice";
  EXPECT_EQ(s.get(uncounted)->knife_down_strokes, 8) << "counted at the restart";
  EXPECT_EQ(s.device_wear("a").blade.knife_down_strokes, 16);
  // A later run of the same job starts uncounted again.
  ASSERT_EQ(s.resume(counted), ResumeResult::resumed);
  ASSERT_EQ(s.claim_for_device("a", "sim")->id, counted);
  s.recover([](const Job&) { return Wear{0, 0, 0, 1}; });
  EXPECT_EQ(s.get(counted)->knife_down_strokes, 9) << "its second run, cut short, is counted";
}

}  // namespace
