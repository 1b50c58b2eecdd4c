// The HTTP API's route table, and what every request passes through before and around its handler:
// refusals from the request line and headers, the token check, body reading, JSON error answers.
#include "http_api.h"

#include "api_handlers.h"
#include "http_framing.h"
#include "log.h"
#include "popcut/error.h"
#include "route_table.h"

namespace popcut::daemon {

// Every route popcutd answers (docs/api.md). A path or method not here is 404 or 405 with Allow,
// a query parameter a route does not take is 400, and a route's token is checked before its
// handler runs: all of that follows from this table (route_table.cpp).
std::vector<Route> api_routes() {
  return {
      {Method::get, "/healthz", Access::none, any_query(), get_health},
      {Method::get, "/metrics", Access::none, any_query(), get_metrics},
      {Method::get, "/", Access::none, any_query(), get_kiosk_page},
      {Method::get, "/kiosk/app.js", Access::none, any_query(), get_kiosk_script},
      {Method::get, "/kiosk/app.css", Access::none, any_query(), get_kiosk_style},
      {Method::get, "/operator", Access::none, any_query(), get_operator_page},
      {Method::get, "/operator/app.js", Access::none, any_query(), get_operator_script},
      {Method::get, "/operator/app.css", Access::none, any_query(), get_operator_style},
      {Method::get, "/design", Access::none, any_query(), get_design_page},
      {Method::get, "/design/app.js", Access::none, any_query(), get_design_script},
      {Method::get, "/design/app.css", Access::none, any_query(), get_design_style},
      {Method::get, "/design/view3d.js", Access::none, any_query(), get_design_view_script},
      {Method::get, "/design/files.js", Access::none, any_query(), get_design_files_script},
      {Method::get, "/design/three.min.js", Access::none, any_query(), get_three_script},
      {Method::get, "/design/OrbitControls.js", Access::none, any_query(), get_orbit_controls},
      {Method::get, "/api/v1/stats", Access::admin, takes({"days"}), get_stats, "reading the statistics"},
      {Method::get, "/api/v1/examples", Access::token, takes_none(), list_examples},
      {Method::get, R"(/api/v1/examples/([^/]+))", Access::token, takes_none(), get_example},
      {Method::get, "/api/v1/devices", Access::token, takes_none(), list_devices},
      {Method::get, "/api/v1/materials", Access::token, takes_none(), list_materials},
      {Method::post, R"(/api/v1/devices/([^/]+)/pause)", Access::admin, takes_none(), pause_device, "pausing a device"},
      {Method::post, R"(/api/v1/devices/([^/]+)/resume)", Access::admin, takes_none(), resume_device,
       "resuming a device"},
      {Method::post, R"(/api/v1/devices/([^/]+)/blade)", Access::admin, takes_none(), reset_blade,
       "resetting a device's blade counters"},
      {Method::post, R"(/api/v1/devices/([^/]+)/sheet)", Access::token, takes_none(), confirm_sheet},
      {Method::post, "/api/v1/jobs", Access::token, takes_none(), submit_job},
      {Method::get, "/api/v1/jobs", Access::token, takes({"limit", "state", "device", "since"}), list_jobs},
      {Method::get, R"(/api/v1/jobs/(\d+))", Access::token, takes_none(), get_job},
      {Method::patch, R"(/api/v1/jobs/(\d+))", Access::admin, takes_none(), patch_job, "moving a job in the queue"},
      {Method::get, R"(/api/v1/jobs/(\d+)/pattern\.svg)", Access::token, takes_none(), get_job_pattern},
      {Method::get, R"(/api/v1/jobs/(\d+)/preview\.png)", Access::token, takes({"angle"}), get_job_preview},
      {Method::post, R"(/api/v1/jobs/(\d+)/cancel)", Access::token, takes_none(), cancel_job},
      {Method::post, R"(/api/v1/jobs/(\d+)/resume)", Access::token, takes_none(), resume_job},
      {Method::post, R"(/api/v1/jobs/(\d+)/pause)", Access::token, takes_none(), pause_job},
      {Method::post, R"(/api/v1/jobs/(\d+)/continue)", Access::token, takes_none(), continue_job},
      {Method::post, "/api/v1/render/pattern.svg", Access::token, takes_none(), render_pattern},
      {Method::post, "/api/v1/render/preview.png", Access::token, takes({"angle"}), render_preview},
      {Method::post, "/api/v1/import", Access::token, takes_none(), import_model},
      {Method::post, "/api/v1/import/drawing", Access::token, takes_none(), import_drawing},
      {Method::post, "/api/v1/designs", Access::token, takes_none(), create_design},
      {Method::get, "/api/v1/designs", Access::token, takes_none(), list_designs},
      {Method::get, "/api/v1/fonts", Access::token, takes_none(), list_fonts},
      {Method::get, R"(/api/v1/designs/(\d+))", Access::token, takes_none(), get_design},
      {Method::patch, R"(/api/v1/designs/(\d+))", Access::token, takes_none(), rename_design},
      {Method::del, R"(/api/v1/designs/(\d+))", Access::token, takes_none(), delete_design},
      {Method::post, R"(/api/v1/designs/(\d+)/items)", Access::token, takes_none(), add_design_item},
      {Method::post, R"(/api/v1/designs/(\d+)/items/(\d+)/remove)", Access::token, takes_none(), remove_design_item},
      {Method::post, R"(/api/v1/designs/(\d+)/undo)", Access::token, takes_none(), undo_design},
      {Method::post, R"(/api/v1/designs/(\d+)/redo)", Access::token, takes_none(), redo_design},
      {Method::get, R"(/api/v1/designs/(\d+)/design\.json)", Access::token, takes_none(), get_design_file},
      {Method::get, R"(/api/v1/designs/(\d+)/pattern\.(svg|dxf|pdf))", Access::token, takes_none(), get_design_pattern},
      {Method::post, R"(/api/v1/designs/(\d+)/submit)", Access::token, takes_none(), submit_design},
  };
}

namespace {

std::string too_large_message(std::size_t limit) {
  return "the body exceeds " + std::to_string(limit) + " bytes ([limits] upload_bytes)";
}

}  // namespace

HttpApi::HttpApi(httplib::Server& server, Daemon& daemon)
    : server_(server), api_(std::make_unique<ApiContext>(daemon)), routes_(std::make_unique<RouteTable>(api_routes())) {
  install_checks();
  install_routes();
}

HttpApi::~HttpApi() = default;

void HttpApi::install_checks() {
  server_.set_payload_max_length(api_->daemon().config().limits.upload_bytes);
  // Checked from the request line and headers alone, before a byte of the body is read; with
  // "Expect: 100-continue" before the client is told to send it.
  server_.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    return refuse_before_body(req, res) ? httplib::Server::HandlerResponse::Handled
                                        : httplib::Server::HandlerResponse::Unhandled;
  });
  server_.set_expect_100_continue_handler([this](const httplib::Request& req, httplib::Response& res) {
    return refuse_before_body(req, res) ? res.status : 100;
  });
  server_.set_error_handler([this](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler already answered
    RequestCounters& counters = api_->counters();
    if (res.status == 413) {
      ++counters.errors_4xx;
      send_error(res, ApiError::too_large, too_large_message(api_->daemon().config().limits.upload_bytes));
    } else if (res.status == 404) {
      ++counters.errors_4xx;
      send_error(res, ApiError::not_found, "no such resource: " + req.path);
    } else if (res.status >= 400 && res.status < 500) {
      ++counters.errors_4xx;
      send_error(res, ApiError::bad_request, "malformed request");
      res.status = 400;
    }
  });
}

