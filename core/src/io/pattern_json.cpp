// Writer and strict reader for popcut.pattern.v1, so a pattern survives a JSON round trip exactly.
#include <sstream>

#include "io/json_util.h"
#include "io/readers.h"
#include "popcut/error.h"
#include "popcut/io/pattern_io.h"

namespace popcut {
using json_util::index_path;
using json_util::json;
using json_util::number_text;

namespace {

void put_point(std::ostream& o, Point2 p) { o << "[" << number_text(p.x_mm) << ", " << number_text(p.v_mm) << "]"; }

void put_ring(std::ostream& o, const Ring& ring) {
  o << "[";
  for (std::size_t i = 0; i < ring.size(); ++i) {
    if (i) o << ", ";
    put_point(o, ring[i]);
  }
  o << "]";
}

constexpr double kMaxCoordinateMm = 1e7;

Point2 get_point(const json_util::Reader& in, const json& j, const std::string& path) {
  if (!j.is_array() || j.size() != 2) in.fail(path, "expected [x, v] in mm");
  return {in.number(j[0], index_path(path, 0), -kMaxCoordinateMm, kMaxCoordinateMm),
          in.number(j[1], index_path(path, 1), -kMaxCoordinateMm, kMaxCoordinateMm)};
}

}  // namespace

PatternFace read_face(const json_util::Reader& in, const json& f, const std::string& path, double limit_mm) {
  in.require_object(f, path);
  in.only_keys(f, {"kind", "t", "label", "outer", "holes", "opening"}, path);
  PatternFace face;
  face.kind = in.named(kFaceKindNames, in.require(f, "kind", path), path + ".kind");
  face.t_mm = in.number(in.require(f, "t", path), path + ".t", 0, limit_mm);
  const auto ring = [&](const json& j, const std::string& where) {
    Ring r;
    for (const auto& [x, v] : in.points(j, where, limit_mm, 3, std::size_t{1} << 24)) r.push_back({x, v});
    return r;
  };
  face.outer = ring(in.require(f, "outer", path), path + ".outer");
  if (f.contains("label")) face.label = get_point(in, f["label"], path + ".label");
  if (f.contains("opening")) face.opening_paper = in.boolean(f["opening"], path + ".opening");
  if (f.contains("holes")) {
    in.require_array(f["holes"], path + ".holes");
    for (std::size_t h = 0; h < f["holes"].size(); ++h)
      face.holes.push_back(ring(f["holes"][h], index_path(path + ".holes", h)));
  }
  return face;
}

std::string to_pattern_json(const Pattern& p) {
  std::ostringstream o;
  write_pattern_json(o, p);
  return o.str();
}

void write_pattern_json(std::ostream& o, const Pattern& p) {
  o << "{\n  \"format\": \"" << kPatternFormat << "\",\n  \"units\": \"mm\",\n";
  o << "  \"sheet\": {\"min\": ";
  put_point(o, p.sheet.min);
  o << ", \"max\": ";
  put_point(o, p.sheet.max);
  o << "},\n  \"lines\": [";
  for (std::size_t i = 0; i < p.lines.size(); ++i) {
    const Segment& s = p.lines[i];
    o << (i ? ",\n    " : "\n    ") << "{\"kind\": \"" << to_string(s.kind) << "\", \"a\": ";
    put_point(o, s.a);
    o << ", \"b\": ";
    put_point(o, s.b);
    o << "}";
  }
  o << "\n  ],\n  \"faces\": [";
  for (std::size_t i = 0; i < p.faces.size(); ++i) {
    const PatternFace& f = p.faces[i];
    o << (i ? ",\n    " : "\n    ") << "{\"kind\": \"" << to_string(f.kind) << "\", \"t\": " << number_text(f.t_mm)
      << ", \"label\": ";
    put_point(o, f.label);
    o << ", \"outer\": ";
    put_ring(o, f.outer);
    o << ", \"holes\": [";
    for (std::size_t h = 0; h < f.holes.size(); ++h) {
      if (h) o << ", ";
      put_ring(o, f.holes[h]);
    }
    o << "]" << (f.opening_paper ? ", \"opening\": true" : "") << "}";
  }
  o << "\n  ],\n  \"folds\": [";
  for (std::size_t i = 0; i < p.folds.size(); ++i) {
    const FoldLink& f = p.folds[i];
    o << (i ? ",\n    " : "\n    ") << "{\"upper\": " << f.upper << ", \"lower\": " << f.lower << ", \"kind\": \""
      << to_string(f.kind) << "\", \"length\": " << number_text(f.length_mm) << "}";
  }
  o << "\n  ],\n  \"back_face\": " << p.back_face << ",\n  \"floor_face\": " << p.floor_face << "\n}\n";
}

Pattern parse_pattern(const std::string& text, const std::string& source) {
  const json root = json_util::parse(text, source);
  const json_util::Reader in(source);
  in.require_document(root, kPatternFormat,
                      {"format", "units", "sheet", "lines", "faces", "folds", "back_face", "floor_face"});
  if (in.string(in.require(root, "units", ""), "units") != "mm") in.fail("units", "expected \"mm\"");

  Pattern p;
  const json& sheet = in.require(root, "sheet", "");
  in.require_object(sheet, "sheet");
  in.only_keys(sheet, {"min", "max"}, "sheet");
  p.sheet = {get_point(in, in.require(sheet, "min", "sheet"), "sheet.min"),
             get_point(in, in.require(sheet, "max", "sheet"), "sheet.max")};
  if (!(p.sheet.min.x_mm < p.sheet.max.x_mm && p.sheet.min.v_mm < p.sheet.max.v_mm)) {
    in.fail("sheet", "min must be below and left of max");
  }

  const json& lines = in.require(root, "lines", "");
  in.require_array(lines, "lines");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string path = index_path("lines", i);
    in.require_object(lines[i], path);
    in.only_keys(lines[i], {"kind", "a", "b"}, path);
    p.lines.push_back({in.named(kLineKindNames, in.require(lines[i], "kind", path), path + ".kind"),
                       get_point(in, in.require(lines[i], "a", path), path + ".a"),
                       get_point(in, in.require(lines[i], "b", path), path + ".b")});
  }

