// A card designed in face mode (polygon paper, webOAcard): walls, openings and roofs drawn on edit planes, kept as a
// live face model with undo and redo.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "popcut/design/text_outline.h"
#include "popcut/model/face_model.h"
#include "popcut/names.h"
#include "popcut/pattern/pattern.h"
#include "popcut/pattern/popup_check.h"

namespace popcut {

// What a drawn outline is: a wall (a VFace in the plane y = t, points (x, z)), an opening cut
// through a wall there, a roof (an HFace in the plane z = t, points (x, y)), or an opening in a roof.
enum class DesignTool { wall, opening, roof, roof_opening };
inline constexpr auto kDesignToolNames = enum_names<DesignTool>({{DesignTool::wall, "wall"},
                                                                 {DesignTool::opening, "opening"},
                                                                 {DesignTool::roof, "roof"},
                                                                 {DesignTool::roof_opening, "roof_opening"}});

// Limits of one design session, checked on every item.
inline constexpr std::size_t kMaxDesignItems = 5000;
// Corners of one item's outline: a circle of 1 m radius within 0.02 mm takes 500; more only costs
// every later edit (each state keeps its exact polygons).
inline constexpr std::size_t kMaxDesignOutlinePoints = 1000;
// Letters' curves are cut within this of the font's curve (as circles are).
inline constexpr double kTextToleranceMm = 0.02;

struct DesignItem {
  DesignTool tool = DesignTool::wall;
  double t_mm = 0;                             // the edit plane: depth y (wall, opening) or height z
  std::vector<std::array<double, 2>> outline;  // in the edit plane, mm; for text, the one point where it starts
  bool top = true;                             // walls: add the top faces back to the wall behind
  bool mirror = false;                         // also draw it mirrored about the card's centre line
  // Letters instead of a drawn outline: a wall of letters (framed or standing free on a bar), or
  // letters cut through a wall (opening) or a roof (roof_opening). outline[0] is the text's lower
  // left corner, descenders included; in a roof the letters read from the front, their tops
  // towards the back board.
  std::optional<TextSpec> text{};
  // Walls without tops and roofs: parts of the outline left out, what is behind showing through
  // (not openings: no paper folds there). A card imported from its faces (a webOAcard card) has
  // them; the editor's tools draw none.
  std::vector<std::vector<std::array<double, 2>>> holes{};
  // Openings: the paper folds down as a ledge on a level bottom edge (false: it is cut all round
  // and drops out, a plain window).
  bool ledge = true;
  friend bool operator==(const DesignItem&, const DesignItem&) = default;
};

// The face model a list of items makes, kept up to date edit by edit.
//
// Items are drawn back to front whatever order the person adds them in, as webOAcard's editor
// does: a wall covers, in the pattern, everything drawn behind it, so drawing order must follow
// depth (walls and their openings by t, roofs by their front edge). Each wall's top faces run
// from its horizontal top edges back to the nearest wall behind that rises above them, found in
// the faces already drawn (so the rule sees exactly the walls behind). Adding an item in front of
// everything lays its faces over the last state; adding one behind redraws the items in front of
// it (their tops may now stop at it). Undo and redo work on items; a failed edit changes nothing.
class FaceDesign {
 public:
  FaceDesign(double width_mm, double back_mm, double floor_mm);

  // Adds an item; throws popcut::Error naming `where` (and the item it collides with) and leaves
  // the design as it was.
  void add(const DesignItem& item, const std::string& where = "edit");
  // Adds many items at once (a file read, a draft restored): the same design as adding them one
  // by one, without the intermediate states; `where[i]` names items[i] in errors. `ids[i]`, when
  // given, is items[i]'s id (unique, from 1; a restored draft keeps the ids its editor knows),
  // else ids follow the largest in use. All or none.
  void add_all(const std::vector<DesignItem>& items, const std::vector<std::string>& where,
               const std::vector<std::uint64_t>& ids = {});
  // Removes the item with this id (see items()); false when there is none.
  bool remove(std::uint64_t id);
  bool undo();
  bool redo();
  // Forgets undo and redo (a design read from a file starts its history there).
  void clear_history();
  bool can_undo() const { return !undo_.empty(); }
  bool can_redo() const { return !redo_.empty(); }

  struct Placed {
    std::uint64_t id = 0;
    DesignItem item;
    std::size_t edits = 0;  // face edits it made (itself, its mirror, its tops)
  };
  const std::vector<Placed>& items() const { return placed_; }  // in drawing order
  const FaceModel& model() const { return model_; }
  double width_mm() const { return width_mm_; }

  // The pattern and pop-up check of the current state, worked out once per state.
  const Pattern& pattern() const;
  const PopupReport& report() const;

  // How many face edits the last add/remove/undo/redo applied or took back (for the benchmark:
  // 1–3 for an item in front, more for one behind).
  std::size_t last_edit_work() const { return last_work_; }

 private:
  struct Action {
    bool added = true;  // the action added the item (undo removes it)
    Placed placed;
  };
  std::size_t position_for(const Placed& placed) const;
  void insert(std::size_t pos, Placed placed, const std::string& where);
  void erase(std::size_t pos);
  std::size_t edits_before(std::size_t pos) const;
  void redraw_from(std::size_t pos, std::vector<Placed> tail, const std::function<std::string(std::size_t)>& name_of);
  std::size_t draw(const DesignItem& item, const std::string& where, const std::vector<OAFace>& behind);
  static std::string default_name(const Placed& p);
  void changed();

  double width_mm_ = 0;
  FaceModel model_;
  std::vector<Placed> placed_;
  std::vector<Action> undo_, redo_;
  std::uint64_t next_id_ = 1;
  std::size_t last_work_ = 0;
  std::size_t model_redo_depth_ = 0;  // actions atop redo_ whose edits the model itself can redo
  mutable bool have_view_ = false;
  mutable Pattern pattern_;
  mutable PopupReport report_;
};

// The top faces webOAcard's rule gives a wall drawn with `outline` at depth t_mm over the faces
// of `model` (the walls behind it, before the wall itself is drawn): for each horizontal top edge at height h,
// stretches of x each running back to the depth of the nearest VFace behind that covers (x, h) from above, or to the
// back board. Stretches where no wall or board stands behind get no top. As add_hface edits.
std::vector<FaceEdit> wall_tops(const FaceModel& model, double t_mm, const std::vector<std::array<double, 2>>& outline);
// The same, from the model's faces already read.
std::vector<FaceEdit> wall_tops(const std::vector<OAFace>& faces, double t_mm,
                                const std::vector<std::array<double, 2>>& outline);

// An outline mirrored about x = width_mm / 2, its winding kept.
std::vector<std::array<double, 2>> mirrored(const std::vector<std::array<double, 2>>& outline, double width_mm);

}  // namespace popcut
