// popcut's client commands against a loopback server that is not popcutd: answers of the wrong shape are exit 3, never
// a crash.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <map>
#include <mutex>
#include <regex>
#include <thread>

#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::read_file;
using popcut::testing::TempDir;

const std::string kSrc = POPCUT_SOURCE_DIR;

// A job as popcutd answers it (docs/api.md): the shape the client must take.
const json kJob = {{"id", 7},
                   {"name", "box"},
                   {"owner", "kiosk"},
                   {"device", "a"},
                   {"profile", "sim"},
                   {"cut_on", nullptr},
                   {"state", "queued"},
                   {"strokes_total", 12},
                   {"strokes_sent", 0},
                   {"resume_from", 0},
                   {"resume_point", nullptr},
                   {"strokes_executed", nullptr},
                   {"progress", 0.0},
                   {"est_time_s", 3.5},
                   {"created_at", 1700000000},
                   {"started_at", nullptr},
                   {"finished_at", nullptr},
                   {"place_in_line", 1},
                   {"eta_s", nullptr}};

// An HTTP server on a free loopback port that answers each "METHOD /path" as told (else a default).
class FakeServer {
 public:
  struct Answer {
    int status;
    std::string body;
  };
  FakeServer() {
    const auto handler = [this](const httplib::Request& req, httplib::Response& res) {
      std::lock_guard lock(m_);
      const auto it = answers_.find(req.method + " " + req.path);
      const Answer& a = it != answers_.end() ? it->second : default_;
      res.status = a.status;
      res.set_content(a.body, "application/json");
    };
    server_.Get(".*", handler);
    server_.Post(".*", handler);
    server_.Patch(".*", handler);
    port_ = server_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { server_.listen_after_bind(); });
  }
  ~FakeServer() {
    server_.stop();
    thread_.join();
  }
  void answer_everything(Answer a) {
    std::lock_guard lock(m_);
    answers_.clear();
    default_ = std::move(a);
  }
  void answer(const std::string& method_and_path, Answer a) {
    std::lock_guard lock(m_);
    answers_[method_and_path] = std::move(a);
  }
  std::string address() const { return "http://127.0.0.1:" + std::to_string(port_); }

 private:
  httplib::Server server_;
  std::thread thread_;
  int port_ = 0;
  std::mutex m_;
  std::map<std::string, Answer> answers_;
  Answer default_{500, "{}"};
};

struct CliRun {
  int code;  // exit status; 128 + N when killed by signal N (an abort is 134)
  std::string out, err;
};

class PopcutClientAnswers : public ::testing::Test {
 protected:
  CliRun cli(const std::string& args) {
    const std::string out = (dir_.path() / "cli.out").string(), err = (dir_.path() / "cli.err").string();
    const std::string command =
        std::string(POPCUT_CLI) + " " + args + " --server " + server_.address() + " --token kiosk-0123456789abcdef";
    // Through a shell, so a killed popcut shows as 128 + signal like an interactive run would.
    const int status = std::system((command + " >" + out + " 2>" + err).c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(out), read_file(err)};
  }
  // Every client command, each needing one answer from the server.
  static std::vector<std::string> commands() {
    return {"jobs",
            "jobs --json",
            "submit " + kSrc + "/examples/voxel/box.json --device a",
            "submit " + kSrc + "/examples/voxel/box.json --device a --json",
            "submit " + kSrc + "/examples/meshes/house.obj --profile sim",
            "cancel 7",
            "resume 7",
            "resume 7 --from executed",
            "move 7 --priority 3",
            "move 7 --before 5",
            "jobs --state done,failed --device a --since 7d",
            "pause 7",
            "continue 7"};
  }
  TempDir dir_{"popcut-client-test"};
  FakeServer server_;
};

// Bodies that are JSON but not what popcutd sends, with the status they came with.
const std::vector<FakeServer::Answer> kWrongShapes = {
    {404, R"({"error":"boom"})"},
    {200, R"({"jobs":"nope"})"},
    {201, R"({"id":"seven","state":null})"},
    {500, R"({"error":{"code":5}})"},
    {202, R"([1,2,3])"},
    {200, R"({"jobs":[{"id":7}]})"},
    {201, kJob.dump().replace(kJob.dump().find("\"queued\""), 8, "\"bogus\"")},
    {409, R"({"error":{"code":"conflict","message":"m","field":3}})"},
    // A WebDriver (chromedriver) on the port: its answer to a path it does not know.
    {404,
     R"({"value":{"error":"unknown command","message":"unknown command: unknown command: api/v1/jobs","stacktrace":""}})"},
};

