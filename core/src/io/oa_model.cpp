// Reader for webOAcard's .oa JSON: settings and the drawn faces, each field checked, then webOAcard's derivation.
#include "popcut/io/oa_model.h"

#include "io/ascii_case.h"
#include "io/json_util.h"
#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
using json_util::index_path;
using json_util::json;
using json_util::key_path;

namespace {

// The reader, and what the card read so far adds up to.
struct OaReader {
  const json_util::Reader& in;
  double card_h_mm;
  std::size_t points = 0;
};

// One ring of {"X", "Y"} points (mm, webOAcard's 2D frame).
Ring read_ring(OaReader& r, const json& j, const std::string& path) {
  const json_util::Reader& in = r.in;
  in.require_array(j, path);
  // Counted before the points are read: a file over the limit is refused at once.
  r.points += j.size();
  if (r.points > kMaxOaPoints) {
    throw Error(ErrorCode::limit, in.source(), path,
                "brings the card's points to " + std::to_string(r.points) + "; the limit for a .oa card is " +
                    std::to_string(kMaxOaPoints));
  }
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

OaContour read_contour(OaReader& r, const json& j, const std::string& path) {
  const json_util::Reader& in = r.in;
  in.require_object(j, path);
  in.only_keys(j, {"outer", "holes"}, path);
  OaContour c;
  c.outer = read_ring(r, in.require(j, "outer", path), key_path(path, "outer"));
  if (j.contains("holes")) {
    const json& holes = j["holes"];
    const std::string hp = key_path(path, "holes");
    in.require_array(holes, hp);
    if (holes.size() > kMaxOaFaces) in.fail(hp, "has more than " + std::to_string(kMaxOaFaces) + " holes");
    // webOAcard writes an empty ring for "no hole" (createFace's "holes": [[]]).
    for (std::size_t h = 0; h < holes.size(); ++h) {
      if (holes[h].is_array() && holes[h].empty()) continue;
      c.holes.push_back(read_ring(r, holes[h], index_path(hp, h)));
      c.hole_index.push_back(h);
    }
  }
  return c;
}

OaMode read_mode(const json_util::Reader& in, const json& j, const std::string& path) {
  try {
    return static_cast<OaMode>(in.integer(j, path, 0, 2));
  } catch (const Error& e) {
    // The numbers alone do not say which is which.
    throw Error(e.code(), e.source(), e.location(), e.message() + " (0 wall, 1 hole, 2 pull)");
  }
}

OaFace read_face(OaReader& r, const json& j, const std::string& path) {
  const json_util::Reader& in = r.in;
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
  // The editor moves its edit plane from the back board (0) to below the card's front edge
  // (cardH): a face further out would stand off the floor, its top face higher than the card.
  if (f.t_mm > r.card_h_mm) {
    in.fail(key_path(path, "t"), "is " + format_significant(f.t_mm) + " mm: a face's depth must be from 0 to cardH (" +
                                     format_significant(r.card_h_mm) + " mm, settings.cardH)");
  }
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
  if (contours.size() > kMaxOaFaces) in.fail(cp, "has more than " + std::to_string(kMaxOaFaces) + " contours");
  for (std::size_t i = 0; i < contours.size(); ++i)
    f.contours.push_back(read_contour(r, contours[i], index_path(cp, i)));
  return f;
}

}  // namespace

bool is_oa_path(const std::string& path) {
  const std::string p = ascii_lower(path);
  return p.size() > 3 && p.compare(p.size() - 3, 3, ".oa") == 0;
}

bool is_oa_document(const std::string& text) {
  const json root = json::parse(text, nullptr, false);
  return root.is_object() && !root.contains("format") && root.contains("settings") && root.contains("faces");
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
  // Half the sheet's limit: a top face can stand as high as a face's depth plus cardH.
  card.half_height_mm =
      in.number(in.require(settings, "cardH", "settings"), "settings.cardH", 1e-3, kMaxFaceCoordinateMm / 2);
  const json& faces = in.require(root, "faces", "");
  in.require_array(faces, "faces");
  if (faces.size() > kMaxOaFaces) {
    throw Error(
        ErrorCode::limit, source, "faces",
        "has " + std::to_string(faces.size()) + " faces; the limit for a .oa card is " + std::to_string(kMaxOaFaces));
  }
  OaReader r{in, card.half_height_mm};
  for (std::size_t i = 0; i < faces.size(); ++i) card.faces.push_back(read_face(r, faces[i], index_path("faces", i)));
  return card;
}

FaceModel parse_oa_model(const std::string& text, const std::string& source) {
  return face_model_from_oa(parse_oa_card(text, source), source);
}

}  // namespace popcut
