// Size limits on submitted models, checked before any geometry work, and the pattern they make.
#include "model_limits.h"

#include <nlohmann/json.hpp>

#include "popcut/error.h"
#include "popcut/io/pattern_io.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"

namespace popcut::daemon {

AnyModel checked_model(const std::string& text, const std::string& source, const Limits& limits) {
  AnyModel m = parse_model(text, source);
  if (const VoxelModel* v = std::get_if<VoxelModel>(&m)) {
    const long long cells = static_cast<long long>(v->width) * v->depth * v->height;
    if (cells > limits.model_cells) {
      throw Error(ErrorCode::limit, source, "model",
                  std::to_string(cells) + " voxel cells; this daemon takes at most " +
                      std::to_string(limits.model_cells) + " ([limits] model_cells)");
    }
  } else {
    const FaceModel& f = std::get<FaceModel>(m);
    const std::size_t n = f.has_edit_history() ? f.edits().size() : f.face_count();
    if (n > static_cast<std::size_t>(limits.pattern_faces)) {
      throw Error(ErrorCode::limit, source, "model",
                  std::to_string(n) + " edits or faces; this daemon takes at most " +
                      std::to_string(limits.pattern_faces) + " ([limits] pattern_faces)");
    }
  }
  return m;
}

namespace {

// A popcut.pattern.v1 document (a drawn sheet's lines, from `popcut submit --as sheet`): cut as it is.
bool is_pattern_document(const std::string& text) {
  const nlohmann::json root = nlohmann::json::parse(text, nullptr, false);
  return root.is_object() && root.contains("format") && root["format"] == kPatternFormat;
}

Pattern checked_pattern_size(Pattern p, const std::string& source, const Limits& limits) {
  if (p.faces.size() > static_cast<std::size_t>(limits.pattern_faces)) {
    throw Error(ErrorCode::limit, source, "model",
                "the pattern has " + std::to_string(p.faces.size()) + " faces; this daemon takes at most " +
                    std::to_string(limits.pattern_faces));
  }
  return p;
}

}  // namespace

Pattern checked_pattern(const std::string& text, const std::string& source, const Limits& limits) {
  if (is_pattern_document(text)) {
    Pattern p = parse_pattern(text, source);
    const std::size_t max_lines = static_cast<std::size_t>(limits.pattern_faces) * kPatternLinesPerFace;
    if (p.faces.size() > static_cast<std::size_t>(limits.pattern_faces))
      throw Error(ErrorCode::limit, source, "model",
                  "the pattern has " + std::to_string(p.faces.size()) + " faces; this daemon takes at most " +
                      std::to_string(limits.pattern_faces) + " ([limits] pattern_faces)");
    if (p.lines.size() > max_lines)
      throw Error(ErrorCode::limit, source, "model",
                  "the pattern has " + std::to_string(p.lines.size()) + " lines; this daemon takes at most " +
                      std::to_string(max_lines) + " (" + std::to_string(kPatternLinesPerFace) +
                      " × [limits] pattern_faces)");
    return p;
  }
  const AnyModel m = checked_model(text, source, limits);
  if (const FaceModel* f = std::get_if<FaceModel>(&m)) return checked_face_pattern(*f, source, limits);
  return checked_pattern_size(make_pattern(m, source), source, limits);
}

Pattern checked_face_pattern(const FaceModel& model, const std::string& source, const Limits& limits) {
  Pattern p = checked_pattern_size(make_pattern(model, source), source, limits);
  require_attached(model, p, check_popup(p), source);
  return p;
}

}  // namespace popcut::daemon
