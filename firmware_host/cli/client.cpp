// popcut's client commands: JSON over HTTP to popcutd, its error codes shown and mapped to exit codes.
#include "cli/client.h"

#include <httplib.h>

#include <array>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "cli/checks.h"
#include "cli/common.h"
#include "cli/import.h"
#include "cli/client_answers.h"
#include "popcut/error.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/files.h"
#include "popcut/io/design_json.h"
#include "popcut/io/oa_model.h"
#include "popcut/mesh/mesh_import.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

// What went wrong talking to the daemon, with the exit code it maps to.
struct ClientFailure {
  int exit_code;
  std::string message;
};

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

// JSON no deeper than a popcut model may be (64 levels, and the answer or body around it):
// serialising a deeper document recurses once per level and overflows the stack.
json parse_shallow(const std::string& text, int exit_code, const std::string& what) {
  return json::parse(text, [&](int depth, json::parse_event_t, json&) {
    if (depth > 66) throw ClientFailure{exit_code, what + ": JSON nested deeper than 64 levels"};
    return true;
  });
}

class Connection {
 public:
  Connection(const std::string& server, const std::string& token) : server_(server), client_(check(server)) {
    if (!token.empty()) client_.set_default_headers({{"Authorization", "Bearer " + token}});
    client_.set_connection_timeout(5);
    client_.set_read_timeout(60);
    client_.set_tcp_nodelay(true);
  }
  // `shape` says what is wrong with a successful answer ("" if nothing): anything but popcutd's
  // shapes means something else answers at that address.
  using Shape = std::string (*)(const json&);
  json request(const std::string& method, const std::string& path, Shape shape, const std::string& body = "",
               const httplib::Headers& headers = {}) {
    return retried(headers, shape, [&] {
      if (method == "GET") return client_.Get(path, headers);
      if (method == "PATCH") return client_.Patch(path, headers, body, "application/json");
      return client_.Post(path, headers, body, "application/json");
    });
  }
  json post_form(const std::string& path, const httplib::MultipartFormDataItems& items, Shape shape,
                 const httplib::Headers& headers = {}) {
    return retried(headers, shape, [&] { return client_.Post(path, headers, items); });
  }

 private:
  json answer(const httplib::Result& r, Shape shape) {
    if (!r) throw ClientFailure{kCannotWrite, "cannot reach popcutd at " + server_ + ": " + why(r.error())};
    const std::string status = std::to_string(r->status);
    json j;
    try {
      j = parse_shallow(r->body, kCannotWrite, server_ + " answered");
    } catch (const json::exception&) {
      // Something answers there, but not popcutd (every popcutd answer is JSON): a wrong address.
      throw ClientFailure{kCannotWrite, server_ + " is not popcutd: it answered " + status +
                                            " with a body that is not JSON (is popcutd listening there?)"};
    }
    const std::string problem = r->status >= 400 ? error_shape_problem(j) : shape(j);
    if (!problem.empty()) {
      throw ClientFailure{kCannotWrite, server_ + " is not popcutd: it answered " + status + " " + excerpt(j) + " (" +
                                            problem + "; is popcutd listening there?)"};
    }
    if (r->status >= 400) {
      const json& e = j["error"];
      std::string msg =
          "popcutd refused (" + status + " " + e["code"].get<std::string>() + "): " + e["message"].get<std::string>();
      if (e.contains("field")) msg += " [" + e["field"].get<std::string>() + "]";
      const int code = r->status == 503 ? kCannotWrite : (r->status >= 500 ? kInternal : kBadInput);
      throw ClientFailure{code, msg};
    }
    return j;
  }

