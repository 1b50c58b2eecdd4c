// popcutd at the HTTP level, over raw loopback sockets: bodies refused as they arrive, framing, methods, idle
// connections.
#include <arpa/inet.h>
#include <brotli/encode.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::connect_loopback;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::read_file;
using popcut::testing::TempDir;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-change-me-0123456789";  // configs/popcutd.toml's kiosk token
const std::size_t kLimit = 1048576;                       // and its [limits] upload_bytes

struct Exchange {
  std::string answer;         // everything the daemon sent until it closed (or 30 s passed)
  std::size_t body_sent = 0;  // bytes of the body sent before the answer came
};

// Sends `head`, then `body` in 16 KiB pieces, looking for an answer between pieces; once one
// comes (or the whole body is out), reads until the daemon closes. An answer to a body that
// should be refused comes while the body is still being sent: body_sent < body.size().
Exchange send_watching(int port, const std::string& head, const std::string& body) {
  Exchange out;
  const int s = connect_loopback(port);
  if (s < 0) return out;
  ::send(s, head.data(), head.size(), MSG_NOSIGNAL);
  pollfd p{s, POLLIN, 0};
  while (out.body_sent < body.size() && ::poll(&p, 1, 20) == 0) {
    const std::size_t n = std::min<std::size_t>(16384, body.size() - out.body_sent);
    const ssize_t sent = ::send(s, body.data() + out.body_sent, n, MSG_NOSIGNAL);
    if (sent <= 0) break;
    out.body_sent += static_cast<std::size_t>(sent);
  }
  timeval tv{30, 0};  // a safety net: the daemon answers and closes long before
  ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  char buf[4096];
  for (ssize_t n; (n = ::recv(s, buf, sizeof buf, 0)) > 0;) out.answer.append(buf, static_cast<std::size_t>(n));
  ::close(s);
  return out;
}

// `text` in chunked transfer coding, 1000-byte chunks.
std::string chunked(const std::string& text) {
  std::string out;
  char size[16];
  for (std::size_t i = 0; i < text.size(); i += 1000) {
    const std::string piece = text.substr(i, 1000);
    std::snprintf(size, sizeof size, "%zx\r\n", piece.size());
    out += size + piece + "\r\n";
  }
  return out + "0\r\n\r\n";
}

std::string post_head(const std::string& path, const std::string& token, const std::string& framing) {
  return "POST " + path + " HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n" +
         (token.empty() ? "" : "Authorization: Bearer " + token + "\r\n") + framing + "\r\n";
}

std::string status_line(const std::string& answer) { return answer.substr(0, answer.find("\r\n")); }
std::string error_code(const std::string& answer) {
  const std::size_t body = answer.find("\r\n\r\n");
  const json j = json::parse(body == std::string::npos ? "" : answer.substr(body + 4), nullptr, false);
  return j.is_object() && j.contains("error") ? j["error"].value("code", "") : "";
}

// `text` brotli-compressed (quality 5, a 4 MiB window).
std::string brotli(const std::string& text) {
  std::string out(BrotliEncoderMaxCompressedSize(text.size()), '\0');
  std::size_t size = out.size();
  if (!BrotliEncoderCompress(5, 22, BROTLI_MODE_GENERIC, text.size(),
                             reinterpret_cast<const std::uint8_t*>(text.data()), &size,
                             reinterpret_cast<std::uint8_t*>(out.data()))) {
    return "";
  }
  out.resize(size);
  return out;
}

class PopcutdHttp : public ::testing::Test {
 protected:
  TempDir dir_{"popcutd-http-test"};
  std::unique_ptr<PopcutdProcess> start(const std::string& config) {
    return std::make_unique<PopcutdProcess>(POPCUTD, config, (dir_.path() / "data").string());
  }
};

