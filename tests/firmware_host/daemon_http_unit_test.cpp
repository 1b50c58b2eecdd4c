// popcutd's HTTP parts without a server: the route table's refusals, body framing, the metrics text, names.
#include <gtest/gtest.h>
#include <httplib.h>

#include "daemon.h"
#include "http_framing.h"
#include "job.h"
#include "metrics.h"
#include "route_table.h"

namespace {
using namespace popcut::daemon;

void no_handler(ApiContext&, const Caller&, const httplib::Request&, httplib::Response&) {}

httplib::Params params(std::initializer_list<std::pair<std::string, std::string>> list) {
  return httplib::Params(list.begin(), list.end());
}

TEST(RouteTable, RefusalsFollowFromTheTable) {
  const RouteTable table({{Method::get, "/a", Access::token, takes({"x"}), no_handler},
                          {Method::post, "/a", Access::token, takes_none(), no_handler},
                          {Method::post, R"(/b/(\d+))", Access::admin, takes_none(), no_handler, "b-ing"},
                          {Method::get, "/page", Access::none, any_query(), no_handler}});
  EXPECT_FALSE(table.refusal("GET", "/a", {})) << "a route takes its own method";
  EXPECT_FALSE(table.refusal("HEAD", "/a", params({{"x", "1"}}))) << "HEAD goes with GET, and with GET's parameters";
  EXPECT_FALSE(table.refusal("POST", "/b/12", {}));
  EXPECT_FALSE(table.refusal("GET", "/page", params({{"token", "t"}, {"zoom", "2"}})))
      << "a route outside the API takes any query";

  const auto missing = table.refusal("GET", "/c", {});
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->code, ApiError::not_found);
  EXPECT_EQ(missing->message, "no such resource: /c");
  EXPECT_EQ(missing->allow, "") << "404 has no Allow";
  ASSERT_TRUE(table.refusal("GET", "/b/x", {})) << "a pattern matches the whole path or not at all";

  const auto put = table.refusal("PUT", "/a", {});
  ASSERT_TRUE(put);
  EXPECT_EQ(put->code, ApiError::method_not_allowed);
  EXPECT_EQ(put->allow, "GET, HEAD, POST") << "Allow lists GET with HEAD, then POST";
  EXPECT_EQ(put->message, "PUT is not allowed on /a (Allow: GET, HEAD, POST)");
  EXPECT_EQ(table.refusal("GET", "/b/1", {})->allow, "POST");
  EXPECT_EQ(table.refusal("POST", "/page", {})->allow, "GET, HEAD");

  const auto zoom = table.refusal("GET", "/a", params({{"x", "1"}, {"zoom", "2"}}));
  ASSERT_TRUE(zoom);
  EXPECT_EQ(zoom->code, ApiError::bad_request);
  EXPECT_EQ(zoom->message, "unknown query parameter 'zoom' (this takes x)");
  EXPECT_EQ(table.refusal("POST", "/a", params({{"x", "1"}}))->message, "unknown query parameter 'x' (this takes none)")
      << "parameters are the route's, not the path's";
}