void HttpApi::install_routes() {
  for (const Route& route : routes_->routes()) {
    if (route.method == Method::get) {
      server_.Get(route.pattern, guarded(route));
      continue;
    }
    if (route.method == Method::del) {
      server_.Delete(route.pattern, guarded(route));
      continue;
    }
    auto with_body = [this, handler = guarded(route)](const httplib::Request& req, httplib::Response& res,
                                                      const httplib::ContentReader& content) {
      // httplib hands a content-reading handler its (non-const) request as const; the body goes
      // where httplib's own reader puts it, so handlers read req.body and req.files as ever.
      if (read_body(const_cast<httplib::Request&>(req), content, res)) handler(req, res);
    };
    if (route.method == Method::post) {
      server_.Post(route.pattern, with_body);
    } else {
      server_.Patch(route.pattern, with_body);
    }
  }
}

// API failures and popcut errors become their documented answers; the daemon keeps serving
// whatever a request holds.
httplib::Server::Handler HttpApi::guarded(const Route& route) {
  return [this, &route](const httplib::Request& req, httplib::Response& res) {
    RequestCounters& counters = api_->counters();
    ++counters.requests;
    try {
      const Caller caller = route.access == Access::none ? Caller() : api_->auth(req);
      if (route.access == Access::admin && !caller.admin())
        fail(ApiError::forbidden, std::string(route.admin_action) + " needs the admin token");
      route.handler(*api_, caller, req, res);
    } catch (const ApiFailure& f) {
      send_error(res, f.code, f.message, f.field);
    } catch (const Error& e) {
      const ApiError code = e.code() == ErrorCode::limit           ? ApiError::model_too_complex
                            : e.code() == ErrorCode::invalid_input ? ApiError::bad_model
                                                                   : ApiError::internal;
      // "model: model: ..." when the field is the whole submitted model: say it once.
      send_error(res, code, e.source() == e.location() ? e.source() + ": " + e.message() : std::string(e.what()),
                 e.location());
    } catch (const std::exception& e) {
      log_line("internal error on ", req.method, " ", req.path, ": ", e.what());
      send_error(res, ApiError::internal, e.what());
    }
    if (res.status >= 500)
      ++counters.errors_5xx;
    else if (res.status >= 400)
      ++counters.errors_4xx;
  };
}