// A body is refused from its headers when they say enough (no token, a declared length over the
// limit), else as soon as the limit is passed: chunked bodies too, which httplib reads to no limit.
TEST_F(PopcutdHttp, BodiesAreRefusedBeforeOrAsTheyPassTheLimit) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  const std::string big(4 * kLimit, 'a');
  const std::string big_chunked = chunked(big);
  struct Case {
    std::string what, head, body, status, code;
  };
  const std::vector<Case> cases = {
      {"chunked without a token", post_head("/api/v1/jobs", "", "Transfer-Encoding: chunked\r\n"), big_chunked,
       "HTTP/1.1 401", "unauthorized"},
      {"Content-Length with a wrong token",
       post_head("/api/v1/jobs", "wrong-token-0123456789", "Content-Length: " + std::to_string(big.size()) + "\r\n"),
       big, "HTTP/1.1 401", "unauthorized"},
      {"chunked over the limit", post_head("/api/v1/jobs", kKiosk, "Transfer-Encoding: chunked\r\n"), big_chunked,
       "HTTP/1.1 413", "too_large"},
      {"chunked over the limit, to render",
       post_head("/api/v1/render/pattern.svg", kKiosk, "Transfer-Encoding: chunked\r\n"), big_chunked, "HTTP/1.1 413",
       "too_large"},
      {"Content-Length over the limit", post_head("/api/v1/jobs", kKiosk, "Content-Length: 2000000\r\n"),
       std::string(2000000, 'a'), "HTTP/1.1 413", "too_large"},
  };
  for (const Case& k : cases) {
    const Exchange e = send_watching(d->port(), k.head, k.body);
    EXPECT_EQ(status_line(e.answer).rfind(k.status, 0), 0u)
        << k.what << ": answered " << k.status << ": " << e.answer.substr(0, 300);
    EXPECT_EQ(error_code(e.answer), k.code) << k.what << ": with the documented code: " << e.answer.substr(0, 300);
    EXPECT_LT(e.body_sent, k.body.size())
        << k.what << ": answered while the body was still coming, not after reading it all";
    EXPECT_NE(e.answer.find("Connection: close"), std::string::npos)
        << k.what << ": the unread body ends the connection";
  }
  // A small gzip body that inflates past the limit (httplib checks the length it is sent, then
  // inflates to no limit): counted after inflating.
  std::string zipped;
  if (FILE* gz = ::popen("head -c 8388608 /dev/zero | gzip -c", "r")) {
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, gz)) > 0;) zipped.append(buf, n);
    ::pclose(gz);
  }
  ASSERT_FALSE(zipped.empty()) << "gzip made the test body";
  const Exchange bomb =
      send_watching(d->port(),
                    post_head("/api/v1/jobs", kKiosk,
                              "Content-Encoding: gzip\r\nContent-Length: " + std::to_string(zipped.size()) + "\r\n"),
                    zipped);
  EXPECT_EQ(error_code(bomb.answer), "too_large")
      << zipped.size() << " bytes of gzip inflating to 8 MiB: " << bomb.answer.substr(0, 300);
  // A chunked body within the limit is read and used like any other.
  const std::string box = read_file(kSrc + "/examples/voxel/box.json");
  const Exchange ok =
      send_watching(d->port(), post_head("/api/v1/jobs", kKiosk, "Transfer-Encoding: chunked\r\nConnection: close\r\n"),
                    chunked(R"({"device": "sim-a", "name": "chunked", "model": )" + box + "}"));
  EXPECT_EQ(status_line(ok.answer).rfind("HTTP/1.1 201", 0), 0u)
      << "a chunked submission within the limit is accepted: " << ok.answer.substr(0, 300);
  httplib::Client none = d->client("");
  EXPECT_EQ(get_json(none, "/healthz").status, 200) << "the daemon serves on";
}

