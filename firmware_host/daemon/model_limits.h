// Models as the daemon accepts them: parsed, held to [limits], turned into a pattern.
#pragma once

#include <string>

#include "config.h"
#include "popcut/io/model_io.h"

namespace popcut::daemon {

// Parses a popcut.voxel.v1 / popcut.faces.v1 document and checks its size against `limits`;
// throws popcut::Error (invalid_input naming the field, or limit).
AnyModel checked_model(const std::string& json_text, const std::string& source, const Limits& limits);

// A submitted pattern may hold this many lines per [limits] pattern_faces.
inline constexpr int kPatternLinesPerFace = 4;

// The model's pattern, as the CLI makes it: a face model with a piece cut free is bad input. A
// popcut.pattern.v1 document (a sheet's own lines) is the pattern itself, its lines held to
// kPatternLinesPerFace × pattern_faces.
Pattern checked_pattern(const std::string& json_text, const std::string& source, const Limits& limits);
// The same for a face model already built (a card inferred from a drawing): no second parse.
Pattern checked_face_pattern(const FaceModel& model, const std::string& source, const Limits& limits);

}  // namespace popcut::daemon
