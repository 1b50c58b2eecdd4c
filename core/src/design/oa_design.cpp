// webOAcard cards as designs: the derived faces read back as wall and roof items, holes and all.
#include "popcut/design/oa_design.h"

#include <algorithm>

#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut {
namespace {

using Outline = std::vector<std::array<double, 2>>;

// A ring of pattern points (x, v) in its face's plane: a wall's (x, z = v + t), a roof's
// (x, y = t - v). The card's faces lie on the nm grid, so the sums are exact to well under a
// nm; the last bit of a corner on the floor or the back board is kept off its wrong side.
Outline in_plane(const Ring& ring, const OAFace& face) {
  const bool wall = face.kind == FaceKind::vertical;
  Outline out;
  out.reserve(ring.size());
  for (const Point2& p : ring) out.push_back({p.x_mm, std::max(0.0, wall ? p.v_mm + face.t_mm : face.t_mm - p.v_mm)});
  return out;
}

std::string face_name(const OAFace& face, std::size_t i) {
  return "face " + std::to_string(i + 1) + " (" +
         (face.kind == FaceKind::vertical ? "a wall at t = " : "a top face at z = ") + format_decimal(face.t_mm, 3) +
         " mm)";
}

}  // namespace

FaceDesign design_from_oa(const OaCard& card, const std::string& source) {
  const FaceModel card_model = face_model_from_oa(card, source);
  const std::vector<OAFace> faces = card_model.faces();
  FaceDesign design(card.width_mm, card.half_height_mm, card.half_height_mm);
  std::vector<DesignItem> items;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const OAFace& f = faces[i];
    // The back board and the floor (and anything drawn in their planes) are the blank card's
    // own: what is left of them is what the other faces leave.
    if (f.t_mm == 0) continue;
    DesignItem item;
    item.tool = f.kind == FaceKind::vertical ? DesignTool::wall : DesignTool::roof;
    item.t_mm = f.t_mm;
    item.top = item.tool != DesignTool::wall;  // only a wall has tops (a roof's flag is unused)
    item.outline = in_plane(f.polygon.outer, f);
    for (const Ring& h : f.polygon.holes) item.holes.push_back(in_plane(h, f));
    const std::string name = face_name(f, items.size());
    std::size_t most = item.outline.size();
    for (const Outline& h : item.holes) most = std::max(most, h.size());
    if (most > kMaxDesignOutlinePoints) {
      throw Error(ErrorCode::limit, source, name,
                  "has a ring of " + std::to_string(most) + " corners; a design item's may have at most " +
                      std::to_string(kMaxDesignOutlinePoints));
    }
    items.push_back(std::move(item));
    names.push_back(name);
  }
  try {
    design.add_all(items, names);
  } catch (const Error& e) {
    throw Error(e.code(), source, e.location(), e.message());
  }
  design.clear_history();
  return design;
}

}  // namespace popcut
