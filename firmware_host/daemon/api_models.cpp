// Model routes: the example models, pictures of a model before it is queued (the kiosk's pattern
// and preview with its slider), and a mesh turned into a model for the kiosk to show and queue.
#include <algorithm>
#include <filesystem>

#include "api_handlers.h"
#include "mesh_upload.h"
#include "model_limits.h"
#include "popcut/io/files.h"
#include "popcut/io/pattern_io.h"

namespace popcut::daemon {
namespace {

namespace fs = std::filesystem;

// Every example model, by id ("voxel-house"), sorted.
std::vector<std::pair<std::string, fs::path>> examples(const ApiContext& api) {
  std::vector<std::pair<std::string, fs::path>> out;
  for (const char* sub : {"voxel", "faces"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(api.daemon().config().examples_dir) / sub, ec)) {
      if (e.path().extension() == ".json")
        out.emplace_back(std::string(sub) + "-" + e.path().stem().string(), e.path());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

// What an example is called where people pick it: its model's own name (a face model may call
// it title; a long one shortened as a job's name is), else its id; a name no job could carry (a
// path, control characters) is not shown.
std::string example_name(const std::string& id, const fs::path& path) {
  try {
    const json model = json::parse(read_text_file(path.string()));
    for (const char* key : {"name", "title"}) {
      const json& v = model.value(key, json());
      if (const std::string label = v.is_string() ? job_label_from(v.get<std::string>()) : ""; !label.empty())
        return label;
    }
  } catch (const std::exception&) {
    // An unreadable example still gets listed by its id; fetching it names the fault.
  }
  return id;
}

}  // namespace

void list_examples(ApiContext& api, const Caller&, const Req&, Res& res) {
  json list = json::array(), names = json::object();
  for (const auto& [id, path] : examples(api)) {
    list.push_back(id);
    names[id] = example_name(id, path);
  }
  send_json(res, {{"examples", list}, {"names", names}});
}

void get_example(ApiContext& api, const Caller&, const Req& req, Res& res) {
  const std::string want = req.matches[1];
  for (const auto& [name, path] : examples(api)) {
    if (name == want) return res.set_content(read_text_file(path.string()), "application/json");
  }
  fail(ApiError::not_found, "no example named " + want);
}

void render_pattern(ApiContext& api, const Caller&, const Req& req, Res& res) {
  parse_body(req);  // not JSON at all: bad_json, as for a submission
  const Pattern p = checked_pattern(req.body, "model", api.daemon().config().limits);
  res.set_content(to_pattern_svg(p, {true}), "image/svg+xml");
}

void render_preview(ApiContext& api, const Caller&, const Req& req, Res& res) {
  const int angle = angle_param(req);
  parse_body(req);
  res.set_content(api.preview("model " + std::to_string(angle) + " " + req.body, angle,
                              [&] { return checked_pattern(req.body, "model", api.daemon().config().limits); }),
                  "image/png");
}

void import_model(ApiContext& api, const Caller&, const Req& req, Res& res) {
  if (!req.is_multipart_form_data())
    fail(ApiError::bad_request, "send the mesh as multipart/form-data (curl: -F mesh=@FILE)", "mesh");
  const MeshUpload u = import_upload(api, req, {"name"});
  checked_model(u.imported.model_json, u.filename, api.daemon().config().limits);
  const ImportResult& r = u.imported.voxels;
  const Rect& sheet = u.imported.pattern.sheet;
  const double width_mm = sheet.max.x_mm - sheet.min.x_mm;
  send_json(
      res,
      {{"model", json::parse(u.imported.model_json)},
       {"sheet_mm", {{"width", width_mm}, {"height", sheet.max.v_mm - sheet.min.v_mm}}},
       {"closed_mm", {{"width", width_mm}, {"height", std::max(sheet.max.v_mm, -sheet.min.v_mm)}}},
       {"warnings", media_warnings(sheet, api.media())},
       {"format", u.imported.faces ? kFacesFormat : "popcut.voxel.v1"},
       {"triangles", r.stats.triangles},
       {"grid",
        {{"width", r.grid.width}, {"depth", r.grid.depth}, {"height", r.grid.height}, {"voxel_mm", r.grid.voxel_mm}}},
       {"cells_filled", r.stats.cells_filled},
       {"windows_added", r.stats.windows_added},
       {"tops_dropped", r.stats.tops_dropped}});
}

}  // namespace popcut::daemon
