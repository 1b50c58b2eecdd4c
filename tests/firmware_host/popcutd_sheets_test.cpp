// The sheet step end to end: a real popcutd with a confirm_sheet sim device waits after each job until a fresh sheet is
// confirmed over HTTP, across kill -9, and raises awaiting_sheet to a loopback webhook.
#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <sys/wait.h>

#include <csignal>
#include <cstdio>
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
const std::string kOther = "other-0123456789abcdef";
const std::string kAdmin = "admin-0123456789abcdef";

// Takes every webhook POST and keeps its body.
class Receiver {
 public:
  Receiver() {
    server_.Post("/hook", [this](const httplib::Request& req, httplib::Response& res) {
      std::lock_guard lock(m_);
      bodies_.push_back(json::parse(req.body));
      res.set_content("{}", "application/json");
    });
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }
  ~Receiver() {
    server_.stop();
    thread_.join();
  }
  int port() const { return port_; }
  std::vector<json> events(const std::string& name) {
    std::lock_guard lock(m_);
    std::vector<json> out;
    for (const json& b : bodies_)
      if (b.value("event", "") == name) out.push_back(b);
    return out;
  }

 private:
  httplib::Server server_;
  std::thread thread_;
  int port_ = 0;
  std::mutex m_;
  std::vector<json> bodies_;
};

// sim-a waits for sheets; box.json plans 6.8 s, cut at sim_time_scale times that. The 409 test
// runs while a job cuts, so it takes the full 6.8 s: under a loaded CI machine a 2 s cut could
// end between seeing "cutting" and asking for a sheet.
std::string config(const TempDir& dir, int hook_port, double time_scale) {
  return dir.write("popcutd.toml",
                   "[server]\ndata_dir = \"" + (dir.path() / "data").string() +
                       "\"\n[[device]]\nname = \"sim-a\"\nprofile = \"" + kSrc +
                       "/configs/devices/sim.toml\"\ntransport = \"sim\"\nconfirm_sheet = true\nsim_time_scale = " +
                       std::to_string(time_scale) + "\n[[token]]\nname = \"kiosk\"\ntoken = \"" + kKiosk +
                       "\"\n[[token]]\nname = \"other\"\ntoken = \"" + kOther +
                       "\"\n[[token]]\nname = \"admin\"\ntoken = \"" + kAdmin + "\"\nrole = \"admin\"\n" +
                       (hook_port ? "[[notify]]\nurl = \"http://127.0.0.1:" + std::to_string(hook_port) +
                                        "/hook\"\nevents = [\"awaiting_sheet\"]\n"
                                  : ""));
}

std::int64_t submit(httplib::Client& c) {
  const json box = json::parse(read_file(kSrc + "/examples/voxel/box.json"));
  const auto r = post_json(c, "/api/v1/jobs", json{{"device", "sim-a"}, {"model", box}}.dump());
  EXPECT_EQ(r.status, 201) << r.body.dump();
  return r.body.value("id", std::int64_t{0});
}

std::string state(httplib::Client& c, std::int64_t id) {
  return get_json(c, "/api/v1/jobs/" + std::to_string(id)).body.value("state", "");
}

void wait_state(httplib::Client& c, std::int64_t id, const std::string& want) {
  EXPECT_TRUE(wait_until([&] { return state(c, id) == want; }, 120)) << "job " << id << " never " << want;
}

std::string sheet(httplib::Client& c) { return get_json(c, "/api/v1/devices").body["devices"][0].value("sheet", ""); }

double metric(PopcutdProcess& d, const std::string& series) {
  const auto r = d.client("").Get("/metrics");
  if (!r) return -1;
  const std::size_t at = r->body.find("\n" + series + " ");
  return at == std::string::npos ? -1 : std::stod(r->body.substr(at + series.size() + 2));
}

