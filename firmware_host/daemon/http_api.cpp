// HTTP routes: token auth, JSON in and out, documented error codes; pictures rendered by core.
#include "http_api.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <unordered_set>

#include "log.h"
#include "model_limits.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/error.h"
#include "popcut/fold/fold.h"
#include "popcut/fold/render.h"
#include "popcut/io/files.h"
#include "popcut/io/pattern_io.h"
#include "popcut/mesh/import_request.h"
#include "preview_cache.h"
#include "../report_json.h"

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

// A preview renders on the request's thread; at most one per core (and half of the HTTP threads)
// do so at once: more would only make each slower. A request that finds no slot free is answered
// 503 busy at once instead of waiting, so job status, submissions and /healthz always have threads.
class RenderSlots {
 public:
  explicit RenderSlots(int http_threads)
      : free_(std::clamp(static_cast<int>(std::thread::hardware_concurrency()), 1, std::max(1, http_threads / 2))) {}
  bool try_take() {
    int n = free_.load();
    while (n > 0) {
      if (free_.compare_exchange_weak(n, n - 1)) return true;
    }
    return false;
  }
  void give() { ++free_; }

 private:
  std::atomic<int> free_;
};

bool iequals(const std::string& a, const std::string& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y)); });
}

// A file written for the length of one request (an uploaded mesh: the importer reads files).
struct TempFile {
  std::filesystem::path path;
  ~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
};

}  // namespace

