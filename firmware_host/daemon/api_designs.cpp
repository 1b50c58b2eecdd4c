// The designer's routes: drafts per token, items added, removed, undone and redone on a live session, each
// answered with the new pattern, its check and the faces for the 3D view; export and "send to cutter".
#include <chrono>
#include <sstream>

#include "../report_json.h"
#include "api_handlers.h"
#include "api_queue.h"
#include "popcut/error.h"
#include "popcut/design/oa_design.h"
#include "popcut/io/design_json.h"
#include "popcut/io/model_io.h"
#include "popcut/io/oa_model.h"
#include "popcut/io/pattern_io.h"
#include "validation.h"

namespace popcut::daemon {
namespace {

// Drafts a list shows at most; the page lists the newest.
constexpr int kDraftListLimit = 200;

std::string source_of(const DesignSession& s) { return "design " + std::to_string(s.id); }

// The whole state an editor shows (docs/api.md "Designs"): the check and the undo state, then
// the design as its file (popcut.design.v1, the document just saved) and the pattern
// (popcut.pattern.v1) spliced in as written, so neither is built twice or in a second shape.
void send_design(Res& res, const DesignSession& s, json head, int status = 200) {
  head["id"] = s.id;
  head["can_undo"] = s.design.can_undo();
  head["can_redo"] = s.design.can_redo();
  head["check"] = validation_json(source_of(s), s.design.pattern(), s.design.report());
  std::string out = rounded_numbers(std::move(head)).dump(-1, ' ', false, json::error_handler_t::replace);
  out.pop_back();  // the closing brace: the two documents go inside
  out += ",\"design\":" + s.document + ",\"pattern\":" + to_pattern_json(s.design.pattern()) + "}";
  res.status = status;
  res.set_content(out, "application/json");
}

json draft_json(const DesignDraft& d) {
  return rounded_numbers({{"id", d.id},
                          {"name", d.name},
                          {"owner", d.owner},
                          {"items", d.items},
                          {"created_at", d.created_s},
                          {"updated_at", d.updated_s}});
}

std::int64_t design_id(const Req& req) {
  const std::string digits = req.matches[1];
  if (digits.size() > 15) fail(ApiError::not_found, "no design " + digits);
  return std::stoll(digits);
}

// The path's design, if the caller may see it; another token's drafts are "not found".
std::shared_ptr<DesignSession> visible_design(ApiContext& api, const Caller& caller, const Req& req) {
  const std::int64_t id = design_id(req);
  std::shared_ptr<DesignSession> s = api.designs().open(id, caller.admin() ? "" : caller.name);
  if (!s) fail(ApiError::not_found, "no design " + std::to_string(id));
  return s;
}

// Runs one edit under the session's lock, saves the draft and answers the new state with the
// time from the edit to the answer (answer_ms). A refused edit throws before anything changed.
void edit_design(ApiContext& api, const Caller& caller, const Req& req, Res& res,
                 const std::function<void(DesignSession&)>& edit) {
  const std::shared_ptr<DesignSession> s = visible_design(api, caller, req);
  std::lock_guard lock(s->mutex);
  const auto t0 = std::chrono::steady_clock::now();
  edit(*s);
  api.designs().save(*s);
  s->design.report();  // worked out before the clock stops: answer_ms covers the edit and its check
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  send_design(res, *s, {{"answer_ms", ms}});
}

std::string design_name(const json& body) {
  if (!body.contains("name")) return "";
  if (!body["name"].is_string() || !is_job_label(body["name"].get<std::string>()))
    fail(ApiError::bad_request, "'name' must be 1 to 64 characters of text, without control characters", "name");
  return body["name"].get<std::string>();
}

}  // namespace

void create_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const json body = parse_body(req);
  if (!body.is_object()) fail(ApiError::bad_request, "the body must be a popcut.design.v1 object");
  // A webOAcard card starts a draft of its faces (docs/designer.md, "Importing a webOAcard card").
  const bool oa = is_oa_document(req.body);
  const std::string name = oa ? "" : design_name(body);
  FaceDesign design = oa ? design_from_oa(parse_oa_card(req.body, "card"), "card") : parse_design(req.body, "design");
  const std::shared_ptr<DesignSession> s = api.designs().create(caller.name, name, std::move(design));
  std::lock_guard lock(s->mutex);
  send_design(res, *s, json::object(), 201);
}

