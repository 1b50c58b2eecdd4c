// The designer's routes: drafts per token, items added, removed, undone and redone on a live session, each
// answered with the new pattern, its check and the faces for the 3D view; export and "send to cutter".
#include <chrono>
#include <sstream>

#include "../report_json.h"
#include "api_handlers.h"
#include "api_queue.h"
#include "popcut/error.h"
#include "popcut/io/design_json.h"
#include "popcut/io/model_io.h"
#include "popcut/io/pattern_io.h"
#include "validation.h"

namespace popcut::daemon {
namespace {

// Drafts a list shows at most; the page lists the newest.
constexpr int kDraftListLimit = 200;

json point_list(const std::vector<std::array<double, 2>>& points) {
  json out = json::array();
  for (const auto& [a, b] : points) out.push_back({a, b});
  return out;
}

json ring_json(const Ring& ring) {
  json out = json::array();
  for (const Point2& p : ring) out.push_back({p.x_mm, p.v_mm});
  return out;
}

json sheet_json(const Rect& s) {
  return {{"width", s.max.x_mm - s.min.x_mm}, {"back", s.max.v_mm}, {"floor", -s.min.v_mm}};
}

// The lines by kind as [x1, v1, x2, v2], and each face's outline and holes in pattern
// coordinates with its plane: the page folds them to any angle itself (to_card, then the
// parallel-fold motion), so one answer serves the angle slider.
json pattern_view(const Pattern& p) {
  json lines = {{"cut", json::array()}, {"mountain", json::array()}, {"valley", json::array()}};
  for (const Segment& s : p.lines)
    lines[kLineKindNames.name(s.kind)].push_back({s.a.x_mm, s.a.v_mm, s.b.x_mm, s.b.v_mm});
  json faces = json::array();
  for (const PatternFace& f : p.faces) {
    json holes = json::array();
    for (const Ring& h : f.holes) holes.push_back(ring_json(h));
    faces.push_back({{"kind", f.kind == FaceKind::vertical ? "vertical" : "horizontal"},
                     {"t", f.t_mm},
                     {"outer", ring_json(f.outer)},
                     {"holes", holes}});
  }
  return {{"sheet", {{"min", {p.sheet.min.x_mm, p.sheet.min.v_mm}}, {"max", {p.sheet.max.x_mm, p.sheet.max.v_mm}}}},
          {"lines", lines},
          {"faces", faces},
          {"back_face", p.back_face},
          {"floor_face", p.floor_face}};
}

json items_json(const FaceDesign& d) {
  json items = json::array();
  for (const FaceDesign::Placed& placed : d.items()) {
    const DesignItem& it = placed.item;
    json j = {{"id", placed.id},
              {"tool", kDesignToolNames.name(it.tool)},
              {"t", it.t_mm},
              {"outline", point_list(it.outline)},
              {"mirror", it.mirror}};
    if (it.tool == DesignTool::wall) j["top"] = it.top;
    items.push_back(std::move(j));
  }
  return items;
}

std::string source_of(const DesignSession& s) { return "design " + std::to_string(s.id); }

// The whole state an editor shows (docs/api.md "Designs").
json design_view(const DesignSession& s) {
  const FaceDesign& d = s.design;
  return rounded_numbers({{"id", s.id},
                          {"name", s.name},
                          {"sheet", sheet_json(d.model().sheet())},
                          {"items", items_json(d)},
                          {"can_undo", d.can_undo()},
                          {"can_redo", d.can_redo()},
                          {"pattern", pattern_view(d.pattern())},
                          {"check", validation_json(source_of(s), d.pattern(), d.report())}});
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
  json view = design_view(*s);
  api.designs().save(*s);
  view["answer_ms"] =
      std::round(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() * 1000) /
      1000;
  send_json(res, view);
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
  const std::string name = design_name(body);
  FaceDesign design = parse_design(req.body, "design");
  const std::shared_ptr<DesignSession> s = api.designs().create(caller.name, name, std::move(design));
  std::lock_guard lock(s->mutex);
  send_json(res, design_view(*s), 201);
}

void list_designs(ApiContext& api, const Caller& caller, const Req&, Res& res) {
  json list = json::array();
  for (const DesignDraft& d : api.daemon().store().list_designs(caller.admin() ? "" : caller.name, kDraftListLimit))
    list.push_back(draft_json(d));
  send_json(res, {{"designs", list}});
}

void get_design(ApiContext& api, const Caller& caller, const Req& req, Res& res) {
  const std::shared_ptr<DesignSession> s = visible_design(api, caller, req);
  std::lock_guard lock(s->mutex);
  send_json(res, design_view(*s));
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
  res.set_content(to_design_json(s->design, s->name), "application/json");
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
