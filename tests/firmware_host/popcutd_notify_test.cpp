// popcutd's webhooks and wear end to end: a real popcutd cutting on sim devices posts to a loopback receiver inside the
// test.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <map>
#include <mutex>
#include <thread>

#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::read_file;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-0123456789abcdef";
const std::string kAdmin = "admin-0123456789abcdef";
const std::string kSecret = "shop-floor-secret-0123";

// What one POST brought.
struct Delivery {
  std::string event, id, signature, body;
  int answered = 0;
};

// An HTTP receiver on loopback: answers each request with status_for(n) (n from 0), or holds
// requests until released when `hold` is set.
class Receiver {
 public:
  explicit Receiver(std::function<int(std::size_t)> status_for, bool hold = false)
      : status_for_(std::move(status_for)), held_(hold) {
    server_.Post("/hook", [this](const httplib::Request& req, httplib::Response& res) {
      std::unique_lock lock(m_);
      const std::size_t n = got_.size();
      got_.push_back({req.get_header_value("X-Popcut-Event"), req.get_header_value("X-Popcut-Delivery"),
                      req.get_header_value("X-Popcut-Signature"), req.body, status_for_(n)});
      cv_.wait(lock, [&] { return !held_; });
      res.status = got_[n].answered;
      res.set_content("{}", "application/json");
    });
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }
  ~Receiver() {
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
  std::vector<Delivery> got() {
    std::lock_guard lock(m_);
    return got_;
  }
  // The deliveries answered 2xx, by event name.
  std::vector<Delivery> delivered(const std::string& event) {
    std::vector<Delivery> out;
    for (const Delivery& d : got())
      if (d.event == event && d.answered / 100 == 2) out.push_back(d);
    return out;
  }

 private:
  std::function<int(std::size_t)> status_for_;
  httplib::Server server_;
  std::thread thread_;
  int port_ = 0;
  std::mutex m_;
  std::condition_variable cv_;
  bool held_;
  std::vector<Delivery> got_;
};

// A port nothing listens on: bound a moment ago, never listened on, closed.
int closed_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

std::string config(const TempDir& dir, const std::string& device_extra, const std::string& notify) {
  return dir.write("popcutd.toml", "[server]\ndata_dir = \"" + (dir.path() / "data").string() +
                                       "\"\n[[device]]\nname = \"sim-a\"\nprofile = \"" + kSrc +
                                       "/configs/devices/sim.toml\"\ntransport = \"sim\"\n" + device_extra +
                                       "[[token]]\nname = \"kiosk\"\ntoken = \"" + kKiosk +
                                       "\"\n[[token]]\nname = \"admin\"\ntoken = \"" + kAdmin +
                                       "\"\nrole = \"admin\"\n" + notify);
}

std::string notify_to(int port, const std::string& extra) {
  return "[[notify]]\nurl = \"http://127.0.0.1:" + std::to_string(port) + "/hook\"\n" + extra;
}

json box() { return json::parse(read_file(kSrc + "/examples/voxel/box.json")); }

std::int64_t submit(httplib::Client& c) {
  const auto r = post_json(c, "/api/v1/jobs", json{{"device", "sim-a"}, {"model", box()}}.dump());
  EXPECT_EQ(r.status, 201) << r.body.dump();
  return r.body["id"].get<std::int64_t>();
}

json job(httplib::Client& c, std::int64_t id) { return get_json(c, "/api/v1/jobs/" + std::to_string(id)).body; }

json wait_state(httplib::Client& c, std::int64_t id, const std::string& state) {
  json j;
  EXPECT_TRUE(wait_until([&] { return (j = job(c, id))["state"] == state; }, 120)) << j.dump();
  return j;
}

// HMAC-SHA256 by the openssl command, apart from popcutd's code: "sha256=HEX".
std::string openssl_signature(const TempDir& dir, const std::string& body) {
  const std::string path = dir.write("body.json", body);
  FILE* p = ::popen(("openssl dgst -sha256 -hmac '" + kSecret + "' -r " + path).c_str(), "r");
  char line[256] = {};
  const bool read = p && std::fgets(line, sizeof line, p);
  if (p) ::pclose(p);
  const std::string out = read ? std::string(line) : "";
  return "sha256=" + out.substr(0, out.find(' '));
}

// `popcut plan` of box.json for the sim profile: its report's cut length by the profile's modes.
struct PlanFigures {
  double cut_mm = 0, score_mm = 0;
  std::int64_t knife_down = 0;
};
PlanFigures planned_box(const TempDir& dir) {
  const std::string rep = (dir.path() / "plan-report.json").string();
  const std::string cmd = std::string(POPCUT_CLI) + " plan " + kSrc + "/examples/voxel/box.json --profile " + kSrc +
                          "/configs/devices/sim.toml -o " + (dir.path() / "plan.hpgl").string() + " --report " + rep +
                          " >/dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const json r = json::parse(read_file(rep));
  PlanFigures f;
  for (const auto& [kind, k] : r["kinds"].items()) {
    (k["mode"] == "cut" ? f.cut_mm : f.score_mm) += k["cut_mm"].get<double>();
  }
  f.knife_down = r["pen_lifts"].get<std::int64_t>();
  return f;
}

// One series' value on /metrics (-1 when absent).
double metric(PopcutdProcess& d, const std::string& series) {
  const auto r = d.client("").Get("/metrics");
  if (!r) return -1;
  const std::size_t at = r->body.find("\n" + series + " ");
  return at == std::string::npos ? -1 : std::stod(r->body.substr(at + series.size() + 2));
}

TEST(PopcutdNotify, SignedEventsRetriedAfterTwo500sAndWearAsPlanned) {
  TempDir dir("popcutd-notify");
  Receiver rx([](std::size_t n) { return n < 2 ? 500 : 200; });
  const std::string cfg =
      config(dir, "blade_life_m = 0.4\n", notify_to(rx.port(), "secret = \"" + kSecret + "\"\ntimeout_s = 5\n"));
  const PlanFigures plan = planned_box(dir);
  ASSERT_GT(plan.cut_mm, 400) << "box.json cuts past the 0.4 m blade life in one job";
  std::int64_t id = 0;
  double cut_mm = 0;
  {
    PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
    httplib::Client c = d.client(kKiosk);
    id = submit(c);
    const json done = wait_state(c, id, "done");
    cut_mm = done["cut_mm"].get<double>();
    EXPECT_NEAR(cut_mm, plan.cut_mm, 0.01) << "the plan's cut-mode length: " << done.dump();
    EXPECT_EQ(done["knife_down_strokes"], plan.knife_down) << "every knife-down path of the plan";
    ASSERT_TRUE(wait_until([&] { return !rx.delivered("job_done").empty(); }, 60)) << d.log();

    // blade_worn came first: refused twice with 500, taken the third time, the same delivery each time.
    const std::vector<Delivery> got = rx.got();
    ASSERT_GE(got.size(), 4u);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(got[i].event, "blade_worn") << i;
      EXPECT_EQ(got[i].id, got[0].id) << "a retry is the same delivery";
      EXPECT_EQ(got[i].body, got[0].body);
    }
    EXPECT_EQ(got[2].answered, 200);
    EXPECT_EQ(got[0].id.size(), 32u);
    EXPECT_NE(got[3].id, got[0].id) << "another event, another delivery";
    for (const Delivery& g : got) EXPECT_EQ(g.signature, openssl_signature(dir, g.body)) << g.body;

    const json worn = json::parse(got[2].body);
    EXPECT_EQ(worn["event"], "blade_worn");
    EXPECT_EQ(worn["device"]["name"], "sim-a");
    EXPECT_EQ(worn["device"]["blade"]["worn"], true);
    EXPECT_EQ(worn["device"]["blade"]["life_m"], 0.4);
    const json body = json::parse(rx.delivered("job_done")[0].body);
    EXPECT_EQ(body["job"]["id"], id);
    EXPECT_EQ(body["job"]["state"], "done");
    EXPECT_NEAR(body["job"]["cut_mm"].get<double>(), cut_mm, 0.001);
    EXPECT_GT(body["at"].get<double>(), 1.7e9);
    EXPECT_EQ(rx.delivered("blade_worn").size(), 1u) << "raised once";

    const json dev = get_json(c, "/api/v1/devices").body["devices"][0];
    EXPECT_NEAR(dev["blade"]["cut_mm"].get<double>(), cut_mm, 0.001) << dev.dump();
    EXPECT_EQ(dev["blade"]["knife_down_strokes"], plan.knife_down);
    EXPECT_NEAR(dev["blade"]["score_mm"].get<double>(), plan.score_mm, 0.01);
    EXPECT_EQ(dev["blade"]["worn"], true);
    EXPECT_NEAR(metric(d, "popcut_device_cut_mm_total{device=\"sim-a\"}"), cut_mm, 0.01);
    EXPECT_EQ(metric(d, "popcut_device_knife_down_strokes_total{device=\"sim-a\"}"),
              static_cast<double>(plan.knife_down));
    EXPECT_EQ(metric(d, "popcut_device_blade_worn{device=\"sim-a\"}"), 1);
    EXPECT_TRUE(wait_until([&] { return metric(d, "popcut_notify_delivered_total") == 2; }, 30))
        << "blade_worn and job_done";
    EXPECT_EQ(metric(d, "popcut_notify_failures_total"), 0);
    EXPECT_EQ(d.stop(SIGTERM), 0);
  }
  // A restart keeps the counters; an admin resets the blade's, the device's life goes on.
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  httplib::Client kiosk = d.client(kKiosk), admin = d.client(kAdmin);
  EXPECT_NEAR(get_json(kiosk, "/api/v1/devices").body["devices"][0]["blade"]["cut_mm"].get<double>(), cut_mm, 0.001);
  EXPECT_NEAR(job(kiosk, id)["cut_mm"].get<double>(), cut_mm, 0.001);
  EXPECT_EQ(metric(d, "popcut_device_blade_worn{device=\"sim-a\"}"), 1);
  EXPECT_EQ(post_json(kiosk, "/api/v1/devices/sim-a/blade", "{}").status, 403);
  EXPECT_EQ(post_json(admin, "/api/v1/devices/sim-z/blade", "{}").status, 404);
  const auto bad = post_json(admin, "/api/v1/devices/sim-a/blade", R"({"cut_mm": 0})");
  EXPECT_EQ(bad.status, 400);
  EXPECT_EQ(bad.body["error"]["field"], "cut_mm");
  EXPECT_EQ(post_json(admin, "/api/v1/devices/sim-a/blade", "[]").status, 400);
  EXPECT_EQ(post_json(admin, "/api/v1/devices/sim-a/blade", "{").status, 400);
  const auto reset = post_json(admin, "/api/v1/devices/sim-a/blade", "{}");
  ASSERT_EQ(reset.status, 200) << reset.body.dump();
  EXPECT_EQ(reset.body["blade"]["cut_mm"], 0);
  EXPECT_EQ(reset.body["blade"]["worn"], false);
  EXPECT_EQ(metric(d, "popcut_device_blade_worn{device=\"sim-a\"}"), 0);
  EXPECT_NEAR(metric(d, "popcut_device_cut_mm_total{device=\"sim-a\"}"), cut_mm, 0.01) << "lifetime, not reset";
  // The new blade wears out in its turn: blade_worn again.
  const std::int64_t second = submit(kiosk);
  wait_state(kiosk, second, "done");
  EXPECT_TRUE(wait_until([&] { return rx.delivered("blade_worn").size() == 2; }, 60));
  EXPECT_NEAR(metric(d, "popcut_device_cut_mm_total{device=\"sim-a\"}"), 2 * cut_mm, 0.02);
}

