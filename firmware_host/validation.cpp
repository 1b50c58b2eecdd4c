// The pop-up check's report in words and as popcut.validation.v1: faces named by where they stand on the open card.
#include "validation.h"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <sstream>

#include "popcut/text.h"

namespace popcut {
namespace {

using nlohmann::json;

json point(Point2 p) { return json::array({p.x_mm, p.v_mm}); }
json rect(const Rect& r) { return {{"min", point(r.min)}, {"max", point(r.max)}}; }

// A tenth of a millimetre; -0.04 reads "0.0", not "-0.0", which a designer takes for a bug.
std::string mm(double v) { return format_fixed(v, 1); }

std::string range(double a, double b) { return a == b ? mm(a) : mm(a) + "–" + mm(b); }

// Where a face stands at 90°, as a 3D box: the numbers a designer measures on the card.
struct Box3 {
  Point3 min, max;
};
Box3 card_box(const PatternFace& f) {
  Box3 b{to_card(f.kind, f.t_mm, f.outer.front()), to_card(f.kind, f.t_mm, f.outer.front())};
  for (const Point2& p : f.outer) {
    const Point3 q = to_card(f.kind, f.t_mm, p);
    b.min = {std::min(b.min.x_mm, q.x_mm), std::min(b.min.y_mm, q.y_mm), std::min(b.min.z_mm, q.z_mm)};
    b.max = {std::max(b.max.x_mm, q.x_mm), std::max(b.max.y_mm, q.y_mm), std::max(b.max.z_mm, q.z_mm)};
  }
  return b;
}

std::string describe_face(const Pattern& p, int index) {
  const PatternFace& f = p.faces[static_cast<std::size_t>(index)];
  const Rect r = bounds(f.outer);
  const Box3 b = card_box(f);
  std::ostringstream o;
  o << "face " << index << " (" << (f.kind == FaceKind::vertical ? "VFace at depth y = " : "HFace at height z = ")
    << mm(f.t_mm) << " mm): pattern x " << range(r.min.x_mm, r.max.x_mm) << ", v " << range(r.min.v_mm, r.max.v_mm)
    << " mm; on the open card x " << range(b.min.x_mm, b.max.x_mm) << ", y " << range(b.min.y_mm, b.max.y_mm) << ", z "
    << range(b.min.z_mm, b.max.z_mm) << " mm";
  return o.str();
}

std::string not_standing_text(const Pattern& p, const FaceProblem& fp) {
  return "would not stand: " + describe_face(p, fp.face) + "; not reached " +
         (!fp.from_back && !fp.from_floor ? "from the back board or the floor"
                                          : (!fp.from_back ? "from the back board" : "from the floor"));
}

std::string flap_text(const Pattern& p, const FaceProblem& fp) {
  return "note: " + describe_face(p, fp.face) + " is held from the " +
         (fp.from_back ? "back board" : (fp.from_floor ? "floor" : "neither side")) + " only; it will hang or tilt";
}

std::string loose_text(const LoosePiece& lp) {
  return "cut free, would fall out: " + std::to_string(lp.faces.size()) + (lp.faces.size() == 1 ? " face" : " faces") +
         " at pattern x " + range(lp.bounds.min.x_mm, lp.bounds.max.x_mm) + ", v " +
         range(lp.bounds.min.v_mm, lp.bounds.max.v_mm) + " mm (" + format_fixed(lp.area_mm2, 1) + " mm²)";
}

std::string cut_out_text(const LoosePiece& lp) {
  return "cut out: the paper of an opening at pattern x " + range(lp.bounds.min.x_mm, lp.bounds.max.x_mm) + ", v " +
         range(lp.bounds.min.v_mm, lp.bounds.max.v_mm) + " mm (" + format_fixed(lp.area_mm2, 1) +
         " mm²) is held by no fold and drops out as the opening is cut";
}

json piece_json(const LoosePiece& lp, const std::string& message) {
  return {{"message", message}, {"faces", lp.faces}, {"bounds", rect(lp.bounds)}, {"area_mm2", lp.area_mm2}};
}

json problem_json(const Pattern& p, const FaceProblem& fp, const std::string& message) {
  const PatternFace& f = p.faces[static_cast<std::size_t>(fp.face)];
  const Box3 b = card_box(f);
  return json{
      {"message", message},
      {"face", fp.face},
      {"kind", to_string(f.kind)},
      {"t", f.t_mm},
      {"reached_from_back", fp.from_back},
      {"reached_from_floor", fp.from_floor},
      {"bounds", rect(bounds(f.outer))},
      {"label", point(f.label)},
      {"card_bounds", {{"min", {b.min.x_mm, b.min.y_mm, b.min.z_mm}}, {"max", {b.max.x_mm, b.max.y_mm, b.max.z_mm}}}}};
}

}  // namespace

json validation_json(const std::string& source, const Pattern& p, const PopupReport& r) {
  const LineCounts c = count_lines(p);
  json j = {{"format", "popcut.validation.v1"},
            {"source", source},
            {"pops_up", r.pops_up()},
            {"sheet_split", r.sheet_split},
            {"no_back_board", r.no_back_board},
            {"no_floor", r.no_floor},
            {"faces", p.faces.size()},
            {"lines", {{"cut", c.cut}, {"mountain", c.mountain}, {"valley", c.valley}}},
            {"line_mm", {{"cut", c.cut_mm}, {"mountain", c.mountain_mm}, {"valley", c.valley_mm}}},
            {"sheet", rect(p.sheet)},
            {"not_standing", json::array()},
            {"loose_pieces", json::array()}};
  j["flaps"] = json::array();
  for (const FaceProblem& fp : r.not_standing)
    j["not_standing"].push_back(problem_json(p, fp, not_standing_text(p, fp)));
  for (const FaceProblem& fp : r.flaps) j["flaps"].push_back(problem_json(p, fp, flap_text(p, fp)));
  j["cut_out"] = json::array();
  for (const LoosePiece& lp : r.loose_pieces) j["loose_pieces"].push_back(piece_json(lp, loose_text(lp)));
  for (const LoosePiece& lp : r.cut_out) j["cut_out"].push_back(piece_json(lp, cut_out_text(lp)));
  return j;
}

void print_validation(std::ostream& out, const std::string& source, const Pattern& p, const PopupReport& r) {
  const LineCounts c = count_lines(p);
  out << source << ": " << (r.pops_up() ? "pops up" : "does NOT pop up") << " (" << p.faces.size() << " faces; "
      << c.cut << " cut, " << c.mountain << " mountain, " << c.valley << " valley lines)\n";
  if (r.no_back_board) out << "  no back board: no vertical face at depth 0 reaches the sheet's top edge\n";
  if (r.no_floor) out << "  no floor: no horizontal face at height 0 reaches the sheet's bottom edge\n";
  if (r.sheet_split) {
    out << "  the sheet falls in two: no fold joins the floor to the back board (is the centre fold cut all along?)\n";
  }
  for (const FaceProblem& fp : r.not_standing) out << "  " << not_standing_text(p, fp) << "\n";
  for (const FaceProblem& fp : r.flaps) out << "  " << flap_text(p, fp) << "\n";
  for (const LoosePiece& lp : r.loose_pieces) out << "  " << loose_text(lp) << "\n";
  for (const LoosePiece& lp : r.cut_out) out << "  note: " << cut_out_text(lp) << "\n";
}

}  // namespace popcut
