// popcutd's HTTP API (docs/api.md) and kiosk page, on cpp-httplib.
#pragma once

#include <httplib.h>

#include <memory>

#include "daemon.h"

namespace popcut::daemon {

class ApiContext;
class RouteTable;
struct Route;

// Registers every route, the payload limit and JSON error bodies on `server`; keep it alive as
// long as the server runs.
class HttpApi {
 public:
  HttpApi(httplib::Server& server, Daemon& daemon);
  ~HttpApi();
  HttpApi(const HttpApi&) = delete;
  HttpApi& operator=(const HttpApi&) = delete;

 private:
  void install_routes();
  void install_checks();
  // The route's token check and handler, its failures turned into their documented answers.
  httplib::Server::Handler guarded(const Route& route);
  // POST bodies are read here, not by httplib, which holds a chunked or compressed body to no
  // limit: every byte after decoding counts against [limits] upload_bytes, and reading stops at it.
  bool read_body(httplib::Request& req, const httplib::ContentReader& content, httplib::Response& res);
  // Answers what the request line and headers alone refuse, before a byte of the body is read.
  bool refuse_before_body(const httplib::Request& req, httplib::Response& res);
  // An answer before the body is read. With `body_unread`, whatever body the client sends is left
  // unread, so the connection cannot carry another request: it is closed (http_server.cpp).
  void refuse(httplib::Response& res, ApiError code, const std::string& message, bool body_unread = true);

  httplib::Server& server_;
  std::unique_ptr<ApiContext> api_;
  std::unique_ptr<RouteTable> routes_;
};

}  // namespace popcut::daemon
