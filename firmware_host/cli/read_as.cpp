// --as card|sheet for every command that reads a model, and validate --as sheet's report.
#include "cli/read_as.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <ostream>

#include "cli/common.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/model_io.h"
#include "popcut/io/pattern_io.h"
#include "popcut/text.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

SheetFoldOptions fold_options(const ReadAs& r) {
  SheetFoldOptions o;
  o.angle_deg = r.crease_deg;
  o.fixed_region = r.fixed;
  for (const std::string& pair : r.folds) {
    const auto turn = parse_crease_angle(pair);
    if (!turn)
      throw CliError(kBadInput, ErrorCode::invalid_input, "", "--fold",
                     std::string("expected ") + kCreaseAngleSyntax + ", got \"" + pair + "\"");
    o.angles.push_back(*turn);
  }
  return o;
}

// "X1,V1,X2,V2" or "...,under": four decimal numbers (mm), then how the side turns.
LineFoldStep parse_fold_line(const std::string& text) {
  std::vector<std::string> parts;
  std::size_t from = 0;
  for (std::size_t comma; (comma = text.find(',', from)) != std::string::npos; from = comma + 1)
    parts.push_back(text.substr(from, comma - from));
  parts.push_back(text.substr(from));
  const bool under = parts.size() == 5 && (parts[4] == "under" || parts[4] == "over");
  bool ok = parts.size() == 4 || under;
  double v[4] = {0, 0, 0, 0};
  for (std::size_t i = 0; ok && i < 4; ++i) {
    ok = is_decimal_text(parts[i]);
    if (ok) v[i] = std::stod(parts[i]);
    ok = ok && std::abs(v[i]) <= kMaxDrawingCoordinateMm;
  }
  if (!ok)
    throw CliError(kBadInput, ErrorCode::invalid_input, "", "--fold-line",
                   "expected X1,V1,X2,V2 or X1,V1,X2,V2,under (mm on the folded sheet, the side left of the first "
                   "point to the second turning over), got \"" +
                       text + "\"");
  return {{v[0], v[1]}, {v[2], v[3]}, under && parts[4] == "under"};
}

json place(Point2 p) { return json::array({p.x_mm, p.v_mm}); }

json problem_json(const SheetProblem& p) {
  return {{"what", p.what}, {"at", place(p.at)}, {"regions", p.regions}, {"hinges", p.hinges}};
}

json timed_json(const SheetMotionReport::Timed& t) {
  json j = problem_json(t.problem);
  j["fraction"] = t.fraction;
  return j;
}

}  // namespace

void check_read_as(const ReadAs& r) {
  if (r.sheet()) return;
  const char* option = !r.folds.empty()        ? "--fold"
                       : !r.fold_lines.empty() ? "--fold-line"
                       : r.crease_given        ? "--crease-angle"
                       : r.fixed >= 0          ? "--fixed"
                                               : nullptr;
  if (option)
    throw CliError(kBadInput, ErrorCode::invalid_input, "", option,
                   std::string(option) + " folds a sheet: it needs --as sheet (a card opens by --angle)");
}

void add_read_as_options(CLI::App* command, ReadAs& r, bool folds) {
  command
      ->add_option("--as", r.as,
                   "Read a drawing (SVG, DXF, FOLD) as an OA card, or as a general sheet that folds rigidly along "
                   "its creases (boxes, kirigami, origami with cuts)")
      ->check(CLI::IsMember({"card", "sheet"}))
      ->capture_default_str();
  if (!folds) return;
  command->add_option("--fold", r.folds,
                      "--as sheet: LINE=DEGREES[@STAGE] turns the line (its SVG id, DXF handle, FOLD edge such as "
                      "edges[3]), the ids starting so (tab-*), or every line of a kind (mountain, valley, fold) by "
                      "that angle, in that stage of the motion (1 first); repeatable, the last wins");
  command
      ->add_option("--crease-angle", r.crease_deg,
                   "--as sheet: the turn of creases that give none, in degrees (mountains turn down, valleys and "
                   "scores up)")
      ->check(CLI::Validator(
          [](std::string& text) {
            return is_decimal_text(text) ? std::string()
                                         : "'" + text + "' is not a number of degrees (a decimal number from 0 to 180)";
          },
          "DEGREES"))
      ->check(CLI::Range(0.0, 180.0))
      ->each([&r](const std::string&) { r.crease_given = true; })
      ->capture_default_str();
  command->add_option("--fold-line", r.fold_lines,
                      "--as sheet: X1,V1,X2,V2[,under] folds the sheet, once folded flat, along that line (mm, in the "
                      "plane where the fixed region lies as drawn) through every layer it crosses: the side left of "
                      "the first point to the second turns over onto the rest (or under it); repeatable, in order, "
                      "each a stage of the motion after the drawing's own creases");
  command->add_option("--fixed", r.fixed, "--as sheet: the region that stays flat (default: each piece's largest)")
      ->check(CLI::NonNegativeNumber);
}