TEST(PopcutdNotify, AHangingAndADownReceiverHoldNoCut) {
  TempDir dir("popcutd-notify-hang");
  Receiver hanging([](std::size_t) { return 200; }, /*hold=*/true);
  const std::string cfg = config(dir, "",
                                 notify_to(hanging.port(), "timeout_s = 120\nretries = 0\n") +
                                     notify_to(closed_port(), "retries = 20\nevents = [\"job_done\"]\n"));
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  std::vector<std::int64_t> ids;
  for (int i = 0; i < 3; ++i) ids.push_back(submit(c));
  for (const std::int64_t id : ids) wait_state(c, id, "done");
  // Every job was cut while the first event's delivery was still held by its receiver, and the
  // down one still retries its first.
  const std::vector<Delivery> got = hanging.got();
  ASSERT_EQ(got.size(), 1u) << "the hanging receiver holds the first delivery; the rest wait behind it";
  EXPECT_EQ(got[0].event, "job_done");
  EXPECT_EQ(json::parse(got[0].body)["job"]["id"], ids[0]);
  EXPECT_EQ(metric(d, "popcut_notify_delivered_total"), 0);
  EXPECT_EQ(d.stop(SIGTERM), 0) << "a hanging receiver does not hold popcutd's stop either: " << d.log();
  EXPECT_NE(d.log().find("events not sent"), std::string::npos) << d.log();
}

