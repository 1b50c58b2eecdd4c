// What every HTTP route handler shares: the daemon, the counters, API errors as answers, the
// token check, and the readers of bodies and query parameters (docs/api.md).
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "daemon.h"
#include "design_sessions.h"
#include "metrics.h"
#include "popcut/mesh/import_request.h"
#include "preview_cache.h"

namespace popcut::daemon {

using json = nlohmann::json;

// An API error on its way to the client: thrown inside a handler, answered by the route's guard.
struct ApiFailure {
  ApiError code;
  std::string message;
  std::string field;
};
[[noreturn]] void fail(ApiError code, std::string message, std::string field = "");

void send_error(httplib::Response& res, ApiError code, const std::string& message, const std::string& field = "");
void send_json(httplib::Response& res, const json& j, int status = 200);

// Who sent a request: the name and role of its token.
struct Caller {
  std::string name;
  Role role = Role::kiosk;
  bool admin() const { return role == Role::admin; }
};

// The body as JSON; a key given twice in one object is refused: the parser would keep the last
// and {"device": "a", "device": "b"} would go to b without a word (RFC 8259 leaves it open).
json parse_body(const httplib::Request& req);
// body[key] as a string; "" when absent or null and not `required`.
std::string string_field(const json& body, const char* key, bool required);
// A JSON whole number from lo to hi (a float such as 2.0, or a number beyond int64, is not).
bool whole_in(const json& v, std::int64_t lo, std::int64_t hi);
// Unix seconds as a query gives them: a finite number from 0, at most 20 characters.
std::optional<double> parse_unix_seconds(const std::string& text);
// A query parameter given at most once: ?angle=10&angle=20 is a malformed request, not a guess.
std::optional<std::string> query_param(const httplib::Request& req, const char* name);
// ?angle= in whole degrees (90 when absent), rounded to the previews' step of 5 degrees.
int angle_param(const httplib::Request& req);

// A preview renders on the request's thread; at most one per core (and half of the HTTP threads)
// do so at once: more would only make each slower. A request that finds no slot free is answered
// 503 busy at once instead of waiting, so job status, submissions and /healthz always have threads.
class RenderSlots {
 public:
  explicit RenderSlots(int http_threads);
  bool try_take();
  void give() { ++free_; }

 private:
  std::atomic<int> free_;
};

class ApiContext {
 public:
  explicit ApiContext(Daemon& daemon);

  Daemon& daemon() const { return daemon_; }
  RequestCounters& counters() { return counters_; }
  double uptime_s() const;

  // The caller named by "Authorization: Bearer TOKEN"; throws ApiFailure (unauthorized).
  Caller auth(const httplib::Request& req) const;
  // The job of the path's first group, if the caller may see it (else not_found).
  Job visible_job(const httplib::Request& req, const Caller& caller) const;
  // The media of every configured device, by the device's name: what --fit-mm may name.
  const std::vector<NamedMedia>& media() const { return media_; }
  // The PNG preview of `pattern()` folded to `angle`, from the cache under `key` when there.
  std::string preview(const std::string& key, int angle, const std::function<Pattern()>& pattern);
  // Runs `work` (a render, a drawing's inference) in one of the render slots; throws ApiFailure
  // busy at once when none is free.
  void in_render_slot(const std::function<void()>& work);
  // The designer's live sessions (api_designs.cpp).
  DesignSessions& designs() { return designs_; }
  // A number no other upload of this run has: temporary files' names.
  std::uint64_t next_upload() { return ++upload_counter_; }

 private:
  Daemon& daemon_;
  std::vector<NamedMedia> media_;  // the configuration does not change while popcutd runs
  RequestCounters counters_;
  PreviewCache previews_;
  RenderSlots render_slots_;
  DesignSessions designs_;
  std::atomic<std::uint64_t> upload_counter_{0};
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace popcut::daemon