FoldableSheet load_cli_sheet(const std::string& path, const ReadAs& r, const DrawingOptions& drawing,
                             const SheetMapOptions& map) {
  if (!is_drawing_path(path))
    throw CliError(kBadInput, ErrorCode::invalid_input, shown(path), "--as",
                   "--as sheet reads drawings (FILE.svg, FILE.dxf, FILE.fold); a model file is a card already");
  LineDrawing d = load_drawing(path, drawing);
  FoldableSheet sheet = make_foldable_sheet(d, build_sheet_map(d, map), fold_options(r));
  for (const std::string& text : r.fold_lines) {
    SheetLineFold next = fold_along_line(d, sheet, parse_fold_line(text), map);
    d = std::move(next.drawing);
    sheet = std::move(next.sheet);
  }
  return sheet;
}

Pattern load_cli_pattern(const std::string& path, const ReadAs& r) {
  check_read_as(r);
  return r.sheet() ? sheet_pattern(load_cli_sheet(path, r)) : load_cli_pattern(path);
}

std::string drawing_job_model(const std::string& path, const ReadAs& r) {
  if (r.sheet()) return to_pattern_json(sheet_pattern(load_cli_sheet(path, r)));
  const AnyModel model = load_model(path);
  return to_face_json(std::get<FaceModel>(model), std::filesystem::path(path).stem().string());
}

json sheet_check_json(const std::string& source, const FoldableSheet& s, const SheetMotionReport& r) {
  json hinges = json::array(), problems = json::array(), cycles = json::array(), collisions = json::array();
  for (const SheetHinge& h : s.hinges)
    hinges.push_back({{"regions", {h.left, h.right}},
                      {"a", place(h.a)},
                      {"b", place(h.b)},
                      {"kind", to_string(h.kind)},
                      {"angle_deg", h.angle_deg},
                      {"stage", h.stage},
                      {"drawn", h.where}});
  json regions = json::array();
  for (std::size_t i = 0; i < s.map.regions.size(); ++i)
    regions.push_back({{"at", place(s.map.regions[i].label)},
                       {"area_mm2", s.map.regions[i].area_mm2},
                       {"piece", s.piece_of[i]},
                       {"cut_out", static_cast<bool>(s.cut_out[i])},
                       {"layer", i < s.layer.size() ? s.layer[i] : 0}});
  json notes = s.map.notes;
  for (const std::string& n : s.notes) notes.push_back(n);
  for (const SheetProblem& p : s.problems) problems.push_back(problem_json(p));
  for (const auto& c : r.open_cycles) cycles.push_back(timed_json(c));
  for (const auto& c : r.collisions) collisions.push_back(timed_json(c));
  return {{"format", "popcut.sheet-check.v1"},
          {"source", source},
          {"folds", sheet_check_exit(s, r) == kOk},
          {"regions", regions},
          {"pieces", s.piece_fixed.size()},
          {"fixed_regions", s.piece_fixed},
          {"hinges", hinges},
          {"frames", r.frames},
          {"problems", problems},
          {"open_cycles", cycles},
          {"collisions", collisions},
          {"notes", notes}};
}

void print_sheet_check(std::ostream& out, const std::string& source, const FoldableSheet& s,
                       const SheetMotionReport& r) {
  out << source << ": " << (sheet_check_exit(s, r) == kOk ? "folds" : "does not fold as drawn") << " ("
      << s.map.regions.size() << " regions, " << s.hinges.size() << " hinges, " << s.piece_fixed.size()
      << (s.piece_fixed.size() == 1 ? " piece" : " pieces") << "; motion checked in " << r.frames << " frames)\n";
  for (const std::string& n : s.map.notes) out << "  note: " << n << "\n";
  for (const std::string& n : s.notes) out << "  note: " << n << "\n";
  for (const auto& c : r.open_cycles)
    out << "  open cycle at " << describe_place(c.problem.at) << ": " << c.problem.what << "\n";
  for (const SheetProblem& p : s.problems) out << "  cannot fold at " << describe_place(p.at) << ": " << p.what << "\n";
  for (const auto& c : r.collisions) out << "  collision: " << c.problem.what << "\n";
}

int sheet_check_exit(const FoldableSheet& s, const SheetMotionReport& r) {
  return r.ok() && s.problems.empty() ? kOk : kDoesNotPopUp;
}

}  // namespace popcut::cli