// Framing the daemon could read two ways is refused (RFC 7230 3.3); every method on every path
// gets the same kind of answer: 404 for a path no route has, 405 with Allow for a method it lacks.
TEST_F(PopcutdHttp, FramingAndMethodsAreAnsweredConsistently) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  const std::string auth = "Authorization: Bearer " + kKiosk + "\r\n";
  const auto request = [&](const std::string& method, const std::string& path, const std::string& headers,
                           const std::string& body = "") {
    return send_watching(
               d->port(),
               method + " " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n" + auth + headers + "\r\n", body)
        .answer;
  };
  struct Case {
    std::string what, answer, status, code;
  };
  const std::vector<Case> cases = {
      {"two different Content-Length headers",
       request("POST", "/api/v1/jobs/1/cancel", "Content-Length: 5\r\nContent-Length: 7\r\n", "{}{}{}{"),
       "HTTP/1.1 400", "bad_request"},
      {"Content-Length: abc", request("POST", "/api/v1/jobs", "Content-Length: abc\r\n"), "HTTP/1.1 400",
       "bad_request"},
      // httplib would take a coding it does not know as none and parse the compressed bytes.
      {"Content-Encoding: zstd",
       request("POST", "/api/v1/jobs", "Content-Encoding: zstd\r\nContent-Length: 2\r\n", "{}"), "HTTP/1.1 400",
       "bad_request"},
      // httplib decodes only the lower-case names: "GZIP" would be read undecoded (a bad_json).
      {"Content-Encoding: GZIP",
       request("POST", "/api/v1/jobs", "Content-Encoding: GZIP\r\nContent-Length: 2\r\n", "{}"), "HTTP/1.1 400",
       "bad_request"},
      {"Content-Encoding: Br", request("POST", "/api/v1/jobs", "Content-Encoding: Br\r\nContent-Length: 2\r\n", "{}"),
       "HTTP/1.1 400", "bad_request"},
      {"Transfer-Encoding: gzip, chunked",
       request("POST", "/api/v1/jobs", "Transfer-Encoding: gzip, chunked\r\n", "0\r\n\r\n"), "HTTP/1.1 400",
       "bad_request"},
      {"Content-Length and chunked together",
       request("POST", "/api/v1/jobs", "Content-Length: 5\r\nTransfer-Encoding: chunked\r\n", "0\r\n\r\n"),
       "HTTP/1.1 400", "bad_request"},
      {"a GET with a body", request("GET", "/api/v1/jobs", "Content-Length: 5\r\n", "hello"), "HTTP/1.1 400",
       "bad_request"},
      {"PUT on the jobs", request("PUT", "/api/v1/jobs", "Content-Length: 2\r\n", "{}"), "HTTP/1.1 405",
       "method_not_allowed"},
      {"PATCH on cancel", request("PATCH", "/api/v1/jobs/1/cancel", "Content-Length: 2\r\n", "{}"), "HTTP/1.1 405",
       "method_not_allowed"},
      {"a PATCH without a length", request("PATCH", "/api/v1/jobs/1", ""), "HTTP/1.1 411", "length_required"},
      {"DELETE on a job", request("DELETE", "/api/v1/jobs/1", ""), "HTTP/1.1 405", "method_not_allowed"},
      {"OPTIONS on healthz", request("OPTIONS", "/healthz", ""), "HTTP/1.1 405", "method_not_allowed"},
      {"GET on cancel", request("GET", "/api/v1/jobs/1/cancel", ""), "HTTP/1.1 405", "method_not_allowed"},
      {"PATCH on no route", request("PATCH", "/api/v1/nothing", "Content-Length: 2\r\n", "{}"), "HTTP/1.1 404",
       "not_found"},
      {"DELETE on no route", request("DELETE", "/nothing", ""), "HTTP/1.1 404", "not_found"},
  };
  for (const Case& k : cases) {
    EXPECT_EQ(status_line(k.answer).rfind(k.status, 0), 0u)
        << k.what << ": answered " << k.status << ": " << k.answer.substr(0, 300);
    EXPECT_EQ(error_code(k.answer), k.code) << k.what << ": with the documented code: " << k.answer.substr(0, 300);
  }
  EXPECT_NE(request("PUT", "/api/v1/jobs", "Content-Length: 0\r\n").find("\r\nAllow: GET, HEAD, POST\r\n"),
            std::string::npos)
      << "405 names the methods the path takes";
  EXPECT_NE(request("DELETE", "/api/v1/jobs/1", "").find("\r\nAllow: GET, HEAD, PATCH\r\n"), std::string::npos)
      << "405 names the methods the path takes";
  EXPECT_EQ(status_line(request("HEAD", "/healthz", "")).rfind("HTTP/1.1 200", 0), 0u) << "HEAD goes with GET";
  httplib::Client none = d->client("");
  EXPECT_EQ(get_json(none, "/healthz").status, 200) << "the daemon serves on";
}