void HttpApi::refuse(httplib::Response& res, ApiError code, const std::string& message, bool body_unread) {
  ++api_->counters().requests;
  ++api_->counters().errors_4xx;
  send_error(res, code, message);
  if (body_unread) res.set_header("Connection", "close");
}

bool HttpApi::refuse_before_body(const httplib::Request& req, httplib::Response& res) {
  if (const std::optional<RouteRefusal> r = routes_->refusal(req.method, req.path, req.params)) {
    if (!r->allow.empty()) res.set_header("Allow", r->allow);
    refuse(res, r->code, r->message, declares_body(req));
    return true;
  }
  const BodyFraming framing = read_framing(req);
  if (framing.refusal) {
    refuse(res, *framing.refusal, framing.message);
    return true;
  }
  if (req.method != "POST" && req.method != "PATCH") return false;
  try {
    api_->auth(req);
  } catch (const ApiFailure& f) {
    refuse(res, f.code, f.message);
    return true;
  }
  const std::size_t limit = api_->daemon().config().limits.upload_bytes;
  if (framing.length && *framing.length > limit) {
    refuse(res, ApiError::too_large, too_large_message(limit));
    return true;
  }
  return false;
}

bool HttpApi::read_body(httplib::Request& req, const httplib::ContentReader& content, httplib::Response& res) {
  const std::size_t limit = api_->daemon().config().limits.upload_bytes;
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
    refuse(res, ApiError::too_large, too_large_message(limit));
  } else {
    refuse(res, ApiError::bad_request,
           "the body could not be read (malformed chunked or multipart encoding, an unknown "
           "Content-Encoding, or the client stopped sending)");
  }
  return false;
}

}  // namespace popcut::daemon
