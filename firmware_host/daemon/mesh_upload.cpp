// Uploaded meshes: the form's parts checked, the mesh written to a temporary file and imported.
#include "mesh_upload.h"

#include <algorithm>
#include <filesystem>

#include "popcut/error.h"
#include "popcut/io/files.h"

namespace popcut::daemon {
namespace {

namespace fs = std::filesystem;

// A file written for the length of one request (an uploaded mesh: the importer reads files).
struct TempFile {
  fs::path path;
  ~TempFile() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};

// The form's parts sorted out: the mesh, the route's own fields, import options; anything else refused.
const httplib::MultipartFormData& sort_parts(const httplib::Request& req, const std::vector<std::string>& fields,
                                             MeshUpload& u, std::vector<std::pair<std::string, std::string>>& options) {
  const httplib::MultipartFormData* mesh = nullptr;
  for (const auto& file : req.files) {
    const std::string& key = file.first;  // a lambda below captures it: clang 14 (lint) cannot parse that for a binding
    const httplib::MultipartFormData& part = file.second;
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
  if (mesh->filename.empty())
    fail(ApiError::bad_request, "'mesh' must be a file part, not a value (curl: -F mesh=@FILE)", "mesh");
  return *mesh;
}

}  // namespace

MeshUpload import_upload(ApiContext& api, const httplib::Request& req, const std::vector<std::string>& fields) {
  MeshUpload u;
  std::vector<std::pair<std::string, std::string>> options;
  const httplib::MultipartFormData& mesh = sort_parts(req, fields, u, options);
  u.filename = mesh.filename;
  // Only its extension (the format) and stem (the job's default name) are used, never as a path:
  // a job name's rules (any script, no '/', '\\', '..', control characters).
  if (!is_job_label(u.filename)) {
    fail(ApiError::bad_name,
         "mesh file names are 1 to 64 characters of text in any script, without control characters, '/', '\\', '..', a "
         "leading '.' or a space at either end",
         "mesh");
  }
  const DaemonConfig& config = api.daemon().config();
  try {
    ImportRequest request = parse_import_options(options, u.filename, api.media());
    request.options.max_cells = config.limits.model_cells;
    request.options.name = u.fields.count("name") ? u.fields["name"] : fs::path(u.filename).stem().string();
    // The importer reads files and picks the format by the extension: the upload's own.
    TempFile tmp{fs::path(config.data_dir) / "tmp" /
                 ("upload-" + std::to_string(api.next_upload()) + fs::path(u.filename).extension().string())};
    fs::create_directories(tmp.path.parent_path());
    write_text_file(tmp.path.string(), [&](std::ostream& o) { o << mesh.content; });
    // A large mesh costs seconds of CGAL work: it takes a preview slot, so imports and renders
    // together never run more at once than the slots allow (503 busy beyond).
    api.in_render_slot(
        [&] { u.imported = import_mesh_file(tmp.path.string(), request, u.filename, config.limits.mesh_triangles); });
  } catch (const Error& e) {
    if (e.code() == ErrorCode::io || e.code() == ErrorCode::internal) throw;
    // The importer's own message; the field is the option at fault, as named in the form: a bad
    // value of a field is a bad request (400), a fault inside the mesh a bad model (422, field
    // "mesh", the message naming the place: "line 3", "face 1"), either over a limit 413.
    const bool option = e.location().rfind("--", 0) == 0;
    const std::string field = option ? e.location().substr(2) : "mesh";
    fail(e.code() == ErrorCode::limit ? ApiError::model_too_complex
         : option                     ? ApiError::bad_request
                                      : ApiError::bad_model,
         e.what(), field);
  }
  return u;
}

}  // namespace popcut::daemon