  // A request with an Idempotency-Key is sent again, with the same key, when the connection broke
  // after it went out: popcutd may have queued the job, and the key makes the retry find it.
  template <typename Send>
  json retried(const httplib::Headers& headers, Shape shape, Send send) {
    httplib::Result r = send();
    const bool keyed = headers.count("Idempotency-Key") > 0;
    for (int attempt = 0; keyed && attempt < 3 && !r && broken_after_sending(r.error()); ++attempt) {
      std::this_thread::sleep_for(std::chrono::milliseconds(500 << attempt));
      r = send();
    }
    return answer(r, shape);
  }
  static bool broken_after_sending(httplib::Error e) { return e == httplib::Error::Read || e == httplib::Error::Write; }

  // httplib names its errors in one word ("Connection"); say what it means for the user.
  static std::string why(httplib::Error e) {
    switch (e) {
      case httplib::Error::Connection: return "no connection (is popcutd running and listening at that address?)";
      case httplib::Error::ConnectionTimeout: return "the connection timed out (is the address reachable?)";
      case httplib::Error::Read: return "the connection closed before the answer was complete (did popcutd stop?)";
      case httplib::Error::Write: return "the connection closed while sending the request (did popcutd stop?)";
      default: return "the request failed (" + httplib::to_string(e) + ")";
    }
  }
  // The client library takes scheme://host[:port] only: a trailing slash, as a browser's address
  // bar gives it, is dropped; a path is refused rather than silently ignored.
  static std::string check(const std::string& server) {
    if (server.rfind("http://", 0) != 0 && server.rfind("https://", 0) != 0) {
      throw ClientFailure{kBadInput, "--server " + server + ": expected http://HOST:PORT"};
    }
    std::string base = server;  // scheme://host[:port]
    const std::size_t host = base.find("://") + 3;
    while (base.size() > host && base.back() == '/') base.pop_back();
    if (base.find('/', host) != std::string::npos || host == base.size()) {
      throw ClientFailure{kBadInput, "--server " + server + ": expected http://HOST:PORT (no path)"};
    }
    return base;
  }
  std::string server_;
  httplib::Client client_;
};

void print_job_line(const json& j) {
  std::cout << j["id"] << "  " << j["state"].get<std::string>() << "  " << j["name"].get<std::string>() << "  on "
            << (j["cut_on"].is_string() ? j["cut_on"].get<std::string>()
                                        : (j["device"].is_string() ? j["device"].get<std::string>()
                                                                   : "profile " + j["profile"].get<std::string>()))
            << "  strokes " << j["strokes_sent"] << "/" << j["strokes_total"];
  if (j["place_in_line"].is_number()) std::cout << "  place " << j["place_in_line"];
  // An interrupted job's two resume points; a resumed one's start.
  if (j["state"] == "interrupted" && j.contains("strokes_executed")) {
    std::cout << "  executed " << (j["strokes_executed"].is_number() ? j["strokes_executed"].dump() : "unknown");
  }
  // A cancel under way: waiting_for_device means another `popcut cancel` gives the wait up.
  if (j.contains("cancel") && j["cancel"].is_string()) std::cout << "  cancel " << j["cancel"].get<std::string>();
  if (j.contains("resume_point") && j["resume_point"].is_string()) {
    std::cout << "  resumed after stroke " << j["resume_from"] << " (" << j["resume_point"].get<std::string>() << ")";
  }
  if (j.contains("error"))
    std::cout << "  (" << j["error"]["code"].get<std::string>() << ": " << j["error"]["message"].get<std::string>()
              << ")";
  std::cout << "\n";
}

int run(const ClientCommands& s, const std::function<int(Connection&)>& body) {
  try {
    Connection c(!s.server.empty() ? s.server : env_or("POPCUT_SERVER", "http://127.0.0.1:8742"),
                 !s.token.empty() ? s.token : env_or("POPCUT_TOKEN", ""));
    return body(c);
  } catch (const ClientFailure& f) {
    std::cerr << "popcut: error: " << f.message << "\n";
    if (s.json_out) print_json_line({{"error", {{"message", f.message}, {"exit_code", f.exit_code}}}});
    return f.exit_code;
  }
}