  const json& faces = in.require(root, "faces", "");
  in.require_array(faces, "faces");
  for (std::size_t i = 0; i < faces.size(); ++i)
    p.faces.push_back(read_face(in, faces[i], index_path("faces", i), kMaxCoordinateMm));

  const long long face_count = static_cast<long long>(p.faces.size());
  if (root.contains("folds")) {
    const json& folds = root["folds"];
    in.require_array(folds, "folds");
    for (std::size_t i = 0; i < folds.size(); ++i) {
      const std::string path = index_path("folds", i);
      in.require_object(folds[i], path);
      in.only_keys(folds[i], {"upper", "lower", "kind", "length"}, path);
      FoldLink l;
      l.upper = in.integer(in.require(folds[i], "upper", path), path + ".upper", 0, face_count - 1);
      l.lower = in.integer(in.require(folds[i], "lower", path), path + ".lower", 0, face_count - 1);
      l.kind = in.named(kLineKindNames, in.require(folds[i], "kind", path), path + ".kind");
      if (l.kind == LineKind::cut) in.fail(path + ".kind", "a fold is \"mountain\" or \"valley\"");
      l.length_mm = in.number(in.require(folds[i], "length", path), path + ".length", 0, kMaxCoordinateMm);
      p.folds.push_back(l);
    }
  }
  if (face_count > 0) {
    p.back_face = in.integer(in.require(root, "back_face", ""), "back_face", 0, face_count - 1);
    p.floor_face = in.integer(in.require(root, "floor_face", ""), "floor_face", 0, face_count - 1);
  }
  return p;
}

}  // namespace popcut