TEST_F(PopcutClientAnswers, EveryCommandCallsAWrongShapeNotPopcutdAndExitsThree) {
  for (const FakeServer::Answer& a : kWrongShapes) {
    server_.answer_everything(a);
    for (const std::string& command : commands()) {
      const CliRun r = cli(command);
      const std::string what = "popcut " + command + " answered " + std::to_string(a.status) + " " + a.body;
      EXPECT_EQ(r.code, 3) << what << ": exit 3, not an abort; stderr: " << r.err;
      EXPECT_NE(r.err.find("is not popcutd: it answered " + std::to_string(a.status)), std::string::npos)
          << what << ": says so: " << r.err;
      EXPECT_EQ(r.err.find("queued job"), std::string::npos) << what << ": nothing printed as if queued: " << r.err;
      // Standard output holds nothing of the answer: with --json, only the error.
      if (!r.out.empty()) {
        const json printed = json::parse(r.out, nullptr, false);
        EXPECT_TRUE(printed.is_object() && printed.size() == 1 && printed.contains("error")) << what << ": " << r.out;
        EXPECT_EQ(printed.contains("error") ? printed["error"].value("exit_code", 0) : 0, 3) << what << ": " << r.out;
      }
    }
  }
}

TEST_F(PopcutClientAnswers, WaitChecksEveryAnswerWhileItPolls) {
  server_.answer("POST /api/v1/jobs", {201, kJob.dump()});
  for (const FakeServer::Answer& a : kWrongShapes) {
    server_.answer("GET /api/v1/jobs/7", a);
    const CliRun r = cli("submit " + kSrc + "/examples/voxel/box.json --device a --wait");
    const std::string what = "submit --wait polled and got " + std::to_string(a.status) + " " + a.body;
    EXPECT_EQ(r.code, 3) << what << ": exit 3, not an abort; stderr: " << r.err;
    EXPECT_NE(r.err.find("queued job 7 (box), place 1 in line"), std::string::npos)
        << what << ": the good answer was shown: " << r.err;
    EXPECT_NE(r.err.find("is not popcutd: it answered " + std::to_string(a.status)), std::string::npos)
        << what << ": says so: " << r.err;
  }
}

// The control: popcutd's own shapes, good and refusing, are taken as before.
TEST_F(PopcutClientAnswers, PopcutdsShapesAreTaken) {
  json done = kJob;
  done["state"] = "done";
  done["cut_on"] = "a";
  done["place_in_line"] = nullptr;
  done["strokes_sent"] = 12;
  done["cancel"] = nullptr;
  done["error"] = {{"code", "device_error"}, {"message", "it said 16"}};
  server_.answer_everything({202, done.dump()});
  server_.answer("GET /api/v1/jobs", {200, json{{"jobs", {kJob, done}}}.dump()});
  server_.answer("POST /api/v1/jobs", {201, kJob.dump()});
  for (const std::string& command : commands()) {
    const CliRun r = cli(command);
    EXPECT_EQ(r.code, 0) << command << ": " << r.err;
  }
  const CliRun jobs = cli("jobs");
  EXPECT_NE(jobs.out.find("7  done  box  on a  strokes 12/12  (device_error: it said 16)"), std::string::npos)
      << jobs.out;
  EXPECT_EQ(cli("submit " + kSrc + "/examples/voxel/box.json --device a --wait").code, 0) << "waited until done";
  server_.answer_everything({404, R"({"error":{"code":"not_found","message":"no job 7"}})"});
  const CliRun refused = cli("cancel 7");
  EXPECT_EQ(refused.code, 2) << "popcutd's refusal is exit 2: " << refused.err;
  EXPECT_NE(refused.err.find("popcutd refused (404 not_found): no job 7"), std::string::npos) << refused.err;
  server_.answer_everything(
      {409, R"({"error":{"code":"conflict","message":"only a paused job continues; job 7 is done"}})"});
  const CliRun not_paused = cli("continue 7");
  EXPECT_EQ(not_paused.code, 2) << "a refused continue is exit 2: " << not_paused.err;
  EXPECT_NE(not_paused.err.find("popcutd refused (409 conflict): only a paused job continues"), std::string::npos)
      << not_paused.err;
  EXPECT_EQ(cli("pause 0").code, cli("cancel 0").code) << "a bad id is refused as for cancel";
}