void list_designs(ApiContext& api, const Caller& caller, const Req&, Res& res) {
  json list = json::array();
  for (const DesignDraft& d : api.daemon().store().list_designs(caller.admin() ? "" : caller.name, kDraftListLimit))
    list.push_back(draft_json(d));
  send_json(res, {{"designs", list}});
}

void list_fonts(ApiContext&, const Caller&, const Req&, Res& res) {
  // What a text item may name: the machine's own fonts, which set its letters.
  send_json(res, {{"fonts", installed_font_families()}, {"default", TextSpec{}.font}});
}

void get_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::shared_ptr<DesignSession> s = visible_design(api, caller, req);
  std::lock_guard lock(s->mutex);
  send_design(res, *s, json::object());
}

void delete_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::shared_ptr<DesignSession> s = visible_design(api, caller, req);
  std::lock_guard lock(s->mutex);
  api.designs().remove(s->id);
  send_json(res, {{"id", s->id}, {"deleted", true}});
}

void add_design_item(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  parse_body(req);  // malformed JSON is a bad request (400), a bad item a bad model (422)
  const DesignItem item = parse_design_item(req.body, "item");
  edit_design(api, caller, req, res, [&](DesignSession& s) {
    try {
      s.design.add(item, "item");
    } catch (const Error& e) {
      // The design's reason, said of the item's field ("item.outline: leaves the sheet"); the
      // face model's own source name means nothing to the person drawing.
      if (e.code() != ErrorCode::invalid_input) throw;
      fail(ApiError::bad_model, (e.location().empty() ? "item" : e.location()) + ": " + e.message(), e.location());
    }
  });
}

void remove_design_item(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::string digits = req.matches[2];
  const std::uint64_t item = digits.size() > 15 ? 0 : std::stoull(digits);
  edit_design(api, caller, req, res, [&](DesignSession& s) {
    if (!s.design.remove(item)) fail(ApiError::not_found, "no item " + digits + " in " + source_of(s));
  });
}

void undo_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  edit_design(api, caller, req, res, [](DesignSession& s) {
    if (!s.design.undo()) fail(ApiError::conflict, "nothing to undo in " + source_of(s));
  });
}

void redo_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  edit_design(api, caller, req, res, [](DesignSession& s) {
    if (!s.design.redo()) fail(ApiError::conflict, "nothing to redo in " + source_of(s));
  });
}

void rename_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const json body = parse_body(req);
  if (!body.is_object() || body.size() != 1 || !body.contains("name"))
    fail(ApiError::bad_request, "the body must be {\"name\": \"...\"}");
  const std::string name = design_name(body);
  edit_design(api, caller, req, res, [&](DesignSession& s) { s.name = name; });
}

void get_design_file(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::shared_ptr<DesignSession> s = visible_design(api, caller, req);
  std::lock_guard lock(s->mutex);
  res.set_header("Content-Disposition", "attachment; filename=\"design-" + std::to_string(s->id) + ".json\"");
  res.set_content(s->document, "application/json");
}

void get_design_pattern(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::shared_ptr<DesignSession> s = visible_design(api, caller, req);
  const std::string kind = req.matches[2];
  std::lock_guard lock(s->mutex);
  std::ostringstream o;
  const std::string file = "design-" + std::to_string(s->id) + "." + kind;
  if (kind == "svg") {
    write_pattern_svg(o, s->design.pattern(), SvgOptions{.shade_faces = true});  // as a job's pattern.svg
    res.set_content(o.str(), "image/svg+xml");
  } else if (kind == "pdf") {
    write_pattern_pdf(o, s->design.pattern());
    res.set_content(o.str(), "application/pdf");
  } else {
    write_pattern_dxf(o, s->design.pattern());
    res.set_content(o.str(), "image/vnd.dxf");
  }
  res.set_header("Content-Disposition", "attachment; filename=\"" + file + "\"");
}

// "Send to cutter": the job's fields as POST /api/v1/jobs takes them, with the design's face
// model (as of now) for `model`.
void submit_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::shared_ptr<DesignSession> s = visible_design(api, caller, req);
  json body = req.body.empty() ? json::object() : parse_body(req);
  if (!body.is_object()) fail(ApiError::bad_request, "the body must be a JSON object such as {\"device\": \"sim\"}");
  if (body.contains("model")) fail(ApiError::bad_request, "the design is the model: leave out 'model'", "model");
  {
    std::lock_guard lock(s->mutex);
    body["model"] = json::parse(to_face_json(s->design.model(), s->name));
  }
  submit_json_job(api, caller, req, body, res);
}

}  // namespace popcut::daemon
