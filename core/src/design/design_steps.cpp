// The face edits each design item makes, in drawing order: an outline and its mirror, a wall's tops, or letters set in
// a font (framed, standing free, or cut through).
#include "design/design_steps.h"

#include <algorithm>
#include <utility>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut::detail {
namespace {

using Outline = std::vector<std::array<double, 2>>;

EditOp op_of(DesignTool tool) {
  switch (tool) {
    case DesignTool::wall: return EditOp::add_vface;
    case DesignTool::opening: return EditOp::add_vhole;
    case DesignTool::roof: return EditOp::add_hface;
    case DesignTool::roof_opening: return EditOp::add_hhole;
  }
  return EditOp::add_vface;
}

bool crosses(const Outline& o, double x) {
  const auto [lo, hi] =
      std::minmax_element(o.begin(), o.end(), [](const auto& a, const auto& b) { return a[0] < b[0]; });
  return lo != o.end() && (*lo)[0] < x && (*hi)[0] > x;
}

void add_tops(std::vector<Step>& steps, const DesignItem& item, const Outline& outline,
              const std::vector<OAFace>& behind) {
  if (item.tool != DesignTool::wall || !item.top) return;
  for (FaceEdit& top : wall_tops(behind, item.t_mm, outline)) steps.push_back({std::move(top), true});
}

// A ring of set text moved to the item's place, `lift_mm` up from the plane's origin.
Outline placed(const Ring& ring, const DesignItem& item, double lift_mm) {
  const auto& at = item.outline.front();
  // In a roof the plane's second axis is depth y, growing towards the front: letters read from
  // the front lie with their tops towards the back board.
  const double up = item.tool == DesignTool::roof_opening ? -1 : 1;
  Outline o;
  o.reserve(ring.size());
  for (const Point2& p : ring) o.push_back({at[0] + p.x_mm, at[1] + up * (p.v_mm + lift_mm)});
  if (up < 0) std::reverse(o.begin(), o.end());  // the flip would turn the winding over
  return o;
}

// How far a wall of letters' bar reaches above the baseline, per mm of letter height: past the
// round letters' overshoot, so every letter stands on it.
constexpr double kTextBarAboveBaseline = 0.06;
// A framed wall of letters: the gap between the letters and the frame, and the frame's width
// beyond it, per mm of letter height. The gap keeps the tallest letters, the first and the last
// (and marks on top, as an umlaut's dots) apart from the frame, so their outlines are cut and
// read.
constexpr double kTextFrameGap = 0.06;
constexpr double kTextFrameMargin = 0.12;
// The width of the strip that holds a mark (an i's dot) to the frame, per mm of letter height:
// about a stroke of a regular weight.
constexpr double kTextBridgeWidth = 0.08;

// Letters standing free on their bar: the bar's top runs back as a top the whole length, then
// each letter's flat tops, and the letters are drawn over them all, so a top stays only where no
// letter's paper is (between and inside letters, as in "H", where paper would otherwise be cut
// free). Then the counters are cut back out. Letters close together can still close off paper
// that nothing holds; the pop-up check names it.
void free_letters(std::vector<Step>& steps, const DesignItem& item, const Outline& bar,
                  const std::vector<Outline>& letters, const std::vector<Outline>& counters,
                  const std::vector<OAFace>& behind) {
  steps.push_back({{EditOp::add_vface, item.t_mm, bar}});
  add_tops(steps, item, bar, behind);
  for (const Outline& o : letters) add_tops(steps, item, o, behind);
  for (const Outline& o : letters) steps.push_back({{EditOp::add_vface, item.t_mm, o}});
  for (const Outline& c : counters) steps.push_back({{EditOp::add_vhole, item.t_mm, c, {}, true}});
}

Ring ring_of(const Outline& o) {
  Ring r;
  r.reserve(o.size());
  for (const auto& p : o) r.push_back({p[0], p[1]});
  return r;
}

Outline outline_of(const Ring& r, double v_offset_mm) {
  Outline o;
  o.reserve(r.size());
  for (const Point2& p : r) o.push_back({p.x_mm, p.v_mm + v_offset_mm});
  return o;
}

// Letters in a frame: a plate from the bar to a frame a little above the tallest letter and
// beside the first and last, drawn as a wall (its tops are a plain wall's), with the space around the
// letters inside it cut out as openings, and the counters. Every letter then hangs in one rigid
// piece of paper, whatever the font. The space around is the inner box minus the letters,
// worked out by the face model in a scratch card.
void framed_letters(std::vector<Step>& steps, const DesignItem& item, const Outline& inner, const Outline& plate,
                    const std::vector<Outline>& letters, const std::vector<Outline>& counters, const FaceModel& model,
                    const std::vector<OAFace>& behind, const std::string& where) {
  const Rect sheet = model.sheet();
  FaceModel scratch(sheet.max.x_mm - sheet.min.x_mm, sheet.max.v_mm, -sheet.min.v_mm);
  scratch.apply({EditOp::add_vface, item.t_mm, inner}, "", where);
  for (const Outline& o : letters) scratch.apply({EditOp::add_vface, item.t_mm, o}, "", where);
  std::vector<Ring> rings;
  for (const Outline& o : letters) rings.push_back(ring_of(o));
  add_tops(steps, item, plate, behind);
  steps.push_back({{EditOp::add_vface, item.t_mm, plate}});
  for (const OAFace& f : scratch.faces()) {
    if (f.kind != FaceKind::vertical || f.t_mm != item.t_mm) continue;
    Point2 p = interior_point(f.polygon.outer, f.polygon.holes);
    p.v_mm += item.t_mm;  // the face's sheet v back to the plane's z
    if (std::any_of(rings.begin(), rings.end(), [&](const Ring& r) { return inside_ring(p, r); })) continue;
    steps.push_back({{EditOp::add_vhole, item.t_mm, outline_of(f.polygon.outer, item.t_mm), {}, true}});
  }
  for (const Outline& c : counters) steps.push_back({{EditOp::add_vhole, item.t_mm, c, {}, true}});
}

// Letters: a wall of letters (one line, framed or free, on a bar along the baseline that folds
// to the floor or roof below), or letters cut through a wall or roof, which lose their counters
// with them as a cut "O" does.
std::vector<Step> text_steps(const DesignItem& item, const FaceModel& model, const std::string& where,
                             const std::vector<OAFace>& behind) {
  if (item.tool == DesignTool::roof)
    throw Error(
        ErrorCode::invalid_input, "", where + ".tool",
        "letters lying in a roof would fall out: cut them through a roof (roof_opening) or stand them on a wall");
  const TextSetting set = set_text(*item.text, kTextToleranceMm, where + ".text");
  const bool wall = item.tool == DesignTool::wall;
  if (wall && set.line_boxes.size() > 1)
    throw Error(ErrorCode::invalid_input, "", where + ".text.string",
                "a wall of letters is one line (its letters stand on one bar): put the next line in a text of its own");
  // `at` is the lower left corner of the whole text, descenders included.
  const double lift = set.descent_mm + set.line_height_mm * static_cast<double>(set.line_boxes.size() - 1);
  std::vector<Step> steps;
  if (!wall) {
    for (const TextShape& s : set.shapes)
      steps.push_back({{op_of(item.tool), item.t_mm, placed(s.outer, item, lift), {}, !item.ledge}});
    return steps;
  }
  std::vector<Outline> letters, counters;
  for (const TextShape& s : set.shapes) {
    letters.push_back(placed(s.outer, item, lift));
    for (const Ring& h : s.holes) counters.push_back(placed(h, item, lift));
  }
  const Rect& line = set.line_boxes.front();
  const double bottom = -set.descent_mm, bar_top = kTextBarAboveBaseline * item.text->size_mm;
  const auto box = [&](double x0, double v0, double x1, double v1) {
    return placed({{x0, v0}, {x1, v0}, {x1, v1}, {x0, v1}}, item, lift);
  };
  if (!item.text->frame) {
    free_letters(steps, item, box(line.min.x_mm, bottom, line.max.x_mm, bar_top), letters, counters, behind);
    return steps;
  }
  const double gap = kTextFrameGap * item.text->size_mm, margin = kTextFrameMargin * item.text->size_mm;
  const double bridge = kTextBridgeWidth * item.text->size_mm, x0 = line.min.x_mm - gap, x1 = line.max.x_mm + gap;
  const double top = line.max.v_mm + gap;
  // Marks that stand on nothing (an i's dot, an umlaut, the stroke of a "!") hang from the frame
  // by a strip from their bottom up, as a stencil's bridges hold its islands; cut away with the
  // space around them, "Zoë" would read "Zoe".
  for (const TextShape& s : set.shapes) {
    const Rect b = bounds(s.outer);
    if (b.min.v_mm <= bar_top) continue;
    const double x = (b.min.x_mm + b.max.x_mm) / 2;
    letters.push_back(box(x - bridge / 2, b.min.v_mm, x + bridge / 2, top + margin / 2));
  }
  // The space around the letters and their counters drop out as they are cut (FaceEdit::drop),
  // rather than fold down on the bar or a level counter bottom ("A") as an opening's ledge.
  const Outline inner = placed({{x0, bar_top}, {x1, bar_top}, {x1, top}, {x0, top}}, item, lift);
  framed_letters(steps, item, inner, box(x0 - margin, bottom, x1 + margin, top + margin), letters, counters, model,
                 behind, where);
  return steps;
}

}  // namespace

