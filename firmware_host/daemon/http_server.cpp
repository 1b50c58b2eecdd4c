// popcutd's connection loop around httplib's request handling: head deadline, idle timeout, closing.
#include "http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <string_view>

namespace popcut::daemon {
namespace {

using Clock = std::chrono::steady_clock;

// A request line and its headers together: httplib caps each line at 8 KiB but not their number,
// and reads a line without end into memory byte by byte.
constexpr std::size_t kMaxHeadBytes = 64 * 1024;

// Waits for `events` on `sock` for at most `timeout_ms`; false on timeout, error or hang-up only.
bool wait_for(socket_t sock, short events, int timeout_ms) {
  pollfd p{sock, events, 0};
  for (;;) {
    const int n = ::poll(&p, 1, std::max(0, timeout_ms));
    if (n < 0 && errno == EINTR) continue;
    return n > 0;
  }
}

int ms_until(Clock::time_point t) {
  return static_cast<int>(std::chrono::ceil<std::chrono::milliseconds>(t - Clock::now()).count());
}

void address_of(const sockaddr_storage& a, std::string& ip, int& port) {
  char text[INET6_ADDRSTRLEN] = "";
  if (a.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
    ::inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text);
    port = ntohs(v4->sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
    ::inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text);
    port = ntohs(v6->sin6_port);
  }
  ip = text;
}

// One connection, kept across its requests (httplib's own stream lives for one request).
class ConnectionStream : public httplib::Stream {
 public:
  ConnectionStream(socket_t sock, const ConnectionLimits& limits) : sock_(sock), limits_(limits) {}

  // The next request's head must be complete by `deadline`.
  void start_head(Clock::time_point deadline) {
    in_head_ = true;
    head_deadline_ = deadline;
    head_bytes_ = 0;
  }
  // httplib has parsed the head: from here on reads wait read_timeout_s each.
  void end_head() { in_head_ = false; }
  // Bytes of the next request are here, or arrive before `deadline`.
  bool wait_for_request(Clock::time_point deadline) const {
    return pos_ < len_ || wait_for(sock_, POLLIN, ms_until(deadline));
  }
  bool failed() const { return failed_; }
  bool close_requested() const { return close_requested_; }

  bool is_readable() const override { return pos_ < len_ || wait_for(sock_, POLLIN, read_wait_ms()); }
  bool is_writable() const override { return wait_for(sock_, POLLOUT, limits_.read_timeout_s * 1000); }

  ssize_t read(char* ptr, std::size_t size) override {
    if (pos_ == len_) {
      if (!is_readable()) return fail();
      const ssize_t n = ::recv(sock_, buf_, sizeof buf_, 0);
      if (n <= 0) return n == 0 ? 0 : fail();
      pos_ = 0;
      len_ = static_cast<std::size_t>(n);
    }
    const std::size_t n = std::min(size, len_ - pos_);
    if (in_head_ && (head_bytes_ += n) > kMaxHeadBytes) return fail();
    std::memcpy(ptr, buf_ + pos_, n);
    pos_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* ptr, std::size_t size) override {
    // httplib writes an answer's status line and headers in one piece: RFC 7230 6.6, an answer
    // that says "Connection: close" is the connection's last.
    const std::string_view data(ptr, size);
    if (data.rfind("HTTP/1.1 ", 0) == 0) {
      const std::string_view head = data.substr(0, data.find("\r\n\r\n"));
      if (head.find("\r\nConnection: close") != std::string_view::npos) close_requested_ = true;
    }
    if (!is_writable()) return fail();
    const ssize_t n = ::send(sock_, ptr, size, MSG_NOSIGNAL);
    return n < 0 ? fail() : n;
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage a{};
    socklen_t n = sizeof a;
    if (::getpeername(sock_, reinterpret_cast<sockaddr*>(&a), &n) == 0) address_of(a, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage a{};
    socklen_t n = sizeof a;
    if (::getsockname(sock_, reinterpret_cast<sockaddr*>(&a), &n) == 0) address_of(a, ip, port);
  }
  socket_t socket() const override { return sock_; }

 private:
  int read_wait_ms() const { return in_head_ ? ms_until(head_deadline_) : limits_.read_timeout_s * 1000; }
  ssize_t fail() {
    failed_ = true;
    return -1;
  }

  socket_t sock_;
  ConnectionLimits limits_;
  bool in_head_ = false, failed_ = false, close_requested_ = false;
  Clock::time_point head_deadline_;
  std::size_t head_bytes_ = 0;
  char buf_[16 * 1024];
  std::size_t pos_ = 0, len_ = 0;
};

// Closing a socket with unread bytes in it sends a reset, which can destroy the answer before
// the client reads it (a refused upload is still arriving). Half-close, then read and drop
// what the client still sends, until it pauses for 250 ms or 2 s have passed, so it sees the
// answer and stops.
void close_after_answer(socket_t sock) {
  ::shutdown(sock, SHUT_WR);
  const Clock::time_point until = Clock::now() + std::chrono::seconds(2);
  char sink[16 * 1024];
  while (wait_for(sock, POLLIN, std::min(250, ms_until(until)))) {
    if (::recv(sock, sink, sizeof sink, 0) <= 0) break;
  }
  ::close(sock);
}

}  // namespace

HttpServer::HttpServer(ConnectionLimits limits) : limits_(limits) {
  set_read_timeout(limits.read_timeout_s);
  set_keep_alive_timeout(limits.keep_alive_timeout_s);
}

int HttpServer::bind_and_listen(const std::string& host, int port) {
  int bound = port;
  if (port == 0) {
    bound = bind_to_any_port(host);
  } else if (!bind_to_port(host, port)) {
    bound = -1;
  }
  if (bound <= 0) return -1;
  // Listening again on a listening socket only sets its backlog (Linux); the kernel caps it at
  // net.core.somaxconn.
  if (::listen(svr_sock_, limits_.listen_backlog) != 0) return -1;
  return bound;
}

bool HttpServer::process_and_close_socket(socket_t sock) {
  ConnectionStream strm(sock, limits_);
  bool ok = false;
  // The first request's head is due header_timeout_s after the connection is taken up; a later
  // one's first byte within keep_alive_timeout_s of the last answer, its whole head within
  // header_timeout_s of that byte.
  for (std::size_t left = keep_alive_max_count_; left > 0 && svr_sock_ != INVALID_SOCKET; --left) {
    const bool first = left == keep_alive_max_count_;
    if (!first && !strm.wait_for_request(Clock::now() + std::chrono::seconds(limits_.keep_alive_timeout_s))) break;
    const Clock::time_point head_due = Clock::now() + std::chrono::seconds(limits_.header_timeout_s);
    strm.start_head(head_due);
    if (first && !strm.wait_for_request(head_due)) break;
    bool client_closes = false;
    ok = process_request(strm, left == 1, client_closes, [&](httplib::Request&) { strm.end_head(); });
    if (!ok || client_closes || strm.failed() || strm.close_requested()) break;
  }
  if (strm.close_requested()) {
    close_after_answer(sock);
  } else {
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
  }
  return ok;
}

}  // namespace popcut::daemon