// --since: unix seconds, or a span back from now ("90m", "12h", "7d").
std::optional<double> since_s(const std::string& text) {
  if (text.empty() || text.size() > 20 || !std::isdigit(static_cast<unsigned char>(text[0]))) return std::nullopt;
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const std::string unit = text.substr(used);
  const double scale = unit == "s" ? 1 : unit == "m" ? 60 : unit == "h" ? 3600 : unit == "d" ? 86400 : 0;
  if (unit.empty()) return v;
  if (scale == 0) return std::nullopt;
  const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  return std::max(0.0, now - v * scale);
}

bool is_mesh_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext == ".obj" || ext == ".stl" || ext == ".off" || ext == ".ply";
}

// A random (version 4) UUID: this invocation's Idempotency-Key.
std::string random_uuid() {
  std::random_device rd;
  std::array<unsigned char, 16> b{};
  for (unsigned char& x : b) x = static_cast<unsigned char>(rd() & 0xff);
  b[6] = static_cast<unsigned char>((b[6] & 0x0f) | 0x40);
  b[8] = static_cast<unsigned char>((b[8] & 0x3f) | 0x80);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (i == 4 || i == 6 || i == 8 || i == 10) out += '-';
    out += {hex[b[i] >> 4], hex[b[i] & 15]};
  }
  return out;
}

int submit(const ClientCommands& s, Connection& c) {
  if (s.device.empty() == s.profile.empty())
    throw ClientFailure{kBadInput, "name exactly one of --device NAME or --profile PROFILE"};
  const httplib::Headers key = {{"Idempotency-Key", s.idempotency_key.empty() ? random_uuid() : s.idempotency_key}};
  json job;
  if (is_mesh_path(s.model_path) && s.read_as.sheet())
    throw ClientFailure{kBadInput, "--as sheet reads drawings (.svg, .dxf, .fold), not a mesh: " + s.model_path};
  if (is_mesh_path(s.model_path)) {
    // The mesh goes as it is, with popcut import's options: popcutd imports it with the same code
    // and answers its errors (422 bad_model naming the option) like any other refusal.
    std::string bytes;
    try {
      bytes = read_text_file(s.model_path, kMaxMeshFileBytes);
    } catch (const Error& e) {
      throw ClientFailure{kBadInput, e.what()};
    }
    httplib::MultipartFormDataItems items{
        {"mesh", bytes, std::filesystem::path(s.model_path).filename().string(), "application/octet-stream"}};
    if (!s.device.empty()) items.push_back({"device", s.device, "", ""});
    if (!s.profile.empty()) items.push_back({"profile", s.profile, "", ""});
    if (!s.name.empty()) items.push_back({"name", s.name, "", ""});
    if (!s.material.empty()) items.push_back({"material", s.material, "", ""});
    if (s.copies != 1) items.push_back({"copies", std::to_string(s.copies), "", ""});
    for (const auto& [option, value] : s.import_values) items.push_back({option, value, "", ""});
    job = c.post_form("/api/v1/jobs", items, job_shape_problem, key);
  } else {
    if (!s.import_values.empty()) {
      throw ClientFailure{
          kBadInput, "--" + s.import_values.front().first +
                         " is an import option: it applies to a mesh (.obj, .stl, .off, .ply), not to " + s.model_path};
    }
    json model;
    try {
      check_read_as(s.read_as);
      if (s.read_as.sheet() && !is_drawing_path(s.model_path))
        throw Error(ErrorCode::invalid_input, s.model_path, "--as",
                    "--as sheet reads drawings (FILE.svg, FILE.dxf, FILE.fold); a model file is a card already");
      // A drawing, a webOAcard card or a design (popcut.design.v1) is read here, as every command
      // reads one, and goes as the model it makes: popcutd reads popcut's own model formats only.
      const bool drawn = is_drawing_path(s.model_path) || is_oa_path(s.model_path);
      std::string text = drawn ? std::string() : read_text_file(s.model_path);
      if (drawn || is_design_document(text)) text = drawing_job_model(s.model_path, s.read_as);
      model = parse_shallow(text, kBadInput, s.model_path);
    } catch (const json::exception& e) {
      throw ClientFailure{kBadInput, s.model_path + ": not JSON: " + e.what()};
    } catch (const Error& e) {
      throw ClientFailure{kBadInput, e.what()};
    }
    json body = {{"model", model}};
    if (!s.device.empty()) body["device"] = s.device;
    if (!s.profile.empty()) body["profile"] = s.profile;
    if (!s.name.empty()) body["name"] = s.name;
    if (!s.material.empty()) body["material"] = s.material;
    if (s.copies != 1) body["copies"] = s.copies;
    job = c.request("POST", "/api/v1/jobs", job_shape_problem, body.dump(), key);
  }
  // Only the submission's answer has them; a job fetched again while waiting does not.
  const json warnings = job.value("warnings", json::array());
  if (!s.json_out) {
    std::cerr << "queued job " << job["id"] << " (" << job["name"].get<std::string>() << "), place "
              << job["place_in_line"] << " in line\n";
    for (const json& w : warnings)
      std::cerr << "popcut: warning: " << s.model_path << ": " << w.get<std::string>() << "\n";
  }
  while (s.wait && (job["state"] == "queued" || job["state"] == "planning" || job["state"] == "ready" ||
                    job["state"] == "cutting")) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    job = c.request("GET", "/api/v1/jobs/" + std::to_string(job["id"].get<long long>()), job_shape_problem);
  }
  if (s.json_out) {
    job["warnings"] = warnings;
    print_json_line(job);
  } else {
    print_job_line(job);
  }
  return s.wait && job["state"] != "done" ? kCannotWrite : kOk;
}

