// Text options of a mesh import checked once for every front end, and the import pipeline they drive.
#include "popcut/mesh/import_request.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <functional>

#include "popcut/error.h"
#include "popcut/io/model_io.h"
#include "popcut/io/voxel_json.h"
#include "popcut/text.h"

namespace popcut {
namespace {

std::string mm_text(double v) { return format_significant(v, 6); }

// A number filling all of `text` but for spaces at either end, or nothing.
std::optional<double> number_in(std::string_view text) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// --fit-mm: a device's name (its flat sheet on the media), or W x H of the closed card.
CardFit parse_fit(const std::string& text, const std::vector<NamedMedia>& media,
                  const std::function<Error(const std::string&)>& bad) {
  for (const NamedMedia& m : media) {
    if (m.name == text)
      return {m.width_mm, m.height_mm, true,
              m.name + "'s media (" + mm_text(m.width_mm) + " x " + mm_text(m.height_mm) + " mm)"};
  }
  for (std::string_view sep : {"\xc3\x97", "x", "X"}) {  // ×, x, X
    const std::size_t at = text.find(sep);
    if (at == std::string::npos) continue;
    const std::optional<double> w = number_in(std::string_view(text).substr(0, at)),
                                h = number_in(std::string_view(text).substr(at + sep.size()));
    if (w && h) return {*w, *h, false, mm_text(*w) + " x " + mm_text(*h) + " mm"};
    break;
  }
  std::string names;
  for (const NamedMedia& m : media) names += (names.empty() ? "" : ", ") + m.name;
  throw bad("'" + text.substr(0, 40) + "' is neither WxH in mm (e.g. 148x105, or 148×105) nor a device" +
            (names.empty() ? std::string(" (none is configured)") : " (" + names + ")"));
}

}  // namespace

std::vector<std::string> media_warnings(const Rect& sheet, const std::vector<NamedMedia>& media) {
  const double w = sheet.max.x_mm - sheet.min.x_mm, h = sheet.max.v_mm - sheet.min.v_mm;
  std::vector<std::string> out;
  for (const NamedMedia& m : media) {
    if (w <= m.width_mm && h <= m.height_mm) continue;
    out.push_back("the sheet (" + mm_text(w) + " x " + mm_text(h) + " mm) does not fit " + m.name + " (at most " +
                  mm_text(m.width_mm) + " x " + mm_text(m.height_mm) + " mm): use --fit-mm " + m.name +
                  " or a smaller --height-mm");
  }
  return out;
}

ImportRequest parse_import_options(const std::vector<std::pair<std::string, std::string>>& values,
                                   const std::string& source, const std::vector<NamedMedia>& media) {
  ImportRequest r;
  ImportOptions& o = r.options;
  std::vector<std::string> seen;
  for (const auto& entry : values) {
    // Named references, not structured bindings: the lambdas below capture them, which clang 14 (lint) cannot parse.
    const std::string& name = entry.first;
    const std::string& text = entry.second;
    const std::string option = "--" + name;
    const auto bad = [&](const std::string& message) -> Error {
      return Error(ErrorCode::invalid_input, source, option, message);
    };
    if (std::find(kImportOptionNames.begin(), kImportOptionNames.end(), name) == kImportOptionNames.end()) {
      std::string known;
      for (std::string_view n : kImportOptionNames) known += (known.empty() ? "" : ", ") + std::string(n);
      throw bad("not an import option (expected one of " + known + ")");
    }
    if (std::find(seen.begin(), seen.end(), name) != seen.end()) throw bad("given twice");
    seen.push_back(name);
    const std::string shown = "'" + text.substr(0, 40) + "'";
    // The range itself is checked (and named) by import_mesh; here only that it is a number.
    const auto whole = [&](const std::string& range) {
      int value = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec == std::errc::result_out_of_range) throw bad(shown + " is out of range: expected " + range);
      if (ec != std::errc() || end != text.data() + text.size())
        throw bad(shown + " is not a whole number: expected " + range);
      return value;
    };
    const auto real = [&] {
      double value = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
      if (ec != std::errc() || end != text.data() + text.size()) throw bad(shown + " is not a number");
      return value;
    };
    const auto axis = [&] {
      if (auto a = parse_axis(text)) return *a;
      throw bad(shown + " is not an axis: use " + kAxisNames.list());
    };
    const auto flag = [&] {
      if (text == "true") return true;
      if (text == "false") return false;
      throw bad(shown + " is not a switch value: use true or false");
    };
    if (name == "up")
      o.up = axis();
    else if (name == "front")
      o.front = axis();
    else if (name == "resolution")
      o.resolution = whole("1 to " + std::to_string(kMaxImportResolution) + " voxels across");
    else if (name == "width-mm")
      o.width_mm = real();
    else if (name == "voxel-mm")
      o.voxel_mm = real();
    else if (name == "height-mm")
      o.height_mm = real();
    else if (name == "fit-mm")
      o.fit = parse_fit(text, media, bad);
    else if (name == "keep-depth")
      o.keep_depth = real();
    else if (name == "smooth")
      o.structuring_element = whole("an odd side, 1 to " + std::to_string(kMaxStructuringElement));
    else if (name == "no-windows")
      o.windows = !flag();
    else if (name == "thin-tops")
      o.thin_top_voxels = whole("0 (off) to " + std::to_string(kMaxVoxelAxis) + " voxels");
    else if (name == "faces")
      r.faces = flag();
    else if (const auto method = kDepthMethodNames.find(text))
      o.depth = *method;  // name == "depth-method"
    else
      throw bad(shown + " is not a method: use " + kDepthMethodNames.list());
  }
  return r;
}

MeshImport import_mesh_file(const std::string& path, const ImportRequest& request, const std::string& source,
                            std::int64_t max_triangles) {
  const auto t0 = std::chrono::steady_clock::now();
  TriangleSoup mesh;
  try {
    mesh = read_mesh(path);
  } catch (const Error& e) {
    if (path == source) throw;
    throw Error(e.code(), source, e.location(), e.message());
  }
  if (static_cast<std::int64_t>(mesh.triangles.size()) > max_triangles) {
    throw Error(ErrorCode::limit, source, "",
                std::to_string(mesh.triangles.size()) + " triangles; at most " + std::to_string(max_triangles) +
                    " are allowed here");
  }
  const double read_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  MeshImport m;
  m.voxels = import_mesh(mesh, request.options, source);
  m.voxels.timings.read_ms = read_ms;
  if (request.faces) m.faces.emplace(silhouette_faces(mesh, request.options, m.voxels, source));
  m.pattern = m.faces ? make_pattern(AnyModel(m.faces->model), source) : make_pattern(m.voxels.model, source);
  m.model_json = m.faces ? to_face_json(m.faces->model, request.options.name) : to_voxel_json(m.voxels.model);
  return m;
}

}  // namespace popcut