// httplib serves a connection on one pool thread for as long as it lasts: connections that send
// nothing, or trickle header lines, used to hold every thread (httplib's read timeout is per
// read) and /healthz waited for them. With header_timeout_s they are cut off, so /healthz is
// answered while more of them are open than there are threads.
TEST_F(PopcutdHttp, HealthzIsAnsweredWhileMoreIdleConnectionsThanThreadsAreOpen) {
  const std::string cfg = dir_.write("tiny-pool.toml",
                                     "[server]\ndata_dir = \"x\"\nhttp_threads = 2\nheader_timeout_s = 2\n"
                                     "[[device]]\nname = \"a\"\nprofile = \"" +
                                         kSrc +
                                         "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
                                         "[[token]]\nname = \"kiosk\"\ntoken = \"" +
                                         kKiosk + "\"\n");
  const auto d = start(cfg);
  std::vector<int> idle;
  for (int i = 0; i < 4; ++i) idle.push_back(connect_loopback(d->port()));
  // Four more that send a request line, then a header line every 200 ms and never the blank
  // line; they stop when /healthz has answered (or after 90 s, a safety net).
  std::atomic<bool> answered{false};
  std::vector<std::thread> tricklers;
  for (int i = 0; i < 4; ++i) {
    tricklers.emplace_back([&] {
      const int s = connect_loopback(d->port());
      const std::string line = "GET /healthz HTTP/1.1\r\n";
      ::send(s, line.data(), line.size(), MSG_NOSIGNAL);
      for (int n = 0; n < 450 && !answered; ++n) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        const std::string header = "X-Slow-" + std::to_string(n) + ": 1\r\n";
        if (::send(s, header.data(), header.size(), MSG_NOSIGNAL) <= 0) break;
      }
      ::close(s);
    });
  }
  // The holders connect first, so they hold the threads before /healthz is queued behind them.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  httplib::Client none = d->client("");
  none.set_read_timeout(60);  // a generous bound: without header_timeout_s the answer waits for the tricklers (90 s)
  const popcut::testing::Reply r = get_json(none, "/healthz");
  answered = true;
  for (auto& t : tricklers) t.join();
  for (const int s : idle) ::close(s);
  EXPECT_EQ(r.status, 200) << "/healthz answered with 8 idle or trickling connections open and 2 threads; log:\n"
                           << d->log();
}