// `popcut sheet NAME`'s answer: {"device": NAME, "sheet": STATE}.
std::string sheet_shape_problem(const json& a) {
  if (!a.is_object()) return "expected an object, got " + excerpt(a);
  if (!a.contains("device") || !a["device"].is_string()) return "\"device\" is missing or not a string";
  if (!a.contains("sheet") || !a["sheet"].is_string()) return "\"sheet\" is missing or not a string";
  return "";
}

// --server, --token and --json, on every client command.
void add_common_options(CLI::App* sub, ClientCommands& s) {
  sub->add_option("--server", s.server, "popcutd's address (default $POPCUT_SERVER or http://127.0.0.1:8742)");
  sub->add_option("--token", s.token, "Access token (default $POPCUT_TOKEN)");
  sub->add_flag("--json", s.json_out, "Print the daemon's answer as JSON");
}

void add_submit_command(CLI::App& app, ClientCommands& s) {
  const auto common = [&](CLI::App* sub) { add_common_options(sub, s); };
  s.submit = app.add_subcommand(
      "submit",
      "Queue a model on popcutd for a device (or any device with a profile).\n"
      "Exit 2 if refused, 3 if popcutd cannot be reached or its queue is full (or with --wait: the job did not\n"
      "finish), 4 if popcutd failed inside.");
  s.submit
      ->add_option("MODEL", s.model_path,
                   "Model file (popcut.voxel.v1 or popcut.faces.v1), a drawing (.svg, .dxf, .fold), or a mesh (.obj, "
                   ".stl, .off, .ply) that popcutd imports with the options below")
      ->required();
  add_read_as_options(s.submit, s.read_as, true);
  s.submit->add_option("--device", s.device, "The cutter's name in popcutd.toml");
  s.submit->add_option("--profile", s.profile, "Any device with this profile (e.g. sim)");
  s.submit
      ->add_option("--copies", s.copies,
                   "Cards to cut (1-1000): nested on the device's media, on as many sheets as they take")
      ->check(CLI::Range(1, 1000));
  s.submit->add_option("--material", s.material,
                       "Material (popcutd's configs/materials/NAME.toml, e.g. card-220) for the device's family");
  s.submit->add_option("--name", s.name, "A label for the job (default: the model's name, or the mesh's file name)")
      ->check(CLI::Validator(
          [](std::string& t) {
            return t.empty() ? std::string("must not be empty: leave --name out to name the job after its model")
                             : std::string();
          },
          "TEXT"));
  s.submit->add_flag("--wait", s.wait, "Wait until the job is done, failed, cancelled or interrupted");
  s.submit
      ->add_option("--idempotency-key", s.idempotency_key,
                   "Send this Idempotency-Key (default: a new UUID per run): a script that runs submit again with the\n"
                   "same key, within 24 h, gets the first job back instead of a second one")
      ->check(CLI::Validator(
          [](std::string& t) {
            const bool visible = std::all_of(t.begin(), t.end(), [](char ch) { return ch > ' ' && ch < 0x7f; });
            return !t.empty() && t.size() <= 255 && visible ? std::string()
                                                            : std::string("1 to 255 visible ASCII characters");
          },
          "KEY"));
  common(s.submit);
  add_import_options(s.submit, s.import_values);
}

}  // namespace

