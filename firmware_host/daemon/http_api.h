// popcutd's HTTP API (docs/api.md) and kiosk page, on cpp-httplib.
#pragma once

#include <httplib.h>

#include <memory>

#include "daemon.h"

namespace popcut::daemon {

class Api;

// Registers every route, the payload limit and JSON error bodies on `server`; keep it alive as
// long as the server runs.
class HttpApi {
 public:
  HttpApi(httplib::Server& server, Daemon& daemon);
  ~HttpApi();
  HttpApi(const HttpApi&) = delete;
  HttpApi& operator=(const HttpApi&) = delete;

 private:
  std::unique_ptr<Api> api_;
};

}  // namespace popcut::daemon
