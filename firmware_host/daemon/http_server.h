// popcutd's HTTP server: cpp-httplib's request handling on connections whose life popcutd decides.
#pragma once

#include <httplib.h>

namespace popcut::daemon {

struct ConnectionLimits {
  int header_timeout_s = 5;      // a request's line and headers must arrive within this
  int keep_alive_timeout_s = 2;  // an idle kept-alive connection is closed after this
  int read_timeout_s = 5;        // a body's next bytes must arrive within this (per read; per write too)
  int listen_backlog = 1024;     // connections the kernel completes and holds until popcutd takes them up
};

// httplib (0.11) serves each connection on one pool thread and gives a client 5 s per read however
// long its headers take, keeps a connection open after an answer that says "Connection: close"
// (the unread body of a refused upload would then be parsed as the next request) and polls
// idle sockets every millisecond. This server runs httplib's request parser and routing on its
// own connection loop: the request head has a deadline and a size cap, idle keep-alive ends after
// keep_alive_timeout_s, and an answer with "Connection: close" closes the connection (after
// letting the client read it).
class HttpServer : public httplib::Server {
 public:
  explicit HttpServer(ConnectionLimits limits);

  // Binds host:port (port 0: any free port) and listens with limits.listen_backlog; returns the
  // port bound, or -1 with errno saying why. httplib's own bind listens with a backlog of 5 (fixed
  // when the library was built): of a burst of new connections the kernel then holds 6 for the
  // accept loop and drops the SYNs of the rest, which TCP sends again only after 1 s (3 s, 7 s ...).
  int bind_and_listen(const std::string& host, int port);

 private:
  bool process_and_close_socket(socket_t sock) override;
  ConnectionLimits limits_;
};

}  // namespace popcut::daemon