void add_client_commands(CLI::App& app, ClientCommands& s) {
  add_submit_command(app, s);
  const auto common = [&](CLI::App* sub) { add_common_options(sub, s); };
  // A command on one job: its id, then the common options.
  const auto one_job = [&](const char* name, const char* help) {
    CLI::App* sub = app.add_subcommand(name, help);
    sub->add_option("ID", s.job_id, "Job id")->required()->check(positive_whole("a job id"));
    common(sub);
    return sub;
  };
  s.jobs = app.add_subcommand("jobs", "List your jobs on popcutd (an admin token sees everyone's), newest first.");
  s.jobs->add_flag("--all", s.all, "Up to 10000 jobs instead of 100");
  s.jobs->add_option("--state", s.states, "Only jobs in these states (comma-separated, e.g. done,failed)");
  s.jobs->add_option("--device", s.filter_device, "Only jobs cut on (or waiting for) this device");
  s.jobs
      ->add_option("--since", s.since,
                   "Only jobs created or finished since: unix seconds, or a span back from now (90m, 12h, 7d)")
      ->check(CLI::Validator([](std::string& t) { return since_s(t) ? std::string() : "unix seconds or 90m, 12h, 7d"; },
                             "WHEN"));
  common(s.jobs);
  s.move = one_job("move",
                   "Move a waiting job in popcutd's queue (admin token): a priority (higher is cut first),\n"
                   "or the place just ahead of another waiting job (taking its priority).\n"
                   "Exit 2 if refused (not waiting, no such job, not the admin token).");
  s.move->add_option("--priority", s.priority, "-100 to 100; 0 is every job's default")->check(CLI::Range(-100, 100));
  s.move->add_option("--before", s.before_id, "The waiting job to go just ahead of")->check(positive_whole("a job id"));
  s.cancel = one_job("cancel",
                     "Cancel a job; a job being cut stops at a command boundary with the knife lifted.\n"
                     "If the cutter holds the line (the job shows 'cancel waiting_for_device'), cancelling again\n"
                     "gives up the wait: the abort is not sent and the cutter may cut all its buffer holds.");
  s.resume =
      one_job("resume",
              "Cut the rest of an interrupted job (a device error, SIGTERM or a crash stopped its cut).\n"
              "Exit 2 if refused (not interrupted; --from executed where the device's executed strokes are unknown).");
  s.resume
      ->add_option(
          "--from", s.resume_from,
          "received (default): continue after the strokes the device certainly received, for a device that kept\n"
          "its buffer; executed: after the strokes it is known to have executed, for a device that was reset or\n"
          "power-cycled (the strokes between may be cut twice)")
      ->check(CLI::IsMember({"received", "executed"}));
  s.sheet = app.add_subcommand(
      "sheet",
      "Say a fresh sheet is loaded on a device that waits for one (awaiting_sheet) after each job.\n"
      "Needs the admin token or that of the last job's owner. Exit 2 if refused (unknown device, another's\n"
      "job, or 409 while the device is cutting), 3 if popcutd cannot be reached.");
  s.sheet->add_option("NAME", s.sheet_device, "The device's name in popcutd.toml")
      ->required()
      ->check(CLI::Validator(
          [](std::string& t) {
            // As popcutd.toml allows them; nothing that would change the request's path.
            const bool ok = !t.empty() && t.size() <= 64 && t[0] != '.' &&
                            t.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_.") ==
                                std::string::npos;
            return ok ? std::string() : "\"" + t + "\" is not a device name (letters, digits, '-', '_', '.')";
          },
          "NAME"));
  common(s.sheet);
  s.pause =
      one_job("pause",
              "Pause a job: a job being cut stops after the stroke in flight, the cutter cuts what it already holds,\n"
              "the knife is lifted and the job waits as 'paused' with the sheet on the device (nothing else is cut\n"
              "there meanwhile). Unlike cancel, nothing is dropped: 'popcut continue' cuts the rest.\n"
              "Exit 2 if refused (the job is not ready or cutting).");
  s.continue_cmd =
      one_job("continue",
              "Continue a paused job: popcutd sends the cutter's set-up again and cuts from the stroke after the\n"
              "last one cut. Exit 2 if refused (the job is not paused).");
}

