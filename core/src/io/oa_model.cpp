// Reader for webOAcard's .oa JSON: settings and the drawn faces, each field checked, then webOAcard's derivation.
#include "popcut/io/oa_model.h"

#include "io/ascii_case.h"
#include "io/json_util.h"
#include "popcut/error.h"

namespace popcut {
using json_util::index_path;
using json_util::json;
using json_util::key_path;

namespace {

// One ring of {"X", "Y"} points (mm, webOAcard's 2D frame).
Ring read_ring(const json_util::Reader& in, const json& j, const std::string& path) {
  in.require_array(j, path);
  if (j.size() < 3) in.fail(path, "needs at least 3 points, got " + std::to_string(j.size()));
  if (j.size() > kMaxOutlinePoints) {
    in.fail(path, "has " + std::to_string(j.size()) + " points; the limit is " + std::to_string(kMaxOutlinePoints));
  }
  Ring ring;
  ring.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string p = index_path(path, i);
    in.require_object(j[i], p);
    in.only_keys(j[i], {"X", "Y"}, p);
    const double x = in.number(in.require(j[i], "X", p), key_path(p, "X"), -kMaxFaceCoordinateMm, kMaxFaceCoordinateMm);
    const double y = in.number(in.require(j[i], "Y", p), key_path(p, "Y"), -kMaxFaceCoordinateMm, kMaxFaceCoordinateMm);
    ring.push_back({x, y});
  }
  return ring;
}

OaContour read_contour(const json_util::Reader& in, const json& j, const std::string& path) {
  in.require_object(j, path);
  in.only_keys(j, {"outer", "holes"}, path);
  OaContour c;
  c.outer = read_ring(in, in.require(j, "outer", path), key_path(path, "outer"));
  if (j.contains("holes")) {
    const json& holes = j["holes"];
    const std::string hp = key_path(path, "holes");
    in.require_array(holes, hp);
    if (holes.size() > kMaxFaces) in.fail(hp, "has more than " + std::to_string(kMaxFaces) + " holes");
    // webOAcard writes an empty ring for "no hole" (createFace's "holes": [[]]).
    for (std::size_t h = 0; h < holes.size(); ++h) {
      if (holes[h].is_array() && holes[h].empty()) continue;
      c.holes.push_back(read_ring(in, holes[h], index_path(hp, h)));
    }
  }
  return c;
}

OaMode read_mode(const json_util::Reader& in, const json& j, const std::string& path) {
  if (!j.is_number_integer() && !j.is_number_unsigned())
    in.fail(path, "expected 0 (wall), 1 (hole) or 2 (pull), got " + j.dump());
  const auto mode = j.get<long long>();
  if (mode < 0 || mode > 2) in.fail(path, "expected 0 (wall), 1 (hole) or 2 (pull), got " + std::to_string(mode));
  return static_cast<OaMode>(mode);
}

OaFace read_face(const json_util::Reader& in, const json& j, const std::string& path) {
  in.require_object(j, path);
  in.only_keys(j, {"contours", "type", "mode", "t", "contoursType", "timestamp"}, path);
  OaFace f;
  f.where = path;
  const std::string type = in.string(in.require(j, "type", path), key_path(path, "type"));
  if (type == "HFACE") {
    in.fail(key_path(path, "type"),
            "\"HFACE\" is not supported: webOAcard's editor draws every face as a \"VFACE\" and derives the "
            "horizontal ones");
  }
  if (type != "VFACE") in.fail(key_path(path, "type"), "expected \"VFACE\", got \"" + type + "\"");
  f.mode = read_mode(in, in.require(j, "mode", path), key_path(path, "mode"));
  f.t_mm = in.number(in.require(j, "t", path), key_path(path, "t"), 0, kMaxFaceCoordinateMm);
  if (j.contains("contoursType")) {
    const std::string kind = in.string(j["contoursType"], key_path(path, "contoursType"));
    if (kind != "" && kind != "expolygons")
      in.fail(key_path(path, "contoursType"), "expected \"\" or \"expolygons\", got \"" + kind + "\"");
    f.expolygons = kind == "expolygons";
  }
  if (j.contains("timestamp")) in.number(j["timestamp"], key_path(path, "timestamp"), -9e15, 9e15);
  const json& contours = in.require(j, "contours", path);
  const std::string cp = key_path(path, "contours");
  in.require_array(contours, cp);
  if (contours.empty()) in.fail(cp, "has no contour: a face needs at least one");
  if (contours.size() > kMaxFaces) in.fail(cp, "has more than " + std::to_string(kMaxFaces) + " contours");
  for (std::size_t i = 0; i < contours.size(); ++i)
    f.contours.push_back(read_contour(in, contours[i], index_path(cp, i)));
  return f;
}

}  // namespace

bool is_oa_path(const std::string& path) {
  const std::string p = ascii_lower(path);
  return p.size() > 3 && p.compare(p.size() - 3, 3, ".oa") == 0;
}

OaCard parse_oa_card(const std::string& text, const std::string& source) {
  const json root = json_util::parse(text, source);
  const json_util::Reader in(source);
  in.require_object(root, "document");
  in.only_keys(root, {"settings", "faces"}, "");
  const json& settings = in.require(root, "settings", "");
  in.require_object(settings, "settings");
  in.only_keys(settings, {"cardW", "cardH"}, "settings");
  OaCard card;
  card.width_mm = in.number(in.require(settings, "cardW", "settings"), "settings.cardW", 1e-3, kMaxFaceCoordinateMm);
  card.half_height_mm =
      in.number(in.require(settings, "cardH", "settings"), "settings.cardH", 1e-3, kMaxFaceCoordinateMm);
  const json& faces = in.require(root, "faces", "");
  in.require_array(faces, "faces");
  if (faces.size() > kMaxFaces) in.fail("faces", "has more than " + std::to_string(kMaxFaces) + " faces");
  std::size_t points = 0;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    card.faces.push_back(read_face(in, faces[i], index_path("faces", i)));
    for (const OaContour& c : card.faces.back().contours) {
      points += c.outer.size();
      for (const Ring& h : c.holes) points += h.size();
    }
    if (points > kMaxOaPoints) {
      throw Error(ErrorCode::limit, source, index_path("faces", i),
                  "the card has more than " + std::to_string(kMaxOaPoints) + " points");
    }
  }
  return card;
}

FaceModel parse_oa_model(const std::string& text, const std::string& source) {
  return face_model_from_oa(parse_oa_card(text, source), source);
}

}  // namespace popcut