std::vector<Step> steps_of(const DesignItem& item, const FaceModel& model, const std::string& where,
                           const std::vector<OAFace>& behind) {
  const double width_mm = model.sheet().max.x_mm - model.sheet().min.x_mm;
  if (item.text) {
    if (item.mirror)
      throw Error(ErrorCode::invalid_input, "", where + ".mirror",
                  "text is not mirrored (it would read backwards): add the text again on the other side");
    return text_steps(item, model, where, behind);
  }
  const bool opening = item.tool == DesignTool::opening || item.tool == DesignTool::roof_opening;
  if (!item.ledge && !opening)
    throw Error(ErrorCode::invalid_input, "", where + ".ledge", "only an opening's paper folds down as a ledge");
  if (!item.holes.empty() && opening)
    throw Error(ErrorCode::invalid_input, "", where + ".holes", "an opening has no holes: draw a wall or roof in it");
  if (!item.holes.empty() && item.tool == DesignTool::wall && item.top) {
    throw Error(ErrorCode::invalid_input, "", where + ".holes",
                "a wall with holes gets no automatic tops: give it \"top\": false and draw its roofs");
  }
  std::vector<Outline> outlines = {item.outline};
  if (item.mirror) {
    if (opening && crosses(item.outline, width_mm / 2)) {
      throw Error(ErrorCode::invalid_input, "", where + ".outline",
                  "a mirrored opening must lie on one side of the centre line x = " + format_decimal(width_mm / 2, 3) +
                      " mm: draw an opening across it whole, without mirror");
    }
    outlines.push_back(mirrored(item.outline, width_mm));
  }
  std::vector<Step> steps;
  steps.push_back({{op_of(item.tool), item.t_mm, item.outline, item.holes, !item.ledge}});
  if (item.mirror) {
    std::vector<Outline> holes;
    for (const Outline& h : item.holes) holes.push_back(mirrored(h, width_mm));
    steps.push_back({{op_of(item.tool), item.t_mm, outlines.back(), std::move(holes), !item.ledge}});
  }
  // The tops are found among the faces behind, before the wall is drawn: then the wall and its
  // tops are laid over the model in one step (one Boolean per face they touch).
  for (const Outline& o : outlines) add_tops(steps, item, o, behind);
  return steps;
}

}  // namespace popcut::detail
