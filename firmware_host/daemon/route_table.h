// popcutd's routes as data: method, path pattern, token needed, query parameters taken, handler.
// What is refused before routing (404, 405 with Allow, an unknown query parameter) follows from it.
#pragma once

#include <httplib.h>

#include <optional>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include "api_context.h"

namespace popcut::daemon {

enum class Method { get, post, patch, del };  // a GET route answers HEAD too
// none: no token asked (health, metrics, the kiosk page); token: any token; admin: the admin token.
enum class Access { none, token, admin };

// The query parameters a route takes. Paths outside /api/ are not the API: the page's own
// ?token= and whatever a browser appends are theirs, so nothing there is refused.
struct Query {
  bool checked = true;
  std::vector<std::string_view> names;
};
inline Query takes(std::vector<std::string_view> names) { return {true, std::move(names)}; }
inline Query takes_none() { return {}; }
inline Query any_query() { return {false, {}}; }

using RouteHandler = void (*)(ApiContext& api, const Caller& caller, const httplib::Request& req,
                              httplib::Response& res);

struct Route {
  Method method;
  const char* pattern;  // a regular expression matched against the whole path; its groups are req.matches
  Access access;
  Query query;
  RouteHandler handler;
  const char* admin_action = "";  // Access::admin: what a kiosk token is refused ("pausing a device")
};

// An answer given before routing, from the request line alone.
struct RouteRefusal {
  ApiError code;
  std::string message;
  std::string allow;  // 405: the methods the path takes, for the Allow header
};

class RouteTable {
 public:
  explicit RouteTable(std::vector<Route> routes);
  ~RouteTable();  // in route_table.cpp, with all else of <regex> (CMakeLists.txt: GCC bug 105562)
  const std::vector<Route>& routes() const { return routes_; }

  // A path no route has is 404 whatever the method; a method the path does not take is 405
  // with Allow (HEAD goes with GET), for PUT, PATCH, DELETE and OPTIONS as for GET and POST;
  // a query parameter the route does not take is 400. nullopt: a route takes the request.
  std::optional<RouteRefusal> refusal(const std::string& method, const std::string& path,
                                      const httplib::Params& params) const;

 private:
  std::vector<Route> routes_;
  std::vector<std::regex> patterns_;  // routes_[i]'s
};

// popcutd's own routes (http_api.cpp).
std::vector<Route> api_routes();

}  // namespace popcut::daemon