TEST(PopcutdNotify, AnInterruptedRunAndItsResumeCountOnlyTheirOwnStrokes) {
  TempDir dir("popcutd-notify-resume");
  Receiver rx([](std::size_t) { return 204; });
  const std::string cfg =
      config(dir, "sim_time_scale = 1\n", notify_to(rx.port(), "events = [\"job_interrupted\", \"job_done\"]\n"));
  const PlanFigures plan = planned_box(dir);
  std::int64_t id = 0;
  json first;
  {
    PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
    httplib::Client c = d.client(kKiosk);
    id = submit(c);
    // Past half of it: the device has executed some strokes, not all.
    ASSERT_TRUE(wait_until(
        [&] {
          const json j = job(c, id);
          return j["state"] == "cutting" && j["strokes_sent"].get<int>() * 2 >= j["strokes_total"].get<int>();
        },
        120))
        << d.log();
    EXPECT_EQ(d.stop(SIGTERM), 0);
    ASSERT_EQ(rx.delivered("job_interrupted").size(), 1u) << "sent while popcutd stopped: " << d.log();
    first = json::parse(rx.delivered("job_interrupted")[0].body)["job"];
  }
  EXPECT_EQ(first["state"], "interrupted");
  const std::int64_t counted = first["knife_down_strokes"].get<std::int64_t>();
  EXPECT_LE(counted, first["resume_from"].get<std::int64_t>()) << "never past what the device certainly took";
  if (first["strokes_executed"].is_number()) {
    EXPECT_EQ(counted, first["strokes_executed"].get<std::int64_t>()) << "what the device said it executed";
  }
  EXPECT_LT(counted, plan.knife_down);
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  ASSERT_EQ(post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", "").status, 202);
  const json done = wait_state(c, id, "done");
  EXPECT_EQ(done["knife_down_strokes"].get<std::int64_t>(),
            counted + plan.knife_down - first["resume_from"].get<std::int64_t>())
      << "the resumed run counts the strokes after resume_from, and only those";
  EXPECT_EQ(get_json(c, "/api/v1/devices").body["devices"][0]["blade"]["knife_down_strokes"],
            done["knife_down_strokes"]);
  EXPECT_TRUE(wait_until([&] { return rx.delivered("job_done").size() == 1; }, 60));
}

// kill -9 mid-cut: the restart finds the job cut short, says so, and counts the strokes the
// device certainly received in the killed run.
TEST(PopcutdNotify, AJobFoundCutShortAtStartIsReported) {
  TempDir dir("popcutd-notify-kill");
  Receiver rx([](std::size_t) { return 200; });
  const std::string cfg = config(dir, "sim_time_scale = 1\n", notify_to(rx.port(), "events = [\"job_interrupted\"]\n"));
  std::int64_t id = 0;
  {
    PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
    httplib::Client c = d.client(kKiosk);
    id = submit(c);
    ASSERT_TRUE(wait_until([&] { return job(c, id)["strokes_sent"].get<int>() >= 2; }, 120)) << d.log();
    d.stop(SIGKILL);
  }
  EXPECT_TRUE(rx.got().empty());
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  ASSERT_TRUE(wait_until([&] { return rx.delivered("job_interrupted").size() == 1; }, 60)) << d.log();
  const json body = json::parse(rx.delivered("job_interrupted")[0].body);
  EXPECT_EQ(body["job"]["id"], id);
  EXPECT_EQ(body["job"]["state"], "interrupted");
  EXPECT_EQ(body["job"]["error"]["code"], "interrupted");
  EXPECT_EQ(body["device"]["name"], "sim-a");
  EXPECT_GT(body["job"]["resume_from"].get<int>(), 0);
  EXPECT_EQ(body["job"]["knife_down_strokes"], body["job"]["resume_from"]) << "strokes 1..strokes_sent";
  httplib::Client c = d.client(kKiosk);
  const json blade = get_json(c, "/api/v1/devices").body["devices"][0]["blade"];
  EXPECT_EQ(blade["knife_down_strokes"], body["job"]["knife_down_strokes"]);
  EXPECT_GT(blade["score_mm"].get<double>() + blade["cut_mm"].get<double>(), 0) << "the folds are scored first";
  EXPECT_EQ(blade["cut_mm"], body["job"]["cut_mm"]);
}

}  // namespace