// The next job stays ready for `s` seconds: nothing claims it.
void stays_ready(httplib::Client& c, std::int64_t id, double s) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(s);
  while (std::chrono::steady_clock::now() < until) {
    ASSERT_EQ(state(c, id), "ready") << "job " << id << " started on a sheet nobody confirmed";
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

const std::string kAwaiting = "popcut_device_awaiting_sheet{device=\"sim-a\"}";

TEST(PopcutdSheets, EachJobWaitsForAConfirmedSheetAnd409WhileCutting) {
  TempDir dir("popcutd-sheets");
  Receiver rx;
  PopcutdProcess d(POPCUTD, config(dir, rx.port(), 1.0), (dir.path() / "data").string());
  httplib::Client kiosk = d.client(kKiosk), other = d.client(kOther), admin = d.client(kAdmin);
  const json dev = get_json(kiosk, "/api/v1/devices").body["devices"][0];
  EXPECT_EQ(dev["sheet"], "loaded") << dev.dump();
  EXPECT_EQ(dev["confirm_sheet"], true);
  const std::int64_t first = submit(kiosk);
  const std::int64_t second = submit(kiosk);
  wait_state(kiosk, first, "cutting");
  EXPECT_EQ(sheet(kiosk), "in_use");
  const auto busy = post_json(admin, "/api/v1/devices/sim-a/sheet", "");
  EXPECT_EQ(busy.status, 409) << busy.body.dump();
  EXPECT_EQ(busy.body["error"]["code"], "conflict");
  wait_state(kiosk, first, "done");
  ASSERT_TRUE(wait_until([&] { return state(kiosk, second) == "ready"; }, 60)) << "planned";
  stays_ready(kiosk, second, 1.5);
  EXPECT_EQ(sheet(kiosk), "awaiting_sheet");
  EXPECT_EQ(metric(d, kAwaiting), 1);
  ASSERT_TRUE(wait_until([&] { return !rx.events("awaiting_sheet").empty(); }, 30)) << d.log();
  const json event = rx.events("awaiting_sheet")[0];
  EXPECT_EQ(event["job"]["id"], first) << event.dump();
  EXPECT_EQ(event["device"]["name"], "sim-a");

  EXPECT_EQ(post_json(admin, "/api/v1/devices/sim-z/sheet", "").status, 404) << "unknown device";
  EXPECT_EQ(post_json(other, "/api/v1/devices/sim-a/sheet", "").status, 403) << "not the owner of the last job";
  const auto bad = post_json(kiosk, "/api/v1/devices/sim-a/sheet", R"({"sheet": "a4"})");
  EXPECT_EQ(bad.status, 400);
  EXPECT_EQ(bad.body["error"]["field"], "sheet");
  stays_ready(kiosk, second, 0.2);
  const auto ok = post_json(kiosk, "/api/v1/devices/sim-a/sheet", "");
  ASSERT_EQ(ok.status, 200) << "the last job's owner confirms, as the kiosk does: " << ok.body.dump();
  EXPECT_EQ(ok.body["sheet"], "loaded");
  EXPECT_EQ(ok.body["device"], "sim-a");
  wait_state(kiosk, second, "done");
  EXPECT_TRUE(wait_until([&] { return rx.events("awaiting_sheet").size() == 2; }, 30)) << "raised after each job";
  EXPECT_EQ(sheet(admin), "awaiting_sheet");
  ASSERT_EQ(post_json(admin, "/api/v1/devices/sim-a/sheet", "{}").status, 200) << "the admin may confirm too";
  EXPECT_EQ(sheet(admin), "loaded");
  EXPECT_EQ(metric(d, kAwaiting), 0);
}

TEST(PopcutdSheets, KillNineWhileAwaitingASheetStartsNothingUntilConfirmed) {
  TempDir dir("popcutd-sheets-kill");
  const std::string cfg = config(dir, 0, 0);
  std::int64_t second = 0;
  {
    PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
    httplib::Client kiosk = d.client(kKiosk);
    const std::int64_t first = submit(kiosk);
    wait_state(kiosk, first, "done");
    second = submit(kiosk);
    ASSERT_TRUE(wait_until([&] { return state(kiosk, second) == "ready"; }, 60));
    EXPECT_EQ(sheet(kiosk), "awaiting_sheet");
    EXPECT_EQ(d.stop(SIGKILL), 128 + SIGKILL);
  }
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  httplib::Client kiosk = d.client(kKiosk);
  EXPECT_EQ(sheet(kiosk), "awaiting_sheet") << "the state came back from the database";
  EXPECT_EQ(metric(d, kAwaiting), 1);
  stays_ready(kiosk, second, 2.0);
  ASSERT_EQ(post_json(kiosk, "/api/v1/devices/sim-a/sheet", "").status, 200);
  wait_state(kiosk, second, "done");
}

TEST(PopcutdSheets, KillNineDuringACutLeavesTheSheetUsed) {
  TempDir dir("popcutd-sheets-cut");
  const std::string cfg = config(dir, 0, 0.5);
  std::int64_t first = 0, second = 0;
  {
    PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
    httplib::Client kiosk = d.client(kKiosk);
    first = submit(kiosk);
    second = submit(kiosk);
    wait_state(kiosk, first, "cutting");
    ASSERT_TRUE(wait_until([&] { return state(kiosk, second) == "ready"; }, 60));
    EXPECT_EQ(d.stop(SIGKILL), 128 + SIGKILL);
  }
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  httplib::Client kiosk = d.client(kKiosk);
  EXPECT_EQ(state(kiosk, first), "interrupted");
  EXPECT_EQ(sheet(kiosk), "awaiting_sheet");
  stays_ready(kiosk, second, 1.5);
  // Its half-cut sheet is on the cutter: a fresh one now would take the rest of that card.
  const auto held = post_json(kiosk, "/api/v1/devices/sim-a/sheet", "");
  EXPECT_EQ(held.status, 409) << held.body.dump();
  EXPECT_NE(held.body["error"]["message"].get<std::string>().find("job " + std::to_string(first) + " is interrupted"),
            std::string::npos)
      << held.body.dump();
  // The interrupted job may go on cutting its own half-cut sheet; the next still waits.
  ASSERT_EQ(post_json(kiosk, "/api/v1/jobs/" + std::to_string(first) + "/resume", "").status, 202);
  wait_state(kiosk, first, "done");
  stays_ready(kiosk, second, 1.0);
  ASSERT_EQ(post_json(kiosk, "/api/v1/devices/sim-a/sheet", "").status, 200);
  wait_state(kiosk, second, "done");
}

}  // namespace