TEST(RouteTable, PopcutdsOwnTable) {
  const RouteTable table(api_routes());
  EXPECT_EQ(table.refusal("DELETE", "/api/v1/jobs", {})->allow, "GET, HEAD, POST");
  EXPECT_EQ(table.refusal("DELETE", "/api/v1/jobs/1", {})->allow, "GET, HEAD, PATCH");
  EXPECT_FALSE(table.refusal("PATCH", "/api/v1/jobs/1", {}));
  EXPECT_FALSE(table.refusal("DELETE", "/api/v1/designs/1", {}));
  EXPECT_EQ(table.refusal("PUT", "/api/v1/designs/1", {})->allow, "GET, HEAD, PATCH, DELETE");
  EXPECT_EQ(table.refusal("GET", "/api/v1/jobs/1/cancel", {})->allow, "POST");
  EXPECT_FALSE(table.refusal("GET", "/api/v1/jobs/7/preview.png", params({{"angle", "30"}})));
  EXPECT_FALSE(table.refusal("POST", "/api/v1/render/preview.png", params({{"angle", "30"}})));
  EXPECT_EQ(table.refusal("GET", "/api/v1/jobs/7", params({{"angle", "30"}}))->message,
            "unknown query parameter 'angle' (this takes none)");
  for (const Route& r : table.routes()) {
    const bool api = std::string(r.pattern).rfind("/api/", 0) == 0;
    EXPECT_EQ(r.query.checked, api) << r.pattern << ": the API's routes check their query, the page's do not";
    EXPECT_EQ(r.access != Access::none, api) << r.pattern << ": every API route takes a token";
    if (r.access == Access::admin) {
      EXPECT_STRNE(r.admin_action, "") << r.pattern << ": a refused kiosk is told what needs the admin";
    }
  }
}

httplib::Request request(const std::string& method,
                         std::initializer_list<std::pair<std::string, std::string>> headers) {
  httplib::Request req;
  req.method = method;
  for (const auto& [k, v] : headers) req.headers.emplace(k, v);
  return req;
}

// The refusal's message, or "" when the framing is sound.
std::string framing_error(const httplib::Request& req) {
  const BodyFraming f = read_framing(req);
  return f.refusal ? f.message : "";
}

TEST(HttpFraming, OneLengthOrChunkedAlone) {
  const BodyFraming sized = read_framing(request("POST", {{"Content-Length", "12"}}));
  EXPECT_FALSE(sized.refusal);
  EXPECT_EQ(sized.length, 12u);
  EXPECT_FALSE(sized.chunked);
  const BodyFraming chunked = read_framing(request("POST", {{"Transfer-Encoding", "Chunked"}}));
  EXPECT_FALSE(chunked.refusal) << "the coding's name is case-insensitive";
  EXPECT_TRUE(chunked.chunked);
  EXPECT_FALSE(chunked.length);
  EXPECT_EQ(framing_error(request("POST", {{"Content-Length", "5"}, {"Content-Length", "5"}})), "")
      << "the same length twice is one length";
  EXPECT_EQ(framing_error(request("POST", {{"Content-Length", "5"}, {"Content-Length", "6"}})),
            "two different Content-Length headers (5 and 6)");
  EXPECT_EQ(framing_error(request("POST", {{"Content-Length", "-1"}})),
            "Content-Length must be a number of bytes, not '-1'");
  EXPECT_EQ(framing_error(request("POST", {{"Content-Length", "5"}, {"Transfer-Encoding", "chunked"}})),
            "both Content-Length and Transfer-Encoding: send one");
  EXPECT_EQ(framing_error(request("POST", {{"Transfer-Encoding", "gzip, chunked"}})),
            "Transfer-Encoding: only 'chunked' is understood");
  EXPECT_EQ(read_framing(request("POST", {})).refusal, ApiError::length_required)
      << "a POST without a length would be read until the client closes";
}

TEST(HttpFraming, CodingsAndBodiesByMethod) {
  EXPECT_EQ(framing_error(request("POST", {{"Content-Length", "1"}, {"Content-Encoding", "gzip"}})), "");
  EXPECT_EQ(framing_error(request("POST", {{"Content-Length", "1"}, {"Content-Encoding", "IDENTITY"}})), "");
  EXPECT_EQ(framing_error(request("POST", {{"Content-Length", "1"}, {"Content-Encoding", "GZIP"}})),
            "Content-Encoding: only gzip, deflate or br (in lower case) or identity is understood, not 'GZIP'")
      << "httplib would pass an upper-case coding through undecoded";
  EXPECT_EQ(framing_error(request("GET", {})), "");
  EXPECT_EQ(framing_error(request("GET", {{"Content-Length", "0"}})), "");
  EXPECT_EQ(framing_error(request("GET", {{"Content-Length", "3"}})), "a GET request has no body");
  EXPECT_EQ(framing_error(request("DELETE", {{"Transfer-Encoding", "chunked"}})), "a DELETE request has no body");
  EXPECT_FALSE(declares_body(request("GET", {{"Content-Length", "0"}})));
  EXPECT_TRUE(declares_body(request("PUT", {{"Content-Length", "3"}})));
  EXPECT_TRUE(declares_body(request("PUT", {{"Transfer-Encoding", "x"}})));
  EXPECT_TRUE(iequals("Bearer", "bEARER"));
  EXPECT_FALSE(iequals("Bearer", "Bearer "));
}

