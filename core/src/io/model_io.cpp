// popcut.faces.v1 reader and writer, and dispatch between model formats by their tag.
#include "popcut/io/model_io.h"

#include <sstream>

#include "io/json_util.h"
#include "io/readers.h"
#include "popcut/error.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/files.h"
#include "popcut/io/oa_model.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
using json_util::index_path;
using json_util::json;
using json_util::number_text;

namespace {

void put_ring(std::ostringstream& o, const Ring& ring) {
  o << "[";
  for (std::size_t i = 0; i < ring.size(); ++i) {
    o << (i ? ", " : "") << "[" << number_text(ring[i].x_mm) << ", " << number_text(ring[i].v_mm) << "]";
  }
  o << "]";
}

}  // namespace

CardSheet read_card_sheet(const json_util::Reader& in, const json& root) {
  const json& sheet = in.require(root, "sheet", "");
  in.require_object(sheet, "sheet");
  in.only_keys(sheet, {"width", "back", "floor"}, "sheet");
  const auto size = [&](const char* key) {
    return in.number(in.require(sheet, key, "sheet"), std::string("sheet.") + key, 1e-3, kMaxFaceCoordinateMm);
  };
  return {size("width"), size("back"), size("floor")};
}

std::string card_sheet_json(const Rect& s) {
  return "{\"width\": " + number_text(s.max.x_mm - s.min.x_mm) + ", \"back\": " + number_text(s.max.v_mm) +
         ", \"floor\": " + number_text(-s.min.v_mm) + "}";
}

FaceModel face_model_from_json(const json& root, const std::string& source) {
  const json_util::Reader in(source);
  in.require_document(root, kFacesFormat, {"format", "name", "sheet", "edits", "faces"});
  const auto [width, back, floor] = read_card_sheet(in, root);
  if (root.contains("name")) in.string(root["name"], "name", 256);
  const bool has_edits = root.contains("edits"), has_faces = root.contains("faces");
  if (has_edits == has_faces) in.fail("edits", "give exactly one of \"edits\" (replayed in order) or \"faces\"");

  if (has_faces) {
    const json& faces = root["faces"];
    in.require_array(faces, "faces");
    if (faces.size() > kMaxFaces) in.fail("faces", "has more than " + std::to_string(kMaxFaces) + " faces");
    std::vector<OAFace> out;
    for (std::size_t i = 0; i < faces.size(); ++i) {
      PatternFace f = read_face(in, faces[i], index_path("faces", i), kMaxFaceCoordinateMm);
      out.push_back({f.kind, f.t_mm, {std::move(f.outer), std::move(f.holes)}, f.opening_paper});
    }
    return FaceModel::from_faces(width, back, floor, out, source);
  }

  const json& edits = root["edits"];
  in.require_array(edits, "edits");
  if (edits.size() > kMaxEdits) in.fail("edits", "has more than " + std::to_string(kMaxEdits) + " edits");
  FaceModel model(width, back, floor);
  for (std::size_t i = 0; i < edits.size(); ++i) {
    const std::string path = index_path("edits", i);
    const json& e = edits[i];
    in.require_object(e, path);
    in.only_keys(e, {"op", "t", "outline", "holes", "drop"}, path);
    FaceEdit edit;
    edit.op = in.named(kEditOpNames, in.require(e, "op", path), path + ".op");
    edit.t_mm = in.number(in.require(e, "t", path), path + ".t", 0, kMaxFaceCoordinateMm);
    edit.outline =
        in.points(in.require(e, "outline", path), path + ".outline", kMaxFaceCoordinateMm, 0, kMaxOutlinePoints);
    if (e.contains("drop")) edit.drop = in.boolean(e["drop"], path + ".drop");
    if (e.contains("holes")) {
      edit.holes =
          in.point_rings(e["holes"], path + ".holes", kMaxFaceCoordinateMm, kMaxOutlinePoints, kMaxOutlinePoints);
    }
    model.apply(edit, source, path);
  }
  return model;
}

FaceModel parse_face_model(const std::string& text, const std::string& source) {
  return face_model_from_json(json_util::parse(text, source), source);
}

namespace {

AnyModel model_from_json(const json& root, const std::string& source) {
  const json_util::Reader in(source);
  in.require_object(root, "document");
  const std::string format = in.string(in.require(root, "format", ""), "format");
  if (format == kVoxelFormat) return voxel_model_from_json(root, source);
  if (format == kFacesFormat) return face_model_from_json(root, source);
  in.fail("format",
          "expected \"" + std::string(kVoxelFormat) + "\" or \"" + kFacesFormat + "\", got \"" + format + "\"");
}

}  // namespace

AnyModel parse_model(const std::string& text, const std::string& source) {
  return model_from_json(json_util::parse(text, source), source);
}

AnyModel load_model(const std::string& path) {
  if (is_drawing_path(path)) {
    CardImport imported = import_card(path);
    if (!imported.card.model) throw CardConflictError(imported.drawing.source, imported.card);
    return std::move(*imported.card.model);
  }
  if (is_oa_path(path)) return parse_oa_model(read_text_file(path), path);
  const std::string source = path == "-" ? "<stdin>" : path;
  const json root = json_util::parse(read_text_file(path), source);  // parsed once, whatever it holds
  if (is_design_json(root)) return design_from_json(root, source).model();
  return model_from_json(root, source);
}

std::string to_face_json(const FaceModel& model, const std::string& name) {
  std::ostringstream o;
  const Rect s = model.sheet();
  o << "{\n  \"format\": \"" << kFacesFormat << "\",\n";
  if (!name.empty()) o << "  \"name\": " << json(name).dump() << ",\n";
  o << "  \"sheet\": " << card_sheet_json(s) << ",\n";
  if (model.has_edit_history()) {
    o << "  \"edits\": [";
    const auto& edits = model.edits();
    for (std::size_t i = 0; i < edits.size(); ++i) {
      o << (i ? ",\n    " : "\n    ") << "{\"op\": \"" << to_string(edits[i].op)
        << "\", \"t\": " << number_text(edits[i].t_mm) << ", \"outline\": ";
      json_util::put_points(o, edits[i].outline);
      if (!edits[i].holes.empty()) {  // most edits have none, and older readers know no "holes"
        o << ", \"holes\": ";
        json_util::put_point_rings(o, edits[i].holes);
      }
      if (edits[i].drop) o << ", \"drop\": true";
      o << "}";
    }
    o << "\n  ]\n}\n";
    return o.str();
  }
  o << "  \"faces\": [";
  const auto faces = model.faces();
  for (std::size_t i = 0; i < faces.size(); ++i) {
    o << (i ? ",\n    " : "\n    ") << "{\"kind\": \"" << to_string(faces[i].kind)
      << "\", \"t\": " << number_text(faces[i].t_mm) << ", \"outer\": ";
    put_ring(o, faces[i].polygon.outer);
    o << ", \"holes\": [";
    for (std::size_t h = 0; h < faces[i].polygon.holes.size(); ++h) {
      if (h) o << ", ";
      put_ring(o, faces[i].polygon.holes[h]);
    }
    o << "]" << (faces[i].opening_paper ? ", \"opening\": true" : "") << "}";
  }
  o << "\n  ]\n}\n";
  return o.str();
}

Pattern make_pattern(const AnyModel& model, const std::string& source) {
  return std::visit([&](const auto& m) { return make_pattern(m, source); }, model);
}

}  // namespace popcut