std::optional<int> run_client_commands(const ClientCommands& s) {
  if (s.submit && *s.submit) return run(s, [&](Connection& c) { return submit(s, c); });
  if (s.jobs && *s.jobs) {
    return run(s, [&](Connection& c) {
      httplib::Params query = {{"limit", s.all ? "10000" : "100"}};
      if (!s.states.empty()) query.emplace("state", s.states);
      if (!s.filter_device.empty()) query.emplace("device", s.filter_device);
      if (!s.since.empty()) query.emplace("since", std::to_string(static_cast<long long>(*since_s(s.since))));
      const json r = c.request("GET", httplib::append_query_params("/api/v1/jobs", query), job_list_shape_problem);
      if (s.json_out)
        print_json_line(r);
      else
        for (const json& j : r["jobs"]) print_job_line(j);
      return kOk;
    });
  }
  // Both act on one job and print it as the daemon answers.
  const auto job_action = [&](const std::string& action, const std::string& body) {
    return run(s, [&](Connection& c) {
      const json j =
          c.request("POST", "/api/v1/jobs/" + std::to_string(s.job_id) + "/" + action, job_shape_problem, body);
      if (s.json_out)
        print_json_line(j);
      else
        print_job_line(j);
      return kOk;
    });
  };
  if (s.cancel && *s.cancel) return job_action("cancel", "");
  if (s.move && *s.move) {
    return run(s, [&](Connection& c) {
      json body = json::object();
      if (*s.move->get_option("--priority")) body["priority"] = s.priority;
      if (*s.move->get_option("--before")) body["before"] = s.before_id;
      if (body.empty()) throw ClientFailure{kBadInput, "name --priority P, --before JOB or both"};
      const json j = c.request("PATCH", "/api/v1/jobs/" + std::to_string(s.job_id), job_shape_problem, body.dump());
      if (s.json_out)
        print_json_line(j);
      else
        print_job_line(j);
      return kOk;
    });
  }
  if (s.resume && *s.resume) return job_action("resume", json{{"from", s.resume_from}}.dump());
  if (s.sheet && *s.sheet) {
    return run(s, [&](Connection& c) {
      const json r = c.request("POST", "/api/v1/devices/" + s.sheet_device + "/sheet", sheet_shape_problem, "");
      if (s.json_out)
        print_json_line(r);
      else
        std::cout << r["device"].get<std::string>() << "  sheet " << r["sheet"].get<std::string>() << "\n";
      return kOk;
    });
  }
  if (s.pause && *s.pause) return job_action("pause", "");
  if (s.continue_cmd && *s.continue_cmd) return job_action("continue", "");
  return std::nullopt;
}

}  // namespace popcut::cli