TEST(Metrics, PrometheusText) {
  MetricsSample m;
  m.jobs_by_state = {{"done", 3}, {"queued", 0}};
  m.requests = 10;
  m.errors_4xx = 2;
  m.errors_5xx = 1;
  m.submitted = 4;
  m.cuts_completed = 3;
  m.devices = {{"a", true, false}, {"b", false, true}};
  m.uptime_s = 1.5;
  const std::string text = metrics_text(m);
  for (const char* line :
       {"# TYPE popcutd_jobs gauge\npopcutd_jobs{state=\"done\"} 3\npopcutd_jobs{state=\"queued\"} 0\n",
        "\npopcutd_http_requests_total 10\n", "\npopcutd_http_errors_total{class=\"4xx\"} 2\n",
        "\npopcutd_http_errors_total{class=\"5xx\"} 1\n", "\npopcutd_jobs_submitted_total 4\n",
        "\npopcutd_cuts_completed_total 3\n",
        "\npopcutd_device_busy{device=\"a\"} 1\npopcutd_device_busy{device=\"b\"} 0\n",
        "\npopcutd_device_paused{device=\"a\"} 0\npopcutd_device_paused{device=\"b\"} 1\n",
        "# TYPE popcutd_uptime_seconds gauge\npopcutd_uptime_seconds 1.5\n"}) {
    EXPECT_NE(text.find(line), std::string::npos) << "missing:\n" << line << "\nin:\n" << text;
  }
  EXPECT_EQ(text.rfind("# HELP popcutd_jobs Jobs in the store by state.\n", 0), 0u);
  EXPECT_EQ(text.back(), '\n');
}

TEST(DaemonNames, EveryValueHasItsName) {
  const JobState states[] = {JobState::queued, JobState::planning, JobState::ready,     JobState::cutting,
                             JobState::done,   JobState::failed,   JobState::cancelled, JobState::interrupted};
  for (const JobState s : states) EXPECT_EQ(parse_job_state(to_string(s)), s) << to_string(s);
  EXPECT_STREQ(to_string(JobState::interrupted), "interrupted");
  EXPECT_FALSE(parse_job_state("Done")) << "names are case-sensitive, as stored";
  EXPECT_EQ(parse_resume_point("executed"), ResumePoint::executed);
  EXPECT_STREQ(to_string(ResumePoint::received), "received");
  EXPECT_FALSE(parse_resume_point(""));
  EXPECT_STREQ(to_string(Role::admin), "admin");
  EXPECT_STREQ(to_string(Role::kiosk), "kiosk");
  EXPECT_STREQ(to_string(CancelStage::waiting_for_device), "waiting_for_device");
  EXPECT_STREQ(to_string(CancelStage::none), "none");
  for (const auto& [e, name] : kApiErrorNames.entries) {
    EXPECT_EQ(std::string(to_string(e)), name);
    EXPECT_GE(http_status(e), 400) << name;
  }
  EXPECT_STREQ(to_string(ApiError::method_not_allowed), "method_not_allowed");
  EXPECT_EQ(kApiErrorNames.entries.size(), static_cast<std::size_t>(ApiError::internal) + 1)
      << "every error code has its name";
}

}  // namespace