namespace {

struct CliRun {
  int code = -1;
  std::string out;
};

// `popcut ARGS` with its standard output and error together, and its exit status.
CliRun popcut(const std::string& args) {
  CliRun r;
  FILE* p = ::popen((std::string(POPCUT_CLI) + " " + args + " 2>&1").c_str(), "r");
  char buf[512];
  while (p && std::fgets(buf, sizeof buf, p)) r.out += buf;
  const int status = p ? ::pclose(p) : -1;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

TEST(PopcutdSheets, PopcutSheetConfirmsAndExitsAsDocumented) {
  TempDir dir("popcutd-sheets-cli");
  PopcutdProcess d(POPCUTD, config(dir, 0, 0.3), (dir.path() / "data").string());
  httplib::Client kiosk = d.client(kKiosk);
  const std::string server = " --server http://127.0.0.1:" + std::to_string(d.port());
  const std::int64_t first = submit(kiosk);
  const std::int64_t second = submit(kiosk);
  wait_state(kiosk, first, "cutting");
  const CliRun busy = popcut("sheet sim-a" + server + " --token " + kAdmin);
  EXPECT_EQ(busy.code, 2) << "409 while cutting is a refusal: " << busy.out;
  EXPECT_NE(busy.out.find("409"), std::string::npos) << busy.out;
  wait_state(kiosk, first, "done");
  ASSERT_TRUE(wait_until([&] { return state(kiosk, second) == "ready"; }, 60));
  EXPECT_EQ(popcut("sheet sim-z" + server + " --token " + kAdmin).code, 2) << "unknown device";
  EXPECT_EQ(popcut("sheet sim-a" + server + " --token " + kOther).code, 2) << "another's job";
  EXPECT_EQ(popcut("sheet ../x" + server + " --token " + kAdmin).code, 2) << "not a device name";
  stays_ready(kiosk, second, 0.5);
  const CliRun ok = popcut("sheet sim-a" + server + " --token " + kKiosk);
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_NE(ok.out.find("sim-a  sheet loaded"), std::string::npos) << ok.out;
  wait_state(kiosk, second, "done");
  const CliRun as_json = popcut("sheet sim-a --json" + server + " --token " + kKiosk);
  EXPECT_EQ(as_json.code, 0) << as_json.out;
  EXPECT_EQ(json::parse(as_json.out)["sheet"], "loaded") << as_json.out;
  EXPECT_EQ(popcut("sheet sim-a --server http://127.0.0.1:1 --token " + kKiosk).code, 3) << "nothing listens";
  const CliRun help = popcut("sheet --help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("fresh sheet"), std::string::npos) << help.out;
}

}  // namespace
