// A mesh uploaded as multipart/form-data with popcut import's options, imported into a model.
#pragma once

#include <httplib.h>

#include <map>
#include <string>
#include <vector>

#include "api_context.h"
#include "popcut/mesh/import_request.h"

namespace popcut::daemon {

struct MeshUpload {
  MeshImport imported;
  std::string filename;
  std::map<std::string, std::string> fields;  // the non-option fields named in `fields`
};

// The form's 'mesh' file part imported with the import options among its parts; `fields` are
// the other parts the route takes ("name", "device" ...). Throws ApiFailure: a malformed form
// is bad_request, a fault in the mesh bad_model, either over a limit model_too_complex.
MeshUpload import_upload(ApiContext& api, const httplib::Request& req, const std::vector<std::string>& fields);

}  // namespace popcut::daemon
