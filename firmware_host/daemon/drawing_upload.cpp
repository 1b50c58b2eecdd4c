// POST /api/v1/import/drawing: a pattern drawn elsewhere (SVG, DXF, FOLD) read as an OA card or as a folding sheet.
#include <httplib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string_view>

#include "api_handlers.h"
#include "model_limits.h"
#include "popcut/error.h"
#include "popcut/fold/render.h"
#include "popcut/fold/sheet_fold.h"
#include "popcut/io/base64.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/model_io.h"
#include "popcut/io/pattern_io.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/text.h"

namespace popcut::daemon {
namespace {

namespace fs = std::filesystem;

constexpr std::array<std::string_view, 9> kFields = {"drawing", "as",       "name", "red-is-cut",  "unit-mm",
                                                     "snap-mm", "chord-mm", "fold", "crease-angle"};
constexpr int kSheetCheckFrames = 12;      // steps of the motion checked for open cycles and collisions
constexpr int kSheetPreviewWidthPx = 480;  // the folded sheet's picture on the kiosk

struct DrawingForm {
  const httplib::MultipartFormData* drawing = nullptr;
  std::map<std::string, std::string> values;  // the other parts, by name
};

DrawingForm sort_parts(const httplib::Request& req) {
  if (!req.is_multipart_form_data())
    fail(ApiError::bad_request, "send the drawing as multipart/form-data (curl: -F drawing=@FILE.svg)", "drawing");
  DrawingForm f;
  for (const auto& [key, part] : req.files) {
    if (std::find(kFields.begin(), kFields.end(), key) == kFields.end()) {
      std::string known;
      for (std::string_view k : kFields) known += (known.empty() ? "" : ", ") + std::string(k);
      fail(ApiError::bad_request, "unknown field '" + key + "' (expected " + known + ")", key);
    }
    if ((key == "drawing" && f.drawing) || f.values.count(key))
      fail(ApiError::bad_request, "'" + key + "' given twice", key);
    if (key == "drawing")
      f.drawing = &part;
    else
      f.values[key] = part.content;
  }
  if (!f.drawing)
    fail(ApiError::bad_request, "missing the 'drawing' file part (curl: -F drawing=@FILE.svg)", "drawing");
  if (f.drawing->filename.empty())
    fail(ApiError::bad_request, "'drawing' must be a file part, not a value (curl: -F drawing=@FILE.svg)", "drawing");
  // Only its extension (the format) and stem (the job's default name) are used, never as a path.
  if (!is_job_label(f.drawing->filename))
    fail(ApiError::bad_name,
         "drawing file names are 1 to 64 characters of text in any script, without control characters, '/', '\\', "
         "'..', a leading '.' or a space at either end",
         "drawing");
  if (!is_drawing_path(f.drawing->filename))
    fail(ApiError::bad_request,
         "'" + f.drawing->filename + "' is not a drawing popcut reads: send FILE.svg, FILE.dxf or FILE.fold",
         "drawing");
  return f;
}

// A number field within [lo, hi] as the CLI's flag of the same name takes it, or `fallback`.
double number_field(const DrawingForm& f, const std::string& key, double lo, double hi, double fallback) {
  const auto it = f.values.find(key);
  if (it == f.values.end()) return fallback;
  const std::string& text = it->second;
  char* end = nullptr;
  const double v = is_decimal_text(text) ? std::strtod(text.c_str(), &end) : NAN;  // no hex, no spaces
  if (!std::isfinite(v) || end != text.c_str() + text.size() || v < lo || v > hi)
    fail(ApiError::bad_request,
         "'" + key + "' must be a number from " + format_significant(lo) + " to " + format_significant(hi) +
             ", got \"" + text + "\"",
         key);
  return v;
}

std::string choice_field(const DrawingForm& f, const std::string& key, const std::vector<std::string>& choices) {
  const auto it = f.values.find(key);
  if (it == f.values.end()) return choices.front();
  if (std::find(choices.begin(), choices.end(), it->second) == choices.end()) {
    std::string known;
    for (const std::string& c : choices) known += (known.empty() ? "" : " or ") + c;
    fail(ApiError::bad_request, "'" + key + "' must be " + known + ", got \"" + it->second + "\"", key);
  }
  return it->second;
}

// A sheet's crease angles: 'fold' holds SELECTOR=DEGREES[@STAGE] items separated by spaces, as
// --fold takes them one at a time; 'crease-angle' the turn of creases that give none.
SheetFoldOptions fold_fields(const DrawingForm& f) {
  SheetFoldOptions o;
  o.angle_deg = number_field(f, "crease-angle", 0, 180, o.angle_deg);
  const auto it = f.values.find("fold");
  std::istringstream items(it == f.values.end() ? "" : it->second);
  for (std::string item; items >> item;) {
    const auto turn = parse_crease_angle(item);
    if (!turn)
      fail(ApiError::bad_request, std::string("'fold': expected ") + kCreaseAngleSyntax + ", got \"" + item + "\"",
           "fold");
    o.angles.push_back(*turn);
  }
  return o;
}

// The drawing read with the form's options; over the daemon's pattern limit before any geometry is built.
LineDrawing read_form_drawing(const DrawingForm& f, const Limits& limits) {
  DrawingOptions o;
  o.red_is_cut = choice_field(f, "red-is-cut", {"false", "true"}) == "true";
  o.unit_mm = number_field(f, "unit-mm", 1e-6, 1e5, o.unit_mm);
  o.chord_tolerance_mm = number_field(f, "chord-mm", 0.001, 10, o.chord_tolerance_mm);
  LineDrawing d = read_drawing(f.drawing->content, f.drawing->filename, o);
  const std::size_t segments = segment_count(d);
  const std::size_t max_lines = static_cast<std::size_t>(limits.pattern_faces) * kPatternLinesPerFace;
  if (segments > max_lines)
    throw Error(ErrorCode::limit, d.source, "drawing",
                "the drawing has " + std::to_string(segments) + " segments; this daemon takes at most " +
                    std::to_string(max_lines) + " (" + std::to_string(kPatternLinesPerFace) +
                    " × [limits] pattern_faces)");
  return d;
}

json place(Point2 p) { return {p.x_mm, p.v_mm}; }

// The answer's fields for the model made, and the sheet it is cut from.
struct Made {
  json answer;
  Rect sheet;
};

Made card_answer(const LineDrawing& d, const SheetMap& map, const std::string& name, const Limits& limits) {
  const InferredCard card = infer_card(d, map);
  if (!card.model) throw CardConflictError(d.source, card);
  const std::string model = to_face_json(*card.model, name);
  const Pattern p =
      checked_face_pattern(*card.model, d.source, limits);  // a piece cut free is refused as for a submission
  return {{{"as", "card"},
           {"format", kFacesFormat},
           {"model", json::parse(model)},
           {"faces", card.model->face_count()},
           {"centre_fold_v_mm", card.centre_fold_v_mm}},
          p.sheet};
}

Made sheet_answer(const LineDrawing& d, SheetMap map, const SheetFoldOptions& folds, const Limits& limits) {
  const FoldableSheet sheet = make_foldable_sheet(d, std::move(map), folds);
  const SheetMotionReport motion = check_sheet_motion(sheet, kSheetCheckFrames);
  const std::string model = to_pattern_json(sheet_pattern(sheet));
  const Pattern p = checked_pattern(model, d.source, limits);
  json problems = json::array();
  for (const SheetProblem& q : sheet.problems) problems.push_back({{"what", q.what}, {"at", place(q.at)}});
  for (const auto* timed : {&motion.open_cycles, &motion.collisions})
    for (const SheetMotionReport::Timed& t : *timed)
      problems.push_back({{"what", t.problem.what}, {"at", place(t.problem.at)}, {"fraction", t.fraction}});
  const CardMesh folded = sheet_mesh(sheet, fold_sheet(sheet, 1), 0.02);
  const std::string png = render_png(folded, view_box({folded}), kSheetPreviewWidthPx);
  return {{{"as", "sheet"},
           {"format", kPatternFormat},
           {"model", json::parse(model)},
           {"regions", sheet.map.regions.size()},
           {"hinges", sheet.hinges.size()},
           {"pieces", sheet.piece_fixed.size()},
           {"folds", problems.empty()},
           {"problems", problems},
           {"folded_png", "data:image/png;base64," + base64(png)}},
          p.sheet};
}

}  // namespace

void import_drawing(ApiContext& api, const Caller&, const Req& req, Res& res) {
  const DrawingForm f = sort_parts(req);
  const std::string as = choice_field(f, "as", {"card", "sheet"});
  std::string name = job_label_from(fs::path(f.drawing->filename).stem().string());
  if (f.values.count("name")) {
    name = f.values.at("name");
    if (!is_job_label(name)) fail(ApiError::bad_name, "'name' must be a job name (1 to 64 characters of text)", "name");
  }
  if (name.empty()) name = "drawing";
  const Limits& limits = api.daemon().config().limits;
  if (as == "card") {
    for (const char* key : {"fold", "crease-angle"})
      if (f.values.count(key))
        fail(ApiError::bad_request, std::string("'") + key + "' folds a sheet: send it with as=sheet", key);
  }
  const SheetFoldOptions folds = fold_fields(f);
  SheetMapOptions map_options;
  map_options.snap_tolerance_mm = number_field(f, "snap-mm", 0, 1, map_options.snap_tolerance_mm);
  Made made;
  try {
    // The map, the inference, the motion check and the picture are a render's work: one slot.
    api.in_render_slot([&] {
      const LineDrawing d = read_form_drawing(f, limits);
      SheetMap map = build_sheet_map(d, map_options);
      json notes = d.notes;
      for (const std::string& n : map.notes) notes.push_back(n);
      made = as == "card" ? card_answer(d, map, name, limits) : sheet_answer(d, std::move(map), folds, limits);
      made.answer["notes"] = notes;
      made.answer["lines"] = d.lines.size();
    });
  } catch (const Error& e) {
    if (e.code() == ErrorCode::io || e.code() == ErrorCode::internal) throw;
    // A crease the 'fold' field names badly (located "--fold", as the CLI's flag) is a bad field;
    // else the reader's or the inference's own message, naming the element or the conflicting faces.
    if (e.location() == "--fold") fail(ApiError::bad_request, e.what(), "fold");
    fail(e.code() == ErrorCode::limit ? ApiError::model_too_complex : ApiError::bad_model, e.what(), "drawing");
  }
  const Rect& sheet = made.sheet;
  made.answer["name"] = name;
  made.answer["sheet_mm"] = {{"width", sheet.max.x_mm - sheet.min.x_mm}, {"height", sheet.max.v_mm - sheet.min.v_mm}};
  made.answer["warnings"] = media_warnings(sheet, api.media());
  send_json(res, made.answer);
}

}  // namespace popcut::daemon
