// HTTP routes: token auth, JSON in and out, documented error codes; pictures rendered by core.
#include "http_api.h"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "log.h"
#include "model_limits.h"
#include "popcut/error.h"
#include "popcut/fold/fold.h"
#include "popcut/fold/render.h"
#include "popcut/io/files.h"
#include "popcut/io/pattern_io.h"

namespace popcut::daemon {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// An API error on its way to the client: thrown inside a handler, answered by `guarded`.
struct ApiFailure {
  ApiError code;
  std::string message;
  std::string field;
};

[[noreturn]] void fail(ApiError code, std::string message, std::string field = "") {
  throw ApiFailure{code, std::move(message), std::move(field)};
}

void send_error(httplib::Response& res, ApiError code, const std::string& message, const std::string& field = "") {
  json e = {{"code", to_string(code)}, {"message", message}};
  if (!field.empty()) e["field"] = field;
  res.status = http_status(code);
  res.set_content(json{{"error", e}}.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

void send_json(httplib::Response& res, const json& j, int status = 200) {
  res.status = status;
  res.set_content(j.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

struct Metrics {
  std::atomic<std::uint64_t> requests{0}, errors_4xx{0}, errors_5xx{0}, submitted{0};
};

struct Caller {
  std::string name;
  Role role = Role::kiosk;
  bool admin() const { return role == Role::admin; }
};

}  // namespace

class Api {
 public:
  Api(httplib::Server& s, Daemon& d) : server_(s), d_(d) {}
  void install();

 private:
  using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
  // Runs a handler: API failures and popcut errors become their documented answers; the daemon
  // keeps serving whatever a request holds.
  Handler guarded(Handler h) {
    return [this, h](const httplib::Request& req, httplib::Response& res) {
      ++metrics_.requests;
      try {
        h(req, res);
      } catch (const ApiFailure& f) {
        send_error(res, f.code, f.message, f.field);
      } catch (const Error& e) {
        const ApiError code = e.code() == ErrorCode::limit ? ApiError::model_too_complex
                              : e.code() == ErrorCode::invalid_input ? ApiError::bad_model
                                                                     : ApiError::internal;
        send_error(res, code, e.what(), e.location());
      } catch (const std::exception& e) {
        log_line("internal error on ", req.method, " ", req.path, ": ", e.what());
        send_error(res, ApiError::internal, e.what());
      }
      if (res.status >= 500) ++metrics_.errors_5xx;
      else if (res.status >= 400) ++metrics_.errors_4xx;
    };
  }
  void get(const char* pattern, Handler h) { server_.Get(pattern, guarded(std::move(h))); }
  void post(const char* pattern, Handler h) { server_.Post(pattern, guarded(std::move(h))); }

  Caller auth(const httplib::Request& req) const {
    const std::string h = req.get_header_value("Authorization");
    if (h.empty()) fail(ApiError::unauthorized, "no token: send 'Authorization: Bearer TOKEN'");
    if (h.rfind("Bearer ", 0) != 0) fail(ApiError::unauthorized, "the Authorization header must be 'Bearer TOKEN'");
    const std::string token = h.substr(7);
    for (const TokenConfig& t : d_.config().tokens) {
      if (t.token.size() == token.size() && constant_time_equal(t.token, token)) return {t.name, t.role};
    }
    fail(ApiError::unauthorized, "unknown token");
  }
  static bool constant_time_equal(const std::string& a, const std::string& b) {
    unsigned char diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
    return diff == 0;
  }

  static json parse_body(const httplib::Request& req) {
    try {
      return json::parse(req.body);
    } catch (const json::parse_error& e) {
      fail(ApiError::bad_json, std::string("the body is not JSON: ") + e.what());
    }
  }
  static std::string string_field(const json& body, const char* key, bool required) {
    if (!body.contains(key) || body[key].is_null()) {
      if (required) fail(ApiError::bad_request, std::string("missing field '") + key + "'", key);
      return "";
    }
    if (!body[key].is_string()) fail(ApiError::bad_request, std::string("'") + key + "' must be a string", key);
    return body[key].get<std::string>();
  }
  static std::int64_t job_id(const httplib::Request& req) {
    const std::string s = req.matches[1];
    if (s.size() > 15) fail(ApiError::not_found, "no job " + s);
    return std::stoll(s);
  }
  Job visible_job(const httplib::Request& req, const Caller& c) {
    const std::int64_t id = job_id(req);
    std::optional<Job> j = d_.store().get(id);
    // Another's job is "not found" for a kiosk token: ids of others' jobs are not disclosed.
    if (!j || (!c.admin() && j->owner != c.name)) fail(ApiError::not_found, "no job " + std::to_string(id));
    return *j;
  }
  static int angle_param(const httplib::Request& req) {
    if (!req.has_param("angle")) return 90;
    const std::string a = req.get_param_value("angle");
    if (a.empty() || a.size() > 3 || a.find_first_not_of("0123456789") != std::string::npos || std::stoi(a) > 180) {
      fail(ApiError::bad_request, "angle must be a whole number of degrees from 0 to 180", "angle");
    }
    return std::stoi(a);
  }

  json job_json(const Job& j);
  void submit(const httplib::Request& req, httplib::Response& res);
  std::string render_png(const Pattern& p, int angle, const fs::path& out);
  void kiosk_file(const std::string& name, const char* type, httplib::Response& res);
  std::vector<std::pair<std::string, fs::path>> examples() const;

  httplib::Server& server_;
  Daemon& d_;
  Metrics metrics_;
  std::atomic<std::uint64_t> tmp_counter_{0};
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

json Api::job_json(const Job& j) {
  json r = {{"id", j.id},
            {"name", j.name},
            {"owner", j.owner},
            {"device", j.target_device.empty() ? json(nullptr) : json(j.target_device)},
            {"profile", j.target_profile},
            {"cut_on", j.device.empty() ? json(nullptr) : json(j.device)},
            {"state", to_string(j.state)},
            {"strokes_total", j.strokes_total},
            {"strokes_sent", j.strokes_sent},
            {"resume_from", j.resume_from},
            {"progress", j.strokes_total > 0 ? static_cast<double>(j.strokes_sent) / static_cast<double>(j.strokes_total) : 0.0},
            {"est_time_s", j.est_time_s},
            {"created_at", j.created_at},
            {"started_at", j.started_at > 0 ? json(j.started_at) : json(nullptr)},
            {"finished_at", j.finished_at > 0 ? json(j.finished_at) : json(nullptr)},
            {"place_in_line", nullptr},
            {"eta_s", nullptr}};
  if (!j.error_code.empty() || !j.error_message.empty()) r["error"] = {{"code", j.error_code}, {"message", j.error_message}};
  if (j.state == JobState::done) r["sim_match"] = j.sim_match;
  if (j.state == JobState::queued || j.state == JobState::planning || j.state == JobState::ready) {
    r["place_in_line"] = d_.store().place_in_line(j);
    if (j.state == JobState::ready) r["eta_s"] = d_.store().work_ahead_s(j) + j.est_time_s;
  } else if (j.state == JobState::cutting && j.strokes_total > 0) {
    r["eta_s"] = j.est_time_s * (1.0 - static_cast<double>(j.strokes_sent) / static_cast<double>(j.strokes_total));
  }
  return r;
}

void Api::submit(const httplib::Request& req, httplib::Response& res) {
  const Caller c = auth(req);
  const json body = parse_body(req);
  if (!body.is_object()) fail(ApiError::bad_request, "the body must be a JSON object");
  for (const auto& [k, v] : body.items()) {
    if (k != "name" && k != "device" && k != "profile" && k != "model") fail(ApiError::bad_request, "unknown field '" + k + "'", k);
  }
  NewJob nj;
  nj.owner = c.name;
  nj.name = string_field(body, "name", false);
  if (nj.name.empty()) nj.name = "card";
  if (!is_safe_name(nj.name)) {
    fail(ApiError::bad_name, "job names are 1 to 64 letters, digits, spaces, '-', '_' or '.', not starting with '.' and without '..'", "name");
  }
  nj.target_device = string_field(body, "device", false);
  nj.target_profile = string_field(body, "profile", false);
  if (nj.target_device.empty() == nj.target_profile.empty()) {
    fail(ApiError::bad_request, "name either a device or a profile (any device with it)", "device");
  }
  if (!nj.target_device.empty()) {
    if (!is_safe_name(nj.target_device)) fail(ApiError::bad_name, "not a device name: " + nj.target_device, "device");
    const DeviceConfig* dev = d_.device(nj.target_device);
    if (!dev) fail(ApiError::no_device, "no device named " + nj.target_device, "device");
    nj.target_profile = Daemon::profile_key(*dev);
  } else {
    if (!is_safe_name(nj.target_profile)) fail(ApiError::bad_name, "not a profile name: " + nj.target_profile, "profile");
    if (!d_.has_profile(nj.target_profile)) fail(ApiError::no_device, "no device has the profile " + nj.target_profile, "profile");
  }
  if (!body.contains("model")) fail(ApiError::bad_request, "missing field 'model'", "model");
  if (!body["model"].is_object()) fail(ApiError::bad_request, "'model' must be a popcut.voxel.v1 or popcut.faces.v1 object", "model");
  nj.model_json = body["model"].dump();
  checked_model(nj.model_json, "model", d_.config().limits);  // bad models are refused now, not at planning
  const std::optional<std::int64_t> id = d_.store().insert(nj, d_.config().limits.queue_length);
  if (!id) fail(ApiError::queue_full, "the queue holds " + std::to_string(d_.config().limits.queue_length) + " unfinished jobs; try later");
  ++metrics_.submitted;
  d_.notify();
  send_json(res, job_json(*d_.store().get(*id)), 201);
}

std::string Api::render_png(const Pattern& p, int angle, const fs::path& out) {
  const CardMesh mesh = fold_card(p, angle);
  // Frame the standing card at every angle so the slider does not make the picture jump.
  const ViewBox box = view_box({fold_card(p, 90), fold_card(p, 180), mesh});
  fs::create_directories(out.parent_path());
  const fs::path tmp = out.string() + ".tmp" + std::to_string(++tmp_counter_);
  write_render_png(tmp.string(), mesh, box, 480);
  fs::rename(tmp, out);
  return read_text_file(out.string(), std::size_t{64} << 20);
}

std::vector<std::pair<std::string, fs::path>> Api::examples() const {
  std::vector<std::pair<std::string, fs::path>> out;
  for (const char* sub : {"voxel", "faces"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(d_.config().examples_dir) / sub, ec)) {
      if (e.path().extension() == ".json") out.emplace_back(std::string(sub) + "-" + e.path().stem().string(), e.path());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

void Api::kiosk_file(const std::string& name, const char* type, httplib::Response& res) {
  std::ifstream in(fs::path(d_.config().kiosk_dir) / name, std::ios::binary);
  if (!in) fail(ApiError::not_found, "the kiosk page is not installed at " + d_.config().kiosk_dir);
  std::ostringstream o;
  o << in.rdbuf();
  res.set_content(o.str(), type);
}

void Api::install() {
  server_.set_payload_max_length(d_.config().limits.upload_bytes);
  server_.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler already answered
    if (res.status == 413) {
      ++metrics_.errors_4xx;
      // Debian's compiled httplib caps form-encoded bodies (what `curl -d` sends) at 8 KiB on
      // its own, whatever our limit: name the real cause and the fix.
      const bool form = req.get_header_value("Content-Type").rfind("application/x-www-form-urlencoded", 0) == 0;
      const std::string limit = std::to_string(d_.config().limits.upload_bytes);
      send_error(res, ApiError::too_large,
                 form && req.get_header_value<std::uint64_t>("Content-Length") <= d_.config().limits.upload_bytes
                     ? "a form-encoded body over 8192 bytes is refused: send JSON with 'Content-Type: application/json' "
                       "(curl: -H 'Content-Type: application/json' --data-binary @FILE); the limit for JSON is " + limit + " bytes"
                     : "the body exceeds " + limit + " bytes ([limits] upload_bytes)");
    } else if (res.status == 404) {
      ++metrics_.errors_4xx;
      send_error(res, ApiError::not_found, "no such resource: " + req.path);
    } else if (res.status >= 400 && res.status < 500) {
      ++metrics_.errors_4xx;
      send_error(res, ApiError::bad_request, "malformed request");
      res.status = 400;
    }
  });

  get("/healthz", [this](const httplib::Request&, httplib::Response& res) {
    send_json(res, {{"ok", true}, {"devices", d_.config().devices.size()}});
  });
  get("/metrics", [this](const httplib::Request&, httplib::Response& res) {
    std::ostringstream o;
    o << "# HELP popcutd_jobs Jobs in the store by state.\n# TYPE popcutd_jobs gauge\n";
    for (const auto& [state, n] : d_.store().count_by_state()) o << "popcutd_jobs{state=\"" << state << "\"} " << n << "\n";
    o << "# HELP popcutd_http_requests_total API requests answered.\n# TYPE popcutd_http_requests_total counter\n"
      << "popcutd_http_requests_total " << metrics_.requests << "\n"
      << "# HELP popcutd_http_errors_total Requests answered with an error, by class.\n# TYPE popcutd_http_errors_total counter\n"
      << "popcutd_http_errors_total{class=\"4xx\"} " << metrics_.errors_4xx << "\n"
      << "popcutd_http_errors_total{class=\"5xx\"} " << metrics_.errors_5xx << "\n"
      << "# HELP popcutd_jobs_submitted_total Jobs accepted since start.\n# TYPE popcutd_jobs_submitted_total counter\n"
      << "popcutd_jobs_submitted_total " << metrics_.submitted << "\n"
      << "# HELP popcutd_cuts_completed_total Cuts finished since start.\n# TYPE popcutd_cuts_completed_total counter\n"
      << "popcutd_cuts_completed_total " << d_.cuts_completed() << "\n"
      << "# HELP popcutd_device_busy 1 while the device cuts.\n# TYPE popcutd_device_busy gauge\n";
    for (const DeviceStatus& s : d_.devices()) o << "popcutd_device_busy{device=\"" << s.name << "\"} " << (s.job ? 1 : 0) << "\n";
    o << "# HELP popcutd_device_paused 1 while an admin holds the device.\n# TYPE popcutd_device_paused gauge\n";
    for (const DeviceStatus& s : d_.devices()) o << "popcutd_device_paused{device=\"" << s.name << "\"} " << (s.paused ? 1 : 0) << "\n";
    o << "# HELP popcutd_uptime_seconds Seconds since popcutd started.\n# TYPE popcutd_uptime_seconds gauge\n"
      << "popcutd_uptime_seconds " << std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() << "\n";
    res.set_content(o.str(), "text/plain; version=0.0.4");
  });

  // The kiosk page: a fixed list of files, so no request path ever reaches the file system.
  get("/", [this](const httplib::Request&, httplib::Response& res) { kiosk_file("index.html", "text/html; charset=utf-8", res); });
  get("/kiosk/app.js", [this](const httplib::Request&, httplib::Response& res) { kiosk_file("app.js", "text/javascript", res); });
  get("/kiosk/app.css", [this](const httplib::Request&, httplib::Response& res) { kiosk_file("app.css", "text/css", res); });

  get("/api/v1/examples", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    json list = json::array();
    for (const auto& [name, path] : examples()) list.push_back(name);
    send_json(res, {{"examples", list}});
  });
  get(R"(/api/v1/examples/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    const std::string want = req.matches[1];
    for (const auto& [name, path] : examples()) {
      if (name == want) return res.set_content(read_text_file(path.string()), "application/json");
    }
    fail(ApiError::not_found, "no example named " + want);
  });
  get("/api/v1/devices", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    json list = json::array();
    for (const DeviceStatus& s : d_.devices()) {
      list.push_back({{"name", s.name},
                      {"profile", s.profile},
                      {"model", d_.device(s.name)->profile.name},
                      {"state", s.paused ? (s.job ? "pausing" : "paused") : (s.job ? "cutting" : "idle")},
                      {"paused", s.paused},
                      {"job", s.job ? json(s.job) : json(nullptr)}});
    }
    send_json(res, {{"devices", list}});
  });
  const auto pause = [this](bool paused) {
    return [this, paused](const httplib::Request& req, httplib::Response& res) {
      if (!auth(req).admin()) fail(ApiError::forbidden, "pausing a device needs the admin token");
      const std::string name = req.matches[1];
      if (!d_.device(name)) fail(ApiError::not_found, "no device named " + name);
      d_.set_paused(name, paused);
      send_json(res, {{"device", name}, {"paused", paused}});
    };
  };
  post(R"(/api/v1/devices/([^/]+)/pause)", pause(true));
  post(R"(/api/v1/devices/([^/]+)/resume)", pause(false));

  post("/api/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) { submit(req, res); });
  get("/api/v1/jobs", [this](const httplib::Request& req, httplib::Response& res) {
    const Caller c = auth(req);
    int limit = 100;
    if (req.has_param("limit")) {
      const std::string l = req.get_param_value("limit");
      if (l.empty() || l.size() > 5 || l.find_first_not_of("0123456789") != std::string::npos || std::stoi(l) < 1 || std::stoi(l) > 10000) {
        fail(ApiError::bad_request, "limit must be a whole number from 1 to 10000", "limit");
      }
      limit = std::stoi(l);
    }
    json list = json::array();
    for (const Job& j : d_.store().list(c.admin() ? "" : c.name, limit)) list.push_back(job_json(j));
    send_json(res, {{"jobs", list}});
  });
  get(R"(/api/v1/jobs/(\d+))", [this](const httplib::Request& req, httplib::Response& res) {
    send_json(res, job_json(visible_job(req, auth(req))));
  });
  get(R"(/api/v1/jobs/(\d+)/pattern\.svg)", [this](const httplib::Request& req, httplib::Response& res) {
    const Job j = visible_job(req, auth(req));
    const fs::path svg = fs::path(d_.job_dir(j.id)) / "pattern.svg";
    if (!fs::exists(svg)) fail(ApiError::conflict, "job " + std::to_string(j.id) + " has no pattern (state " + to_string(j.state) + ")");
    res.set_content(read_text_file(svg.string(), std::size_t{64} << 20), "image/svg+xml");
  });
  get(R"(/api/v1/jobs/(\d+)/preview\.png)", [this](const httplib::Request& req, httplib::Response& res) {
    const Job j = visible_job(req, auth(req));
    const int angle = angle_param(req);
    const fs::path png = fs::path(d_.job_dir(j.id)) / ("preview-" + std::to_string(angle) + ".png");
    if (fs::exists(png)) return res.set_content(read_text_file(png.string(), std::size_t{64} << 20), "image/png");
    const std::optional<std::string> model = d_.store().model_json(j.id);
    if (!model) fail(ApiError::not_found, "no model for job " + std::to_string(j.id));
    res.set_content(render_png(checked_pattern(*model, "job", d_.config().limits), angle, png), "image/png");
  });
  post(R"(/api/v1/jobs/(\d+)/cancel)", [this](const httplib::Request& req, httplib::Response& res) {
    const Caller c = auth(req);
    const Job j = visible_job(req, c);
    switch (d_.cancel(j.id)) {
      case CancelResult::cancelled:
      case CancelResult::requested: break;
      case CancelResult::already_final:
        fail(ApiError::conflict, "job " + std::to_string(j.id) + " is already " + to_string(d_.store().get(j.id)->state));
      case CancelResult::not_found: fail(ApiError::not_found, "no job " + std::to_string(j.id));
    }
    send_json(res, job_json(*d_.store().get(j.id)), 202);
  });
  post(R"(/api/v1/jobs/(\d+)/resume)", [this](const httplib::Request& req, httplib::Response& res) {
    const Job j = visible_job(req, auth(req));
    if (!d_.store().resume(j.id)) fail(ApiError::conflict, "only an interrupted job resumes; job " + std::to_string(j.id) + " is " + to_string(j.state));
    d_.notify();
    send_json(res, job_json(*d_.store().get(j.id)), 202);
  });

  // Pictures of a model before it is queued (the kiosk's pattern and preview with its slider).
  post("/api/v1/render/pattern.svg", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    const Pattern p = checked_pattern(req.body, "model", d_.config().limits);
    res.set_content(to_pattern_svg(p, {true}), "image/svg+xml");
  });
  post("/api/v1/render/preview.png", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    const int angle = angle_param(req);
    const Pattern p = checked_pattern(req.body, "model", d_.config().limits);
    const fs::path tmp = fs::path(d_.config().data_dir) / "tmp" / ("preview-" + std::to_string(++tmp_counter_) + ".png");
    std::string png = render_png(p, angle, tmp);
    fs::remove(tmp);
    res.set_content(std::move(png), "image/png");
  });
}

HttpApi::HttpApi(httplib::Server& server, Daemon& daemon) : api_(std::make_unique<Api>(server, daemon)) { api_->install(); }
HttpApi::~HttpApi() = default;

}  // namespace popcut::daemon
