// The HTTP handlers' shared parts: error answers, token check, JSON and query readers, previews.
#include "api_context.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <thread>
#include <unordered_set>

#include "http_framing.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/error.h"
#include "popcut/fold/fold.h"
#include "popcut/fold/render.h"

namespace popcut::daemon {
namespace {

// Rounded to a multiple of kAngleStepDeg (the kiosk slider's step): at most 37 pictures per model.
constexpr int kAngleStepDeg = 5;

bool constant_time_equal(const std::string& a, const std::string& b) {
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

std::string preview_png(const Pattern& p, int angle) {
  const CardMesh mesh = fold_card_for_picture(p, angle);
  // Frame the standing card at every angle so the slider does not make the picture jump.
  const ViewBox box = view_box({fold_card(p, 90), fold_card(p, 180), mesh});
  return render_png(mesh, box, 480);  // in memory: no temporary file to write and read back
}

}  // namespace

void fail(ApiError code, std::string message, std::string field) {
  throw ApiFailure{code, std::move(message), std::move(field)};
}

void send_error(httplib::Response& res, ApiError code, const std::string& message, const std::string& field) {
  json e = {{"code", to_string(code)}, {"message", message}};
  if (!field.empty()) e["field"] = field;
  res.status = http_status(code);
  res.set_content(json{{"error", e}}.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

void send_json(httplib::Response& res, const json& j, int status) {
  res.status = status;
  res.set_content(j.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

json parse_body(const httplib::Request& req) {
  std::vector<std::unordered_set<std::string>> keys;  // per open object, the keys seen so far
  std::string repeated;
  const json::parser_callback_t check = [&](int depth, json::parse_event_t event, json& parsed) {
    // The model's own limit (64 levels) plus the body around it. Deeper, the job's model_json
    // dump (recursive) overflowed the stack of a request thread at ~75,000 levels.
    if (depth > 65) fail(ApiError::bad_json, "the body is nested deeper than 65 levels (a model may nest 64)");
    if (event == json::parse_event_t::object_start)
      keys.emplace_back();
    else if (event == json::parse_event_t::object_end)
      keys.pop_back();
    else if (event == json::parse_event_t::key && repeated.empty()) {
      const std::string& key = parsed.get_ref<const std::string&>();
      if (!keys.back().insert(key).second) repeated = key;
    }
    return true;
  };
  json body;
  try {
    body = json::parse(req.body, check);
  } catch (const json::parse_error& e) {
    fail(ApiError::bad_json, std::string("the body is not JSON: ") + e.what());
  } catch (const json::exception& e) {
    // A number past a double's range (1e400) is not JSON popcutd can read either: the client's fault.
    fail(ApiError::bad_json, std::string("the body is not JSON popcutd can read: ") + e.what());
  }
  if (!repeated.empty()) fail(ApiError::bad_request, "'" + repeated + "' given twice in one object", repeated);
  return body;
}

std::string string_field(const json& body, const char* key, bool required) {
  if (!body.contains(key) || body[key].is_null()) {
    if (required) fail(ApiError::bad_request, std::string("missing field '") + key + "'", key);
    return "";
  }
  if (!body[key].is_string()) fail(ApiError::bad_request, std::string("'") + key + "' must be a string", key);
  return body[key].get<std::string>();
}

bool whole_in(const json& v, std::int64_t lo, std::int64_t hi) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    return hi >= 0 && u <= static_cast<std::uint64_t>(hi) && static_cast<std::int64_t>(u) >= lo;
  }
  if (!v.is_number_integer()) return false;
  const std::int64_t n = v.get<std::int64_t>();
  return n >= lo && n <= hi;
}

std::optional<double> parse_unix_seconds(const std::string& text) {
  if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789.") != std::string::npos)
    return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<std::string> query_param(const httplib::Request& req, const char* name) {
  const std::size_t n = req.get_param_value_count(name);
  if (n > 1) fail(ApiError::bad_request, std::string("'") + name + "' given twice in the query", name);
  if (n == 0) return std::nullopt;
  return req.get_param_value(name);
}

int angle_param(const httplib::Request& req) {
  const std::optional<std::string> given = query_param(req, "angle");
  if (!given) return 90;
  const std::string& a = *given;
  // Whole degrees (previews are cached per step); "-0" is 0, as a slider or a script may send it.
  const std::string digits = a == "-0" ? "0" : a;
  if (digits.empty() || digits.size() > 15 || digits.find_first_not_of("0123456789") != std::string::npos) {
    fail(ApiError::bad_request, "angle must be a whole number of degrees from 0 to 180, not '" + a.substr(0, 40) + "'",
         "angle");
  }
  const long long angle = std::stoll(digits);
  try {
    check_fold_angle(static_cast<double>(angle), "angle");  // the range every command and field that takes an angle has
  } catch (const Error& e) {
    fail(ApiError::bad_request, e.message(), "angle");
  }
  return static_cast<int>((angle + kAngleStepDeg / 2) / kAngleStepDeg * kAngleStepDeg);
}

RenderSlots::RenderSlots(int http_threads)
    : free_(std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, std::max(1, http_threads / 2))) {}

bool RenderSlots::try_take() {
  int n = free_.load();
  while (n > 0) {
    if (free_.compare_exchange_weak(n, n - 1)) return true;
  }
  return false;
}

ApiContext::ApiContext(Daemon& daemon)
    : daemon_(daemon),
      previews_(daemon.config().limits.preview_cache_bytes),
      render_slots_(daemon.config().http_threads),
      designs_(daemon.store(), static_cast<std::size_t>(daemon.config().limits.design_sessions)) {
  for (const DeviceConfig& dev : daemon.config().devices) media_.push_back(drivers::media_of(dev.profile, dev.name));
}

double ApiContext::uptime_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

Caller ApiContext::auth(const httplib::Request& req) const {
  const std::string h = req.get_header_value("Authorization");
  if (h.empty()) fail(ApiError::unauthorized, "no token: send 'Authorization: Bearer TOKEN'");
  // RFC 7235: the scheme is case-insensitive ("bearer" is Bearer); one or more spaces follow it.
  const std::size_t space = h.find(' ');
  if (space == std::string::npos || !iequals(h.substr(0, space), "Bearer")) {
    fail(ApiError::unauthorized, "the Authorization header must be 'Bearer TOKEN'");
  }
  const std::size_t start = h.find_first_not_of(' ', space);
  const std::string token = start == std::string::npos ? "" : h.substr(start);
  for (const TokenConfig& t : daemon_.config().tokens) {
    if (t.token.size() == token.size() && constant_time_equal(t.token, token)) return {t.name, t.role};
  }
  fail(ApiError::unauthorized, "unknown token");
}

Job ApiContext::visible_job(const httplib::Request& req, const Caller& caller) const {
  const std::string digits = req.matches[1];
  if (digits.size() > 15) fail(ApiError::not_found, "no job " + digits);
  const std::int64_t id = std::stoll(digits);
  std::optional<Job> j = daemon_.store().get(id);
  // Another's job is "not found" for a kiosk token: ids of others' jobs are not disclosed.
  if (!j || (!caller.admin() && j->owner != caller.name)) fail(ApiError::not_found, "no job " + std::to_string(id));
  return *j;
}

void ApiContext::in_render_slot(const std::function<void()>& work) {
  if (!render_slots_.try_take()) fail(ApiError::busy, "every preview slot is rendering; retry in a moment");
  struct Give {
    RenderSlots& slots;
    ~Give() { slots.give(); }
  } give{render_slots_};
  work();
}

std::string ApiContext::preview(const std::string& key, int angle, const std::function<Pattern()>& pattern) {
  if (std::optional<std::string> png = previews_.get(key)) return *png;
  std::string png;
  in_render_slot([&] { png = preview_png(pattern(), angle); });
  previews_.put(key, png);
  return png;
}

}  // namespace popcut::daemon
