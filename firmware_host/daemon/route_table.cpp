// The answers that follow from the route table alone: unknown paths, methods and query parameters.
#include "route_table.h"

#include <algorithm>

namespace popcut::daemon {
namespace {

// "angle", "a or b": for the message naming what a route takes.
std::string or_list(const std::vector<std::string_view>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " or " : ", ";
    out += names[i];
  }
  return out;
}

}  // namespace

RouteTable::RouteTable(std::vector<Route> routes) : routes_(std::move(routes)) {
  for (const Route& r : routes_) patterns_.emplace_back(r.pattern);
}

RouteTable::~RouteTable() = default;

std::optional<RouteRefusal> RouteTable::refusal(const std::string& method, const std::string& path,
                                                const httplib::Params& params) const {
  bool has[4] = {false, false, false, false};  // by Method
  const Route* routed = nullptr;
  const std::optional<Method> asked = method == "GET" || method == "HEAD" ? std::optional(Method::get)
                                      : method == "POST"                  ? std::optional(Method::post)
                                      : method == "PATCH"                 ? std::optional(Method::patch)
                                      : method == "DELETE"                ? std::optional(Method::del)
                                                                          : std::nullopt;
  for (std::size_t i = 0; i < routes_.size(); ++i) {
    if (!std::regex_match(path, patterns_[i])) continue;
    has[static_cast<int>(routes_[i].method)] = true;
    if (asked && routes_[i].method == *asked) routed = &routes_[i];
  }
  std::string allow;
  for (const auto& [m, name] : {std::pair{Method::get, "GET, HEAD"},
                                {Method::post, "POST"},
                                {Method::patch, "PATCH"},
                                {Method::del, "DELETE"}}) {
    if (has[static_cast<int>(m)]) allow += (allow.empty() ? "" : ", ") + std::string(name);
  }
  if (allow.empty()) return RouteRefusal{ApiError::not_found, "no such resource: " + path, ""};
  if (!routed)
    return RouteRefusal{ApiError::method_not_allowed, method + " is not allowed on " + path + " (Allow: " + allow + ")",
                        allow};
  // Query parameters the API does not take are refused, not ignored (?zoom=2 is a typo or a
  // client expecting something popcutd does not do).
  if (!routed->query.checked) return std::nullopt;
  const std::vector<std::string_view>& names = routed->query.names;
  for (const auto& [key, value] : params) {
    if (std::find(names.begin(), names.end(), key) != names.end()) continue;
    const std::string takes = names.empty() ? "none" : or_list(names);
    return RouteRefusal{ApiError::bad_request,
                        "unknown query parameter '" + key.substr(0, 40) + "' (this takes " + takes + ")", ""};
  }
  return std::nullopt;
}

}  // namespace popcut::daemon