class Api {
 public:
  Api(httplib::Server& s, Daemon& d)
      : server_(s), d_(d), previews_(d.config().limits.preview_cache_bytes), render_slots_(d.config().http_threads) {}
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
        // "model: model: ..." when the field is the whole submitted model: say it once.
        send_error(res, code, e.source() == e.location() ? e.source() + ": " + e.message() : std::string(e.what()), e.location());
      } catch (const std::exception& e) {
        log_line("internal error on ", req.method, " ", req.path, ": ", e.what());
        send_error(res, ApiError::internal, e.what());
      }
      if (res.status >= 500) ++metrics_.errors_5xx;
      else if (res.status >= 400) ++metrics_.errors_4xx;
    };
  }
  void get(const char* pattern, Handler h) {
    routes_.emplace_back(std::regex(pattern), "GET");
    server_.Get(pattern, guarded(std::move(h)));
  }
  // POST bodies are read here, not by httplib, which holds a chunked or compressed body to no
  // limit: every byte after decoding counts against [limits] upload_bytes, and reading stops at it.
  void post(const char* pattern, Handler h) {
    routes_.emplace_back(std::regex(pattern), "POST");
    server_.Post(pattern, [this, handler = guarded(std::move(h))](const httplib::Request& req, httplib::Response& res,
                                                                const httplib::ContentReader& content) {
      // httplib hands a content-reading handler its (non-const) request as const; the body goes
      // where httplib's own reader puts it, so handlers read req.body and req.files as ever.
      if (read_body(const_cast<httplib::Request&>(req), content, res)) handler(req, res);
    });
  }
  bool read_body(httplib::Request& req, const httplib::ContentReader& content, httplib::Response& res);
  bool refuse_before_body(const httplib::Request& req, httplib::Response& res);
  // An answer before the body is read. With `body_unread`, whatever body the client sends is left
  // unread, so the connection cannot carry another request: it is closed (http_server.cpp).
  void refuse(httplib::Response& res, ApiError code, const std::string& message, bool body_unread = true) {
    ++metrics_.requests;
    ++metrics_.errors_4xx;
    send_error(res, code, message);
    if (body_unread) res.set_header("Connection", "close");
  }

  Caller auth(const httplib::Request& req) const {
    const std::string h = req.get_header_value("Authorization");
    if (h.empty()) fail(ApiError::unauthorized, "no token: send 'Authorization: Bearer TOKEN'");
    // RFC 7235: the scheme is case-insensitive ("bearer" is Bearer); one or more spaces follow it.
    const std::size_t space = h.find(' ');
    if (space == std::string::npos || !iequals(h.substr(0, space), "Bearer")) {
      fail(ApiError::unauthorized, "the Authorization header must be 'Bearer TOKEN'");
    }
    const std::size_t start = h.find_first_not_of(' ', space);
    const std::string token = start == std::string::npos ? "" : h.substr(start);
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

  // JSON with a key given twice in one object is refused: the parser would keep the last and
  // {"device": "a", "device": "b"} would go to b without a word (RFC 8259 leaves it open).
  static json parse_body(const httplib::Request& req) {
    std::vector<std::unordered_set<std::string>> keys;  // per open object, the keys seen so far
    std::string repeated;
    const json::parser_callback_t check = [&](int depth, json::parse_event_t event, json& parsed) {
      // The model's own limit (64 levels) plus the body around it. Deeper, the job's model_json
      // dump (recursive) overflowed the stack of a request thread at ~75,000 levels.
      if (depth > 65) fail(ApiError::bad_json, "the body is nested deeper than 65 levels (a model may nest 64)");
      if (event == json::parse_event_t::object_start) keys.emplace_back();
      else if (event == json::parse_event_t::object_end) keys.pop_back();
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
    }
    if (!repeated.empty()) fail(ApiError::bad_request, "'" + repeated + "' given twice in one object", repeated);
    return body;
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
  // POST resume's optional body {"from": "received" | "executed"}; none (or {}) is "received".
  static ResumePoint resume_point(const httplib::Request& req) {
    if (req.body.empty()) return ResumePoint::received;
    const json body = parse_body(req);
    if (!body.is_object()) fail(ApiError::bad_request, "the body must be a JSON object such as {\"from\": \"executed\"}, or empty");
    for (const auto& [k, v] : body.items()) {
      if (k != "from") fail(ApiError::bad_request, "unknown field '" + k + "' (resume takes 'from')", k);
    }
    const std::string from = string_field(body, "from", false);
    if (!body.contains("from") || body["from"].is_null()) return ResumePoint::received;
    const std::optional<ResumePoint> point = parse_resume_point(from);
    if (!point) fail(ApiError::bad_request, "'from' must be \"received\" (after the strokes the device certainly received, the default) or \"executed\" (after those it is known to have executed: for a device that was reset or power-cycled)", "from");
    return *point;
  }
  // Polls until job `id` is in a final state (or interrupted), at most `limit`.
  void wait_for_final(std::int64_t id, std::chrono::milliseconds limit) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      const std::optional<Job> j = d_.store().get(id);
      if (!j || j->state != JobState::cutting) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  // Rounded to a multiple of kAngleStepDeg (the kiosk slider's step): at most 37 pictures per model.
  static constexpr int kAngleStepDeg = 5;
  // A query parameter given at most once: ?angle=10&angle=20 is a malformed request, not a guess.
  static std::optional<std::string> query_param(const httplib::Request& req, const char* name) {
    const std::size_t n = req.get_param_value_count(name);
    if (n > 1) fail(ApiError::bad_request, std::string("'") + name + "' given twice in the query", name);
    if (n == 0) return std::nullopt;
    return req.get_param_value(name);
  }
  static int angle_param(const httplib::Request& req) {
    const std::optional<std::string> given = query_param(req, "angle");
    if (!given) return 90;
    const std::string& a = *given;
    // Whole degrees (previews are cached per step); "-0" is 0, as a slider or a script may send it.
    const std::string digits = a == "-0" ? "0" : a;
    if (digits.empty() || digits.size() > 15 || digits.find_first_not_of("0123456789") != std::string::npos) {
      fail(ApiError::bad_request, "angle must be a whole number of degrees from 0 to 180, not '" + a.substr(0, 40) + "'", "angle");
    }
    const long long angle = std::stoll(digits);
    try {
      check_fold_angle(static_cast<double>(angle), "angle");  // the range every command and field that takes an angle has
    } catch (const Error& e) {
      fail(ApiError::bad_request, e.message(), "angle");
    }
    return static_cast<int>((angle + kAngleStepDeg / 2) / kAngleStepDeg * kAngleStepDeg);
  }

  // The queue played forward once per request (docs/api.md eta_s), shared by every job listed.
  using Forecast = std::unordered_map<std::int64_t, double>;
  Forecast forecast();
  static double busy_s(const DeviceStatus& device, const std::vector<Job>& cutting);
  json job_json(const Job& j, const Forecast* forecast = nullptr);
  void submit(const httplib::Request& req, httplib::Response& res);
  void set_target(NewJob& nj, const std::string& device, const std::string& profile);
  std::vector<std::string> check_for_device(const NewJob& nj, const std::string& source);
  std::vector<NamedMedia> media() const;
  struct Upload {
    MeshImport imported;
    std::string filename;
    std::map<std::string, std::string> fields;  // the non-option fields named in `fields`
  };
  Upload import_upload(const httplib::Request& req, const std::vector<std::string>& fields);
  std::string preview(const std::string& key, int angle, const std::function<Pattern()>& pattern);
  std::string preview_png(const Pattern& p, int angle);
  void kiosk_file(const std::string& name, const char* type, httplib::Response& res);
  std::vector<std::pair<std::string, fs::path>> examples() const;
  static std::string example_name(const std::string& id, const fs::path& path);

  httplib::Server& server_;
  Daemon& d_;
  Metrics metrics_;
  PreviewCache previews_;
  RenderSlots render_slots_;
  std::vector<std::pair<std::regex, std::string>> routes_;  // path pattern, method: for 404 and 405 before routing
  std::atomic<std::uint64_t> tmp_counter_{0};
  std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

// What the cut on `device` has left, by the device's clock; 0 when it is idle.
double Api::busy_s(const DeviceStatus& device, const std::vector<Job>& cutting) {
  for (const Job& j : cutting) {
    if (j.id == device.job) return cut_left_s(j, device.time_factor, device.run_started_s, unix_now_s());
  }
  return 0;
}

Api::Forecast Api::forecast() {
  const std::vector<Job> cutting = d_.store().cutting();
  std::vector<ForecastDevice> taking;  // devices that start new cuts
  for (const DeviceStatus& dev : d_.devices()) {
    if (!dev.paused) taking.push_back({dev.name, dev.profile, dev.time_factor, busy_s(dev, cutting)});
  }
  return forecast_done_s(d_.store().waiting(), std::move(taking));
}

json Api::job_json(const Job& j, const Forecast* shared) {
  json r = {{"id", j.id},
            {"name", j.name},
            {"owner", j.owner},
            {"device", j.target_device.empty() ? json(nullptr) : json(j.target_device)},
            {"profile", j.target_profile},
            {"cut_on", j.device.empty() ? json(nullptr) : json(j.device)},
            {"bound_to", j.bound_device().empty() ? json(nullptr) : json(j.bound_device())},
            {"state", to_string(j.state)},
            {"strokes_total", j.strokes_total},
            {"strokes_sent", j.strokes_sent},
            {"resume_from", j.resume_from},
            {"resume_point", j.resume_point ? json(to_string(*j.resume_point)) : json(nullptr)},
            {"strokes_executed", j.strokes_executed ? json(*j.strokes_executed) : json(nullptr)},
            {"progress", j.strokes_total > 0 ? static_cast<double>(j.strokes_sent) / static_cast<double>(j.strokes_total) : 0.0},
            {"est_time_s", j.est_time_s},
            {"created_at", j.created_at},
            {"started_at", j.started_at > 0 ? json(j.started_at) : json(nullptr)},
            {"finished_at", j.finished_at > 0 ? json(j.finished_at) : json(nullptr)},
            {"place_in_line", nullptr},
            {"eta_s", nullptr}};
  if (!j.error_code.empty() || !j.error_message.empty()) r["error"] = {{"code", j.error_code}, {"message", j.error_message}};
  // Only a simulated cutter reports what it cut; for a real one there is nothing to compare.
  const DeviceConfig* cut_on = d_.device(j.device);
  if (j.state == JobState::done && cut_on && cut_on->transport == "sim") r["sim_match"] = j.sim_match;
  if (j.state == JobState::queued || j.state == JobState::planning || j.state == JobState::ready) {
    r["place_in_line"] = d_.store().place_in_line(j);
    if (j.state == JobState::ready) {
      const Forecast own = shared ? Forecast() : forecast();
      const Forecast& f = shared ? *shared : own;
      if (const auto it = f.find(j.id); it != f.end()) r["eta_s"] = it->second;
    }
  } else if (j.state == JobState::cutting) {
    r["cancel"] = nullptr;
    for (const DeviceStatus& dev : d_.devices()) {
      if (dev.job != j.id) continue;
      r["eta_s"] = busy_s(dev, {j});
      if (dev.cancel != CancelStage::none) r["cancel"] = to_string(dev.cancel);
    }
  }
  return rounded_numbers(std::move(r));
}

void Api::set_target(NewJob& nj, const std::string& device, const std::string& profile) {
  if (!is_job_label(nj.name)) {
    fail(ApiError::bad_name, "job names are 1 to 64 characters of text in any script, without control characters, direction overrides, '/', '\\', '..', a leading '.' or a space at either end", "name");
  }
  nj.target_device = device;
  nj.target_profile = profile;
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
}

// The media of every configured device, by the device's name: what --fit-mm may name.
std::vector<NamedMedia> Api::media() const {
  std::vector<NamedMedia> out;
  for (const DeviceConfig& dev : d_.config().devices) out.push_back(drivers::media_of(dev.profile, dev.name));
  return out;
}

// The checks planning would make, made before the job is accepted: a model that is not a card,
// is over [limits], or whose sheet does not fit the device is refused now (4xx), not failed later.
// Returns the devices whose media the sheet is too big for (the job may still go to another).
std::vector<std::string> Api::check_for_device(const NewJob& nj, const std::string& source) {
  const Pattern p = checked_pattern(nj.model_json, source, d_.config().limits);
  const DeviceConfig* dev = d_.planning_device(nj.target_device, nj.target_profile);
  if (!dev) fail(ApiError::no_device, "no device for this job", "device");
  try {
    drivers::plan_for_device(p, dev->profile, dev->profile_path);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    fail(ApiError::bad_model, "the card does not fit " + (nj.target_device.empty() ? "profile " + nj.target_profile : nj.target_device) +
                                  ": " + e.message(), "model");
  }
  return media_warnings(p.sheet, media());
}

Api::Upload Api::import_upload(const httplib::Request& req, const std::vector<std::string>& fields) {
  Upload u;
  const httplib::MultipartFormData* mesh = nullptr;
  std::vector<std::pair<std::string, std::string>> options;
  for (const auto& [key, part] : req.files) {
    if (key == "mesh") {
      if (mesh) fail(ApiError::bad_request, "more than one 'mesh' part", "mesh");
      mesh = &part;
    } else if (std::find(fields.begin(), fields.end(), key) != fields.end()) {
      if (u.fields.count(key)) fail(ApiError::bad_request, "'" + key + "' given twice", key);
      u.fields[key] = part.content;
    } else if (std::find(kImportOptionNames.begin(), kImportOptionNames.end(), key) != kImportOptionNames.end()) {
      // A repeated part is a malformed form (400) like a repeated 'name' or 'mesh', not a bad model.
      const bool repeated = std::any_of(options.begin(), options.end(), [&](const auto& o) { return o.first == key; });
      if (repeated) fail(ApiError::bad_request, "'" + key + "' given twice", key);
      options.emplace_back(key, part.content);
    } else {
      std::string known = "mesh";
      for (const std::string& f : fields) known += ", " + f;
      for (std::string_view n : kImportOptionNames) known += ", " + std::string(n);
      fail(ApiError::bad_request, "unknown field '" + key + "' (expected " + known + ")", key);
    }
  }
  if (!mesh) fail(ApiError::bad_request, "missing the 'mesh' file part (curl: -F mesh=@FILE)", "mesh");
  if (mesh->filename.empty()) fail(ApiError::bad_request, "'mesh' must be a file part, not a value (curl: -F mesh=@FILE)", "mesh");
  u.filename = mesh->filename;
  // Only its extension (the format) and stem (the job's default name) are used, never as a path:
  // a job name's rules (any script, no '/', '\\', '..', control characters).
  if (!is_job_label(u.filename)) {
    fail(ApiError::bad_name, "mesh file names are 1 to 64 characters of text in any script, without control characters, '/', '\\', '..', a leading '.' or a space at either end", "mesh");
  }
  try {
    ImportRequest request = parse_import_options(options, u.filename, media());
    request.options.max_cells = d_.config().limits.model_cells;
    request.options.name = u.fields.count("name") ? u.fields["name"] : fs::path(u.filename).stem().string();
    // The importer reads files and picks the format by the extension: the upload's own.
    TempFile tmp{fs::path(d_.config().data_dir) / "tmp" / ("upload-" + std::to_string(++tmp_counter_) + fs::path(u.filename).extension().string())};
    fs::create_directories(tmp.path.parent_path());
    write_text_file(tmp.path.string(), [&](std::ostream& o) { o << mesh->content; });
    u.imported = import_mesh_file(tmp.path.string(), request, u.filename, d_.config().limits.mesh_triangles);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::io || e.code() == ErrorCode::internal) throw;
    // The importer's own message; the field is the option at fault, as named in the form: a bad
    // value of a field is a bad request (400), a fault inside the mesh a bad model (422, field
    // "mesh", the message naming the place: "line 3", "face 1"), either over a limit 413.
    const bool option = e.location().rfind("--", 0) == 0;
    const std::string field = option ? e.location().substr(2) : "mesh";
    fail(e.code() == ErrorCode::limit ? ApiError::model_too_complex : option ? ApiError::bad_request : ApiError::bad_model, e.what(), field);
  }
  return u;
}

void Api::submit(const httplib::Request& req, httplib::Response& res) {
  const Caller c = auth(req);
  NewJob nj;
  nj.owner = c.name;
  std::string source = "model";
  if (req.is_multipart_form_data()) {
    // A mesh with popcut import's options: imported now, so its errors answer this request; the
    // job then holds the imported model like any other.
    Upload u = import_upload(req, {"name", "device", "profile"});
    // Unnamed, the job is named after the file (house.obj: "house").
    if (u.fields.count("name") && u.fields["name"].empty()) fail(ApiError::bad_request, "'name' is empty: leave it out to name the job after its file", "name");
    nj.name = u.fields.count("name") ? u.fields["name"] : fs::path(u.filename).stem().string();
    set_target(nj, u.fields["device"], u.fields["profile"]);
    nj.model_json = std::move(u.imported.model_json);
    source = u.filename;
  } else {
    const json body = parse_body(req);
    if (!body.is_object()) fail(ApiError::bad_request, "the body must be a JSON object");
    for (const auto& [k, v] : body.items()) {
      if (k != "name" && k != "device" && k != "profile" && k != "model") fail(ApiError::bad_request, "unknown field '" + k + "'", k);
    }
    if (!body.contains("model")) fail(ApiError::bad_request, "missing field 'model'", "model");
    if (!body["model"].is_object()) fail(ApiError::bad_request, "'model' must be a popcut.voxel.v1 or popcut.faces.v1 object", "model");
    nj.name = string_field(body, "name", false);
    const bool named = body.contains("name") && !body["name"].is_null();
    if (named && nj.name.empty()) fail(ApiError::bad_request, "'name' is empty: leave it out to name the job after its model", "name");
    if (!named) {
      // Unnamed, the job takes its model's name ("Castle gatehouse with towers"), else "card".
      const json& model_name = body["model"].value("name", json());
      const std::string label = model_name.is_string() ? job_label_from(model_name.get<std::string>()) : "";
      nj.name = label.empty() ? "card" : label;
    }
    set_target(nj, string_field(body, "device", false), string_field(body, "profile", false));
    nj.model_json = body["model"].dump();
  }
  const std::vector<std::string> warnings = check_for_device(nj, source);
  const std::optional<std::int64_t> id = d_.store().insert(nj, d_.config().limits.queue_length);
  if (!id) fail(ApiError::queue_full, "the queue holds " + std::to_string(d_.config().limits.queue_length) + " unfinished jobs; try later");
  ++metrics_.submitted;
  d_.notify();
  json answer = job_json(*d_.store().get(*id));
  answer["warnings"] = warnings;
  send_json(res, answer, 201);
}

std::string Api::preview_png(const Pattern& p, int angle) {
  const CardMesh mesh = fold_card_for_picture(p, angle);
  // Frame the standing card at every angle so the slider does not make the picture jump.
  const ViewBox box = view_box({fold_card(p, 90), fold_card(p, 180), mesh});
  return render_png(mesh, box, 480);  // in memory: no temporary file to write and read back
}

std::string Api::preview(const std::string& key, int angle, const std::function<Pattern()>& pattern) {
  if (std::optional<std::string> png = previews_.get(key)) return *png;
  if (!render_slots_.try_take()) fail(ApiError::busy, "every preview slot is rendering; retry in a moment");
  struct Give {
    RenderSlots& s;
    ~Give() { s.give(); }
  } give{render_slots_};
  std::string png = preview_png(pattern(), angle);
  previews_.put(key, png);
  return png;
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

// What an example is called where people pick it: its model's own name (a face model may call
// it title; a long one shortened as a job's name is), else its id; a name no job could carry (a
// path, control characters) is not shown.
std::string Api::example_name(const std::string& id, const fs::path& path) {
  try {
    const json model = json::parse(read_text_file(path.string()));
    for (const char* key : {"name", "title"}) {
      const json& v = model.value(key, json());
      if (const std::string label = v.is_string() ? job_label_from(v.get<std::string>()) : ""; !label.empty()) return label;
    }
  } catch (const std::exception&) {
    // An unreadable example still gets listed by its id; fetching it names the fault.
  }
  return id;
}

void Api::kiosk_file(const std::string& name, const char* type, httplib::Response& res) {
  std::ifstream in(fs::path(d_.config().kiosk_dir) / name, std::ios::binary);
  if (!in) fail(ApiError::not_found, "the kiosk page is not installed at " + d_.config().kiosk_dir);
  std::ostringstream o;
  o << in.rdbuf();
  res.set_content(o.str(), type);
}

bool Api::refuse_before_body(const httplib::Request& req, httplib::Response& res) {
  // A path no route has is 404 whatever the method; a method the path does not take is 405
  // with Allow (HEAD goes with GET), for PUT, PATCH, DELETE and OPTIONS as for GET and POST.
  bool has_get = false, has_post = false;
  for (const auto& [pattern, method] : routes_) {
    if (!std::regex_match(req.path, pattern)) continue;
    (method == "GET" ? has_get : has_post) = true;
  }
  const std::string allow = has_get && has_post ? "GET, HEAD, POST" : has_get ? "GET, HEAD" : has_post ? "POST" : "";
  const bool routed = ((req.method == "GET" || req.method == "HEAD") && has_get) || (req.method == "POST" && has_post);
  const std::string declared = req.get_header_value("Content-Length");
  const bool body = req.has_header("Transfer-Encoding") || !(declared.empty() || declared == "0");
  if (allow.empty()) {
    refuse(res, ApiError::not_found, "no such resource: " + req.path, body);
    return true;
  }
  if (!routed) {
    res.set_header("Allow", allow);
    refuse(res, ApiError::method_not_allowed, req.method + " is not allowed on " + req.path + " (Allow: " + allow + ")", body);
    return true;
  }
  // Query parameters the API does not take are refused, not ignored (?zoom=2 is a typo or a
  // client expecting something popcutd does not do). The page itself (/?token=) is not the API.
  if (req.path.rfind("/api/", 0) == 0) {
    const bool picture = req.path.size() > 12 && req.path.compare(req.path.size() - 12, 12, "/preview.png") == 0;
    const char* takes = picture ? "angle" : (req.path == "/api/v1/jobs" && req.method != "POST") ? "limit" : "";
    for (const auto& [key, value] : req.params) {
      if (key != takes) {
        refuse(res, ApiError::bad_request,
               "unknown query parameter '" + key.substr(0, 40) + "'" + (*takes ? std::string(" (this takes ") + takes + ")" : std::string(" (this takes none)")),
               body);
        return true;
      }
    }
  }
  // Framing, RFC 7230 3.3: one length, or chunked alone; anything else could be read two ways.
  const bool chunked = req.has_header("Transfer-Encoding");
  if (chunked && (req.get_header_value_count("Transfer-Encoding") > 1 || !iequals(req.get_header_value("Transfer-Encoding"), "chunked"))) {
    refuse(res, ApiError::bad_request, "Transfer-Encoding: only 'chunked' is understood");
    return true;
  }
  // httplib (built with zlib and brotli) decodes gzip, deflate and br, spelt in lower case, and
  // passes any other coding through as if it were none: the compressed bytes would be read as the
  // body (a "GZIP" body was refused as bad_json).
  if (req.has_header("Content-Encoding")) {
    const std::string coding = req.get_header_value("Content-Encoding");
    if (req.get_header_value_count("Content-Encoding") > 1 ||
        !(iequals(coding, "identity") || coding == "gzip" || coding == "deflate" || coding == "br")) {
      refuse(res, ApiError::bad_request, "Content-Encoding: only gzip, deflate or br (in lower case) or identity is understood, not '" +
                                             coding.substr(0, 40) + "'");
      return true;
    }
  }
  std::string length;
  for (std::size_t i = 0; i < req.get_header_value_count("Content-Length"); ++i) {
    const std::string v = req.get_header_value("Content-Length", i);
    if (v.empty() || v.size() > 18 || v.find_first_not_of("0123456789") != std::string::npos) {
      refuse(res, ApiError::bad_request, "Content-Length must be a number of bytes, not '" + v.substr(0, 40) + "'");
      return true;
    }
    if (i > 0 && v != length) {
      refuse(res, ApiError::bad_request, "two different Content-Length headers (" + length + " and " + v + ")");
      return true;
    }
    length = v;
  }
  if (chunked && !length.empty()) {
    refuse(res, ApiError::bad_request, "both Content-Length and Transfer-Encoding: send one");
    return true;
  }
  if (req.method != "POST") {
    // httplib does not read such a body: it would be parsed as the next request.
    if (chunked || (!length.empty() && std::stoull(length) > 0)) {
      refuse(res, ApiError::bad_request, "a " + req.method + " request has no body");
      return true;
    }
    return false;
  }
  // httplib reads a POST body without Content-Length until the client closes: a client that
  // neither sends a length nor closes would hold a thread for the whole read timeout.
  if (length.empty() && !chunked) {
    refuse(res, ApiError::length_required, "a POST needs Content-Length (curl: -d '' for an empty body)");
    return true;
  }
  try {
    auth(req);
  } catch (const ApiFailure& f) {
    refuse(res, f.code, f.message);
    return true;
  }
  const std::size_t limit = d_.config().limits.upload_bytes;
  if (!length.empty() && std::stoull(length) > limit) {
    refuse(res, ApiError::too_large, "the body exceeds " + std::to_string(limit) + " bytes ([limits] upload_bytes)");
    return true;
  }
  return false;
}

bool Api::read_body(httplib::Request& req, const httplib::ContentReader& content, httplib::Response& res) {
  const std::size_t limit = d_.config().limits.upload_bytes;
  std::size_t total = 0;
  const auto take = [&](std::size_t n) { return (total += n) <= limit; };
  bool read = false;
  if (req.is_multipart_form_data()) {
    httplib::MultipartFormDataMap::iterator part;
    read = content(
        [&](const httplib::MultipartFormData& header) {
          if (!take(header.name.size() + header.filename.size() + header.content_type.size())) return false;
          part = req.files.emplace(header.name, header);
          return true;
        },
        [&](const char* data, std::size_t n) {
          if (!take(n)) return false;
          part->second.content.append(data, n);
          return true;
        });
  } else {
    read = content([&](const char* data, std::size_t n) {
      if (!take(n)) return false;
      req.body.append(data, n);
      return true;
    });
  }
  if (read) return true;
  if (total > limit) {
    refuse(res, ApiError::too_large, "the body exceeds " + std::to_string(limit) + " bytes ([limits] upload_bytes)");
  } else {
    refuse(res, ApiError::bad_request, "the body could not be read (malformed chunked or multipart encoding, an unknown "
                                       "Content-Encoding, or the client stopped sending)");
  }
  return false;
}

void Api::install() {
  server_.set_payload_max_length(d_.config().limits.upload_bytes);
  // Checked from the request line and headers alone, before a byte of the body is read; with
  // "Expect: 100-continue" before the client is told to send it.
  server_.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    return refuse_before_body(req, res) ? httplib::Server::HandlerResponse::Handled : httplib::Server::HandlerResponse::Unhandled;
  });
  server_.set_expect_100_continue_handler([this](const httplib::Request& req, httplib::Response& res) {
    return refuse_before_body(req, res) ? res.status : 100;
  });
  server_.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler already answered
    if (res.status == 413) {
      ++metrics_.errors_4xx;
      send_error(res, ApiError::too_large, "the body exceeds " + std::to_string(d_.config().limits.upload_bytes) + " bytes ([limits] upload_bytes)");
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
    json list = json::array(), names = json::object();
    for (const auto& [id, path] : examples()) {
      list.push_back(id);
      names[id] = example_name(id, path);
    }
    send_json(res, {{"examples", list}, {"names", names}});
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
    const Caller c = auth(req);
    json list = json::array();
    for (const DeviceStatus& s : d_.devices()) {
      // A kiosk sees which of its own jobs a device cuts; another's id would only answer 404.
      std::optional<Job> cutting;
      if (s.job && !c.admin()) cutting = d_.store().get(s.job);
      const bool shown = s.job && (c.admin() || (cutting && cutting->owner == c.name));
      list.push_back({{"name", s.name},
                      {"profile", s.profile},
                      {"model", d_.device(s.name)->profile.name},
                      {"state", s.paused ? (s.job ? "pausing" : "paused") : (s.job ? "cutting" : "idle")},
                      {"paused", s.paused},
                      {"job", shown ? json(s.job) : json(nullptr)}});
    }
    send_json(res, {{"devices", list}});
  });
  const auto pause = [this](bool paused) {
    return [this, paused](const httplib::Request& req, httplib::Response& res) {
      if (!auth(req).admin()) fail(ApiError::forbidden, std::string(paused ? "pausing" : "resuming") + " a device needs the admin token");
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
    if (const std::optional<std::string> given = query_param(req, "limit")) {
      const std::string& l = *given;
      if (l.empty() || l.size() > 5 || l.find_first_not_of("0123456789") != std::string::npos || std::stoi(l) < 1 || std::stoi(l) > 10000) {
        fail(ApiError::bad_request, "limit must be a whole number from 1 to 10000", "limit");
      }
      limit = std::stoi(l);
    }
    json list = json::array();
    const std::vector<Job> jobs = d_.store().list(c.admin() ? "" : c.name, limit);
    const bool any_ready = std::any_of(jobs.begin(), jobs.end(), [](const Job& j) { return j.state == JobState::ready; });
    const Forecast f = any_ready ? forecast() : Forecast();
    for (const Job& j : jobs) list.push_back(job_json(j, &f));
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
    res.set_content(preview("job " + std::to_string(j.id) + " " + std::to_string(angle), angle, [&] {
                      const std::optional<std::string> model = d_.store().model_json(j.id);
                      if (!model) fail(ApiError::not_found, "no model for job " + std::to_string(j.id));
                      return checked_pattern(*model, "job", d_.config().limits);
                    }),
                    "image/png");
  });
  post(R"(/api/v1/jobs/(\d+)/cancel)", [this](const httplib::Request& req, httplib::Response& res) {
    const Caller c = auth(req);
    const Job j = visible_job(req, c);
    switch (d_.cancel(j.id)) {
      case CancelResult::cancelled:
      case CancelResult::requested: break;
      case CancelResult::giving_up: {
        // The sender notices within one write slice (a quarter second) and the worker records the
        // job: answer with that outcome (200), or, should it take longer, with the job as it is (202).
        wait_for_final(j.id, std::chrono::seconds(10));
        const Job now = *d_.store().get(j.id);
        return send_json(res, job_json(now), is_terminal(now.state) ? 200 : 202);
      }
      case CancelResult::already_final:
        fail(ApiError::conflict, "job " + std::to_string(j.id) + " is already " + to_string(d_.store().get(j.id)->state));
      case CancelResult::not_found: fail(ApiError::not_found, "no job " + std::to_string(j.id));
    }
    send_json(res, job_json(*d_.store().get(j.id)), 202);
  });
  post(R"(/api/v1/jobs/(\d+)/resume)", [this](const httplib::Request& req, httplib::Response& res) {
    const Job j = visible_job(req, auth(req));
    const ResumePoint from = resume_point(req);
    // The rest of a half-cut sheet is cut on the device holding it: without that device, a
    // resume would wait for good.
    if (const std::string bound = j.bound_device(); j.state == JobState::interrupted && !bound.empty() && !d_.device(bound)) {
      fail(ApiError::conflict, "job " + std::to_string(j.id) + " was cut on " + bound + ", which holds its half-cut sheet and is not " +
                                   "configured any more; only that device may finish it: configure it again, or cancel the job and submit it anew");
    }
    switch (d_.store().resume(j.id, from)) {
      case ResumeResult::resumed: break;
      case ResumeResult::not_interrupted:
        fail(ApiError::conflict, "only an interrupted job resumes; job " + std::to_string(j.id) + " is " + to_string(d_.store().get(j.id)->state));
      case ResumeResult::executed_unknown:
        fail(ApiError::conflict, "job " + std::to_string(j.id) + ": the strokes the device executed are unknown (its transport gives no "
                                 "status answers, or the cut ended without asking, e.g. popcutd was killed), so there is no "
                                 "executed point to resume from; resume from \"received\" if the device kept its buffer",
             "from");
    }
    d_.notify();
    send_json(res, job_json(*d_.store().get(j.id)), 202);
  });

  // Pictures of a model before it is queued (the kiosk's pattern and preview with its slider).
  post("/api/v1/render/pattern.svg", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    parse_body(req);  // not JSON at all: bad_json, as for a submission
    const Pattern p = checked_pattern(req.body, "model", d_.config().limits);
    res.set_content(to_pattern_svg(p, {true}), "image/svg+xml");
  });
  post("/api/v1/render/preview.png", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    const int angle = angle_param(req);
    parse_body(req);
    res.set_content(preview("model " + std::to_string(angle) + " " + req.body, angle,
                            [&] { return checked_pattern(req.body, "model", d_.config().limits); }),
                    "image/png");
  });
  // A mesh turned into a model with popcut import's options, for the kiosk to show and queue.
  post("/api/v1/import", [this](const httplib::Request& req, httplib::Response& res) {
    auth(req);
    if (!req.is_multipart_form_data()) fail(ApiError::bad_request, "send the mesh as multipart/form-data (curl: -F mesh=@FILE)", "mesh");
    const Upload u = import_upload(req, {"name"});
    checked_model(u.imported.model_json, u.filename, d_.config().limits);
    const ImportResult& r = u.imported.voxels;
    const Rect& sheet = u.imported.pattern.sheet;
    const double width_mm = sheet.max.x_mm - sheet.min.x_mm;
    send_json(res, {{"model", json::parse(u.imported.model_json)},
                    {"sheet_mm", {{"width", width_mm}, {"height", sheet.max.v_mm - sheet.min.v_mm}}},
                    {"closed_mm", {{"width", width_mm}, {"height", std::max(sheet.max.v_mm, -sheet.min.v_mm)}}},
                    {"warnings", media_warnings(sheet, media())},
                    {"format", u.imported.faces ? kFacesFormat : "popcut.voxel.v1"},
                    {"triangles", r.stats.triangles},
                    {"grid", {{"width", r.grid.width}, {"depth", r.grid.depth}, {"height", r.grid.height}, {"voxel_mm", r.grid.voxel_mm}}},
                    {"cells_filled", r.stats.cells_filled},
                    {"windows_added", r.stats.windows_added},
                    {"tops_dropped", r.stats.tops_dropped}});
  });
}

HttpApi::HttpApi(httplib::Server& server, Daemon& daemon) : api_(std::make_unique<Api>(server, daemon)) { api_->install(); }
HttpApi::~HttpApi() = default;

}  // namespace popcut::daemon