// A loopback listener that reads `n` requests, one connection each, and keeps their headers; the
// first `drop` are closed unanswered (the job may have been queued: the client cannot know).
class DroppingServer {
 public:
  DroppingServer(int n, int drop, std::string answer) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), len) != 0 || ::listen(fd_, 4) != 0 ||
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) != 0)
      throw std::runtime_error("cannot listen on loopback");
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this, n, drop, answer] {
      for (int i = 0; i < n; ++i) {
        const int c = ::accept(fd_, nullptr, nullptr);
        if (c < 0) return;
        std::string got;
        char buf[4096];
        // Headers, then the Content-Length of body, so the client sees its request taken whole.
        while (got.find("\r\n\r\n") == std::string::npos) {
          const ssize_t k = ::read(c, buf, sizeof buf);
          if (k <= 0) break;
          got.append(buf, static_cast<std::size_t>(k));
        }
        std::smatch m;
        const std::size_t body_at = got.find("\r\n\r\n") + 4;
        if (std::regex_search(got, m, std::regex("Content-Length: (\\d+)", std::regex::icase))) {
          // Read the length before appending: the match points into got, which may move.
          const std::size_t body_bytes = std::stoul(m[1]);
          while (got.size() < body_at + body_bytes) {
            const ssize_t k = ::read(c, buf, sizeof buf);
            if (k <= 0) break;
            got.append(buf, static_cast<std::size_t>(k));
          }
        }
        {
          std::lock_guard lock(m_);
          requests_.push_back(got.substr(0, body_at));
        }
        if (i >= drop) {
          const std::string reply = "HTTP/1.1 201 Created\r\nContent-Type: application/json\r\nContent-Length: " +
                                    std::to_string(answer.size()) + "\r\nConnection: close\r\n\r\n" + answer;
          (void)!::write(c, reply.data(), reply.size());
        }
        ::close(c);
      }
    });
  }
  ~DroppingServer() {
    ::shutdown(fd_, SHUT_RDWR);
    ::close(fd_);
    thread_.join();
  }
  std::string address() const { return "http://127.0.0.1:" + std::to_string(port_); }
  // Each request's Idempotency-Key header value ("" where it had none).
  std::vector<std::string> keys() {
    std::lock_guard lock(m_);
    std::vector<std::string> out;
    for (const std::string& r : requests_) {
      std::smatch m;
      out.push_back(std::regex_search(r, m, std::regex("Idempotency-Key: ([^\r]*)", std::regex::icase)) ? m[1].str()
                                                                                                        : "");
    }
    return out;
  }

 private:
  int fd_ = -1, port_ = 0;
  std::thread thread_;
  std::mutex m_;
  std::vector<std::string> requests_;
};

int run_popcut(const std::string& args) {
  const int status = std::system((std::string(POPCUT_CLI) + " " + args + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(PopcutSubmitKey, ARetryAfterABrokenConnectionSendsTheSameKey) {
  DroppingServer server(3, 2, kJob.dump());
  EXPECT_EQ(run_popcut("submit " + kSrc + "/examples/voxel/box.json --device a --server " + server.address() +
                       " --token kiosk-0123456789abcdef"),
            0)
      << "the third try is answered";
  const std::vector<std::string> keys = server.keys();
  ASSERT_EQ(keys.size(), 3u);
  EXPECT_TRUE(
      std::regex_match(keys[0], std::regex("[0-9a-f]{8}-[0-9a-f]{4}-4[0-9a-f]{3}-[89ab][0-9a-f]{3}-[0-9a-f]{12}")))
      << "a version 4 UUID: " << keys[0];
  EXPECT_EQ(keys[1], keys[0]);
  EXPECT_EQ(keys[2], keys[0]) << "every retry of one submission carries its key";
}

TEST(PopcutSubmitKey, EachRunHasItsOwnKeyUnlessOneIsGiven) {
  std::vector<std::string> keys;
  for (const std::string& given : {std::string(""), std::string(""), std::string(" --idempotency-key order-1138")}) {
    DroppingServer server(1, 0, kJob.dump());
    EXPECT_EQ(run_popcut("submit " + kSrc + "/examples/voxel/box.json --device a --server " + server.address() +
                         " --token kiosk-0123456789abcdef" + given),
              0);
    keys.push_back(server.keys().at(0));
  }
  EXPECT_NE(keys[0], keys[1]) << "a second run is a second job";
  EXPECT_EQ(keys[2], "order-1138");
  EXPECT_EQ(run_popcut("submit " + kSrc + "/examples/voxel/box.json --device a --idempotency-key 'a b'"), 2)
      << "a key popcutd would refuse is refused before sending";
}

}  // namespace