// A burst of fresh connections (scripts running `popcut submit` at once) is held by the kernel
// until popcutd takes them up. A listen backlog of 5 held 6: the SYNs of the rest were dropped
// and sent again by TCP a second later (p99 ~1 s). popcutd is stopped while the burst connects,
// so how fast it accepts plays no part, and each connection's own TCP retransmit count says
// whether it had to be retried: no timing is measured.
TEST_F(PopcutdHttp, ABurstOfConnectionsIsHeldUntilTakenUpNotDropped) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  constexpr int kBurst = 64;
  ASSERT_EQ(::kill(d->pid(), SIGSTOP), 0);
  std::vector<int> socks;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(d->port()));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  for (int i = 0; i < kBurst; ++i) {
    const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
    const int rc = ::connect(s, reinterpret_cast<const sockaddr*>(&a), sizeof a);
    EXPECT_TRUE(rc == 0 || errno == EINPROGRESS) << "connection " << i << ": " << std::strerror(errno);
    socks.push_back(s);
  }
  ASSERT_EQ(::kill(d->pid(), SIGCONT), 0);
  int answered = 0, retried = 0;
  for (const int s : socks) {
    pollfd p{s, POLLOUT, 0};
    ::poll(&p, 1, 30000);  // a safety net: a retried SYN is answered within 1 + 2 + 4 s
    ::fcntl(s, F_SETFL, ::fcntl(s, F_GETFL) & ~O_NONBLOCK);
    timeval tv{30, 0};
    ::setsockopt(s, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    const std::string get = "GET /healthz HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n";
    ::send(s, get.data(), get.size(), MSG_NOSIGNAL);
    std::string answer;
    char buf[4096];
    for (ssize_t n; (n = ::recv(s, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(n));
    if (status_line(answer) == "HTTP/1.1 200 OK") ++answered;
    tcp_info info{};
    socklen_t len = sizeof info;
    if (::getsockopt(s, IPPROTO_TCP, TCP_INFO, &info, &len) == 0 && info.tcpi_total_retrans > 0) ++retried;
    ::close(s);
  }
  EXPECT_EQ(answered, kBurst) << "every connection of the burst was answered 200";
  EXPECT_EQ(retried, 0) << retried << " of " << kBurst
                        << " connections had to be sent again (their SYN was dropped: the "
                        << "listen backlog holds fewer); log:\n"
                        << d->log();
}

// Content-Encoding br is decoded like gzip and deflate (the Debian cpp-httplib is built with
// brotli), and its decoded bytes count against [limits] upload_bytes.
TEST_F(PopcutdHttp, BrotliBodiesAreDecodedAndCountedAfterDecoding) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  const std::string body =
      R"({"device": "sim-a", "name": "brotli", "model": )" + read_file(kSrc + "/examples/voxel/box.json") + "}";
  const std::string small = brotli(body), bomb = brotli(std::string(8 * kLimit, ' '));
  ASSERT_FALSE(small.empty() || bomb.empty()) << "brotli made the test bodies";
  const auto post = [&](const std::string& coding, const std::string& bytes) {
    return send_watching(d->port(),
                         post_head("/api/v1/jobs", kKiosk,
                                   "Content-Encoding: " + coding + "\r\nContent-Length: " +
                                       std::to_string(bytes.size()) + "\r\nConnection: close\r\n"),
                         bytes)
        .answer;
  };
  const std::string ok = post("br", small);
  EXPECT_EQ(status_line(ok).rfind("HTTP/1.1 201", 0), 0u)
      << "a brotli submission is decoded and queued: " << ok.substr(0, 300);
  EXPECT_NE(ok.find(R"("name":"brotli")"), std::string::npos) << "the decoded model was read: " << ok.substr(0, 300);
  const std::string big = post("br", bomb);
  EXPECT_EQ(error_code(big), "too_large")
      << bomb.size() << " bytes of brotli decoding to 8 MiB: " << big.substr(0, 300);
  const std::string garbage = post("br", "{\"not\": \"brotli\"}");
  EXPECT_EQ(status_line(garbage).rfind("HTTP/1.1 400", 0), 0u)
      << "a body that is not brotli: " << garbage.substr(0, 300);
  EXPECT_EQ(error_code(garbage), "bad_request") << garbage.substr(0, 300);
}

// The preview's angle is checked by the rule every command's --angle is (docs/formats.md).
TEST_F(PopcutdHttp, ThePreviewAngleHasTheRangeOfEveryOpeningAngle) {
  const auto d = start(kSrc + "/configs/popcutd.toml");
  httplib::Client c = d->client(kKiosk);
  const std::string box = read_file(kSrc + "/examples/voxel/box.json");
  for (const char* angle : {"500", "181", "1000000000"}) {
    const popcut::testing::Reply r =
        popcut::testing::post_json(c, std::string("/api/v1/render/preview.png?angle=") + angle, box);
    EXPECT_EQ(r.status, 400) << angle << ": " << r.body.dump();
    EXPECT_EQ(r.body.value("/error/field"_json_pointer, ""), "angle") << r.body.dump();
    EXPECT_EQ(r.body.value("/error/message"_json_pointer, ""),
              std::string("the fold angle must be from 0 (flat) to 180 (closed) degrees, not ") + angle)
        << r.body.dump();
  }
  const httplib::Result ok = c.Post("/api/v1/render/preview.png?angle=180", box, "application/json");
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->status, 200) << "180, closed, is in range: " << ok->body.substr(0, 200);
}

}  // namespace
