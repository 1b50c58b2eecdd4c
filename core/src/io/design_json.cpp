// popcut.design.v1 reader and writer: a face-mode design's sheet and items.
#include "popcut/io/design_json.h"

#include <sstream>

#include "io/json_util.h"
#include "io/readers.h"
#include "popcut/error.h"

namespace popcut {
using json_util::index_path;
using json_util::json;
using json_util::number_text;

bool is_design_document(const std::string& text) { return is_design_json(json::parse(text, nullptr, false)); }

bool is_design_json(const json& root) {
  return root.is_object() && root.contains("format") && root["format"] == kDesignFormat;
}

namespace {

constexpr std::uint64_t kMaxDesignItemId = std::uint64_t{1} << 50;  // exact in every JSON reader's double

TextSpec read_text(const json_util::Reader& in, const json& j, const std::string& path) {
  in.require_object(j, path);
  in.only_keys(j, {"string", "font", "size", "frame"}, path);
  TextSpec text;
  // The length is the text setter's to judge (a limit, with the count), not the reader's.
  text.text = in.string(in.require(j, "string", path), path + ".string", std::string::npos);
  if (j.contains("font")) text.font = in.string(j["font"], path + ".font", 256);
  if (j.contains("size")) text.size_mm = in.number(j["size"], path + ".size", kMinTextSizeMm, kMaxTextSizeMm);
  if (j.contains("frame")) text.frame = in.boolean(j["frame"], path + ".frame");
  return text;
}

DesignItem read_design_item(const json_util::Reader& in, const json& j, const std::string& path, bool with_id) {
  in.require_object(j, path);
  if (with_id)
    in.only_keys(j, {"id", "tool", "t", "outline", "holes", "text", "at", "top", "mirror", "ledge"}, path);
  else
    in.only_keys(j, {"tool", "t", "outline", "holes", "text", "at", "top", "mirror", "ledge"}, path);
  DesignItem item;
  const std::string at = path.empty() ? "" : path + ".";
  item.tool = in.named(kDesignToolNames, in.require(j, "tool", path), at + "tool");
  item.t_mm = in.number(in.require(j, "t", path), at + "t", 0, kMaxFaceCoordinateMm);
  if (j.contains("text")) {
    if (j.contains("outline")) in.fail(at + "outline", "an item is an outline or a text, not both");
    item.text = read_text(in, j["text"], at + "text");
    const json& start = in.require(j, "at", path);
    in.require_array(start, at + "at");
    if (start.size() != 2)
      in.fail(at + "at", "expected [x, z] (a roof: [x, y]): where the first line's baseline starts");
    item.outline = {{in.number(start[0], at + "at[0]", -kMaxFaceCoordinateMm, kMaxFaceCoordinateMm),
                     in.number(start[1], at + "at[1]", -kMaxFaceCoordinateMm, kMaxFaceCoordinateMm)}};
  } else {
    if (j.contains("at")) in.fail(at + "at", "only a text has a starting point \"at\"");
    item.outline =
        in.points(in.require(j, "outline", path), at + "outline", kMaxFaceCoordinateMm, 3, kMaxDesignOutlinePoints);
    if (j.contains("holes")) {
      item.holes =
          in.point_rings(j["holes"], at + "holes", kMaxFaceCoordinateMm, kMaxDesignOutlinePoints, kMaxOutlinePoints);
    }
  }
  if (j.contains("holes") && item.text) in.fail(at + "holes", "a text has no holes");
  const auto flag = [&](const char* key, bool fallback) {
    return j.contains(key) ? in.boolean(j[key], at + key) : fallback;
  };
  item.top = flag("top", true);
  if (j.contains("top") && item.tool != DesignTool::wall) in.fail(at + "top", "only a wall has top faces");
  item.mirror = flag("mirror", false);
  item.ledge = flag("ledge", true);
  const bool opening = item.tool == DesignTool::opening || item.tool == DesignTool::roof_opening;
  if (j.contains("ledge") && !opening) in.fail(at + "ledge", "only an opening's paper folds down as a ledge");
  return item;
}

}  // namespace

DesignItem parse_design_item(const std::string& text, const std::string& source) {
  const json_util::Reader in(source);
  return read_design_item(in, json_util::parse(text, source), "", false);
}

FaceDesign parse_design(const std::string& text, const std::string& source) {
  return design_from_json(json_util::parse(text, source), source);
}

FaceDesign design_from_json(const json& root, const std::string& source) {
  const json_util::Reader in(source);
  in.require_document(root, kDesignFormat, {"format", "name", "sheet", "items"});
  const auto [width, back, floor] = read_card_sheet(in, root);
  if (root.contains("name")) in.string(root["name"], "name", 256);
  const json& items = in.require(root, "items", "");
  in.require_array(items, "items");
  if (items.size() > kMaxDesignItems) {
    throw Error(ErrorCode::limit, source, "items", "has more than " + std::to_string(kMaxDesignItems) + " items");
  }
  FaceDesign design(width, back, floor);
  std::vector<DesignItem> read;
  std::vector<std::string> paths;
  std::vector<std::uint64_t> ids;  // all given, or none: ids then follow the file's order
  for (std::size_t i = 0; i < items.size(); ++i) {
    paths.push_back(index_path("items", i));
    read.push_back(read_design_item(in, items[i], paths.back(), true));
    if (items[i].contains("id") != (i == 0 ? items[0].contains("id") : !ids.empty()))
      in.fail(paths.back() + ".id", "give every item an id, or none");
    if (items[i].contains("id")) {
      const json& id = items[i]["id"];
      if (!id.is_number_unsigned() || id.get<std::uint64_t>() < 1 || id.get<std::uint64_t>() > kMaxDesignItemId)
        in.fail(paths.back() + ".id", "expected a whole number from 1 to " + std::to_string(kMaxDesignItemId));
      ids.push_back(id.get<std::uint64_t>());
    }
  }
  try {
    design.add_all(read, paths, ids);
  } catch (const Error& e) {
    throw Error(e.code(), source, e.location(), e.message());
  }
  design.clear_history();  // undo starts from the design as read, not item by item through the file
  return design;
}

std::string to_design_json(const FaceDesign& design, const std::string& name) {
  std::ostringstream o;
  const Rect s = design.model().sheet();
  o << "{\n  \"format\": \"" << kDesignFormat << "\",\n";
  if (!name.empty()) o << "  \"name\": " << json(name).dump() << ",\n";
  o << "  \"sheet\": " << card_sheet_json(s) << ",\n  \"items\": [";
  const auto& items = design.items();
  for (std::size_t i = 0; i < items.size(); ++i) {
    const DesignItem& it = items[i].item;
    o << (i ? ",\n    " : "\n    ") << "{\"id\": " << items[i].id << ", \"tool\": \"" << kDesignToolNames.name(it.tool)
      << "\", \"t\": " << number_text(it.t_mm);
    if (it.text) {
      o << ", \"text\": {\"string\": " << json(it.text->text).dump() << ", \"font\": " << json(it.text->font).dump()
        << ", \"size\": " << number_text(it.text->size_mm) << (it.text->frame ? "" : ", \"frame\": false")
        << "}, \"at\": [" << number_text(it.outline[0][0]) << ", " << number_text(it.outline[0][1]) << "]";
    } else {
      o << ", \"outline\": ";
      json_util::put_points(o, it.outline);
      if (!it.holes.empty()) {
        o << ", \"holes\": ";
        json_util::put_point_rings(o, it.holes);
      }
    }
    if (it.tool == DesignTool::wall && !it.top) o << ", \"top\": false";
    if (it.mirror) o << ", \"mirror\": true";
    if (!it.ledge) o << ", \"ledge\": false";
    o << "}";
  }
  o << (items.empty() ? "]\n}\n" : "\n  ]\n}\n");
  return o.str();
}

}  // namespace popcut
