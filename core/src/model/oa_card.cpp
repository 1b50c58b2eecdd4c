// webOAcard's face derivation (OA.Clipper.makeModel in js/oa.clipper.js), exact: walls, holes, pulls and top faces.
#include "popcut/model/oa_card.h"

#include <CGAL/Boolean_set_operations_2.h>

#include <algorithm>
#include <limits>
#include <map>
#include <memory>

#include "model/exact_faces.h"
#include "model/oa_faces.h"
#include "popcut/text.h"

namespace popcut {
using namespace detail;

namespace {

// A set of pattern regions (x, v) in nm, the plane they lie in, and the .oa faces that drew them.
struct Layer {
  FT t_nm;                  // depth of a wall, height of a top face
  bool expolygons = false;  // the first face of this depth was text: top edges only
  PolygonSet region;
  std::vector<std::size_t> faces;  // indices into OaCard::faces, for messages
};

// Walls by depth, top faces by height: merging a face into its plane is a look-up, not a scan.
using Layers = std::map<FT, Layer>;

// A top edge (webOAcard's "upper"): a horizontal boundary edge with its face below it.
struct Upper {
  FT v_nm, x_min_nm, x_max_nm, t_nm;  // the edge at pattern height v from x_min to x_max, of a wall at depth t
  bool in_hole = false;               // on a hole's ring: its top face may spread across the card
  std::shared_ptr<const std::vector<std::size_t>> faces;  // the wall's .oa faces
};

struct Card {
  FT width_nm, half_nm;
  ExactPolygon rect(const FT& v0_nm, const FT& v1_nm) const { return rectangle(0, v0_nm, width_nm, v1_nm); }
};

std::string mm_text(const FT& nm) { return format_significant(to_mm(nm)); }

CGAL::Bbox_2 bbox_of(const PolygonSet& s) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  CGAL::Bbox_2 box(kInf, kInf, -kInf, -kInf);
  for (auto v = s.arrangement().vertices_begin(); v != s.arrangement().vertices_end(); ++v) box += v->point().bbox();
  return box;
}

// A contour's outer ring minus its holes, in pattern coordinates (X, -Y).
PolygonSet contour_region(const OaContour& c, const std::string& source, const std::string& where) {
  const auto pattern = [](const Ring& r) {
    Ring out;
    out.reserve(r.size());
    for (const Point2& p : r) out.push_back({p.x_mm, -p.v_mm});
    return out;
  };
  PolygonSet region(exact_polygon(pattern(c.outer), source, where + ".outer"));
  for (std::size_t h = 0; h < c.holes.size(); ++h) {
    region.difference(
        exact_polygon(pattern(c.holes[h]), source, where + ".holes[" + std::to_string(c.hole_index[h]) + "]"));
  }
  return region;
}

// clipBoundary: the face on the card and above the floor (z = t - Y >= 0, i.e. v >= -t).
PolygonSet face_region(const OaFace& f, const Card& card, const std::string& source) {
  PolygonSet region;
  for (std::size_t i = 0; i < f.contours.size(); ++i)
    region.join(contour_region(f.contours[i], source, f.where + ".contours[" + std::to_string(i) + "]"));
  region.intersection(card.rect(-card.half_nm, card.half_nm));
  if (region.is_empty()) {
    fail(source, f.where + ".contours",
         "lies outside the card (X from 0 to " + mm_text(card.width_nm) + " mm, Y from -" + mm_text(card.half_nm) +
             " to " + mm_text(card.half_nm) + " mm)");
  }
  const FT t_nm = exact_nm(f.t_mm);
  region.intersection(card.rect(std::max(-t_nm, -card.half_nm), card.half_nm));
  if (region.is_empty()) fail(source, f.where + ".contours", "lies below the floor: every point has Y > t");
  return region;
}

// Layers of one depth are one face (tryMergeFaces); the first keeps its kind of contours.
void merge_into(Layers& layers, Layer layer) {
  const auto [it, added] = layers.try_emplace(layer.t_nm, std::move(layer));
  if (added) return;
  it->second.region.join(layer.region);
  it->second.faces.insert(it->second.faces.end(), layer.faces.begin(), layer.faces.end());
}

// Cuts the hole from the layer unless their boxes are apart; true when nothing is left of it.
bool cut(Layer& l, const Layer& hole, const CGAL::Bbox_2& hole_box) {
  if (!CGAL::do_overlap(bbox_of(l.region), hole_box)) return false;
  l.region.difference(hole.region);
  return l.region.is_empty();
}

// A hole cuts every layer at its depth or behind it (t <= the hole's); layers left empty go.
void cut_hole(Layers& layers, const Layer& hole) {
  const CGAL::Bbox_2 box = bbox_of(hole.region);
  for (auto it = layers.begin(); it != layers.upper_bound(hole.t_nm);)
    it = cut(it->second, hole, box) ? layers.erase(it) : std::next(it);
}

void cut_hole(std::vector<Layer>& layers, const Layer& hole) {
  const CGAL::Bbox_2 box = bbox_of(hole.region);
  std::erase_if(layers, [&](Layer& l) { return l.t_nm <= hole.t_nm && cut(l, hole, box); });
}

std::vector<ExactPolygonWithHoles> pieces(const PolygonSet& s) {
  std::vector<ExactPolygonWithHoles> out;
  s.polygons_with_holes(std::back_inserter(out));
  return out;
}

// Horizontal edges running towards -x (the face lies below them: left of the edge), merged where
// consecutive, as webOAcard's Clipper output has no collinear vertices.
std::vector<Upper> ring_uppers(const ExactPolygon& ring, const Layer& layer, bool in_hole) {
  std::vector<Upper> out;
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const ExactPoint& p = ring[i];
    const ExactPoint& q = ring[(i + 1) % n];
    if (p.y() != q.y() || q.x() >= p.x()) continue;
    out.push_back({p.y(), q.x(), p.x(), layer.t_nm, in_hole, nullptr});
  }
  std::sort(out.begin(), out.end(), [](const Upper& a, const Upper& b) {
    return a.v_nm != b.v_nm ? a.v_nm < b.v_nm : a.x_min_nm < b.x_min_nm;
  });
  std::vector<Upper> merged;
  for (const Upper& u : out) {
    if (!merged.empty() && merged.back().v_nm == u.v_nm && merged.back().x_max_nm == u.x_min_nm)
      merged.back().x_max_nm = u.x_max_nm;
    else
      merged.push_back(u);
  }
  return merged;
}

// updateUpperLower2Ds: every top edge of the outer rings and holes; text (expolygons) only the
// topmost edges of each outer ring; a pull only those of its holes (its outer ones are "invalid").
void add_uppers(const Layer& layer, bool outer_edges, std::vector<Upper>& out) {
  const auto faces = std::make_shared<const std::vector<std::size_t>>(layer.faces);
  const std::size_t first = out.size();
  for (const ExactPolygonWithHoles& p : pieces(layer.region)) {
    std::vector<Upper> outer = ring_uppers(p.outer_boundary(), layer, false);
    if (layer.expolygons && !outer.empty()) {
      const FT top = std::max_element(outer.begin(), outer.end(), [](const Upper& a, const Upper& b) {
                       return a.v_nm < b.v_nm;
                     })->v_nm;
      std::erase_if(outer, [&](const Upper& u) { return u.v_nm != top; });
    }
    if (outer_edges) out.insert(out.end(), outer.begin(), outer.end());
    if (layer.expolygons) continue;
    for (const ExactPolygon& h : p.holes()) {
      const std::vector<Upper> hole = ring_uppers(h, layer, true);
      out.insert(out.end(), hole.begin(), hole.end());
    }
  }
  for (std::size_t i = first; i < out.size(); ++i) out[i].faces = faces;
}

// getConnectedPoly: the pieces with an outer vertex on the edge's line within its extent.
PolygonSet touching(const PolygonSet& s, const Upper& e) {
  PolygonSet out;
  for (const ExactPolygonWithHoles& p : pieces(s)) {
    const ExactPolygon& o = p.outer_boundary();
    if (std::any_of(o.vertices_begin(), o.vertices_end(), [&](const ExactPoint& q) {
          return q.y() == e.v_nm && e.x_min_nm <= q.x() && q.x() <= e.x_max_nm;
        })) {
      out.join(p);
    }
  }
  return out;
}

struct Boxed {
  const Layer* layer;
  CGAL::Bbox_2 box;
};

// createHFaces for one edge: a top face from the edge back to the back board (a hole's edge
// across the whole card), less every wall in front or at its depth, and less every wall behind
// where that wall stands above the top face's height; the pieces still on the edge. Walls whose
// boxes miss the top face's cannot change it.
Layer top_face(const Upper& e, const std::vector<Boxed>& walls, const Card& card) {
  const bool wide = e.in_hole;
  const ExactPolygon strip =
      rectangle(wide ? FT(0) : e.x_min_nm, e.v_nm, wide ? card.width_nm : e.x_max_nm, e.v_nm + e.t_nm);
  const CGAL::Bbox_2 box = strip.bbox();
  PolygonSet region(strip);
  for (const Boxed& w : walls) {
    if (!CGAL::do_overlap(w.box, box)) continue;
    if (w.layer->t_nm >= e.t_nm) {
      region.difference(w.layer->region);
    } else {
      PolygonSet above = w.layer->region;
      above.difference(rectangle(e.x_min_nm, e.v_nm, e.x_max_nm, e.v_nm + (e.t_nm - w.layer->t_nm)));
      region.difference(above);
    }
  }
  return {e.v_nm + e.t_nm, false, touching(region, e), *e.faces};
}

// "faces[3]", "faces[3], faces[5]", "faces[3], faces[5], faces[8] and 4 more".
std::string faces_text(const std::vector<std::size_t>& faces) {
  std::string out;
  for (std::size_t i = 0; i < faces.size() && i < 3; ++i)
    out += (i ? ", faces[" : "faces[") + std::to_string(faces[i]) + "]";
  if (faces.size() > 3) out += " and " + std::to_string(faces.size() - 3) + " more";
  return out;
}

// What made a wall layer: "faces[3] (a wall at t = 24 mm)", "faces[3], faces[5] (walls and pulls at t = 24 mm)".
std::string wall_name(const Layer& l, const OaCard& oa) {
  const auto pulls =
      std::count_if(l.faces.begin(), l.faces.end(), [&](std::size_t i) { return oa.faces[i].mode == OaMode::pull; });
  const bool one = l.faces.size() == 1;
  const std::string what = pulls == 0                                          ? (one ? "a wall" : "walls")
                           : static_cast<std::size_t>(pulls) == l.faces.size() ? (one ? "a pull" : "pulls")
                                                                               : "walls and pulls";
  return faces_text(l.faces) + " (" + what + " at t = " + mm_text(l.t_nm) + " mm)";
}

std::string top_name(const Layer& l) {
  return "the top face of " + faces_text(l.faces) + " (at z = " + mm_text(l.t_nm) + " mm)";
}

// Each layer's region less what a later (higher) layer or `over` covers, emitted as pieces. Only
// the covers whose boxes meet a layer's are united for it, in one aggregated union.
template <typename Name>
void emit(const Layers& layers, FaceKind kind, std::vector<ExactPolygonWithHoles> over, Name name,
          std::vector<OaPiece>& out) {
  std::vector<CGAL::Bbox_2> boxes;
  for (const ExactPolygonWithHoles& p : over) boxes.push_back(p.outer_boundary().bbox());
  for (auto it = layers.rbegin(); it != layers.rend(); ++it) {
    const Layer& l = it->second;
    const CGAL::Bbox_2 box = bbox_of(l.region);
    std::vector<ExactPolygonWithHoles> near;
    for (std::size_t i = 0; i < over.size(); ++i)
      if (CGAL::do_overlap(boxes[i], box)) near.push_back(over[i]);
    PolygonSet shown = l.region, cover;
    cover.join(near.begin(), near.end());
    shown.difference(cover);
    const std::string drawn_by = name(l);
    for (const ExactPolygonWithHoles& p : pieces(shown))
      for (ExactPolygonWithHoles& lobe : split_lobes(p)) out.push_back({kind, l.t_nm, std::move(lobe), drawn_by});
    for (ExactPolygonWithHoles& p : pieces(l.region)) {
      boxes.push_back(p.outer_boundary().bbox());
      over.push_back(std::move(p));
    }
  }
}

std::vector<ExactPolygonWithHoles> all_pieces(const Layers& layers) {
  std::vector<ExactPolygonWithHoles> out;
  for (const auto& [t, l] : layers) l.region.polygons_with_holes(std::back_inserter(out));
  return out;
}

// The drawn faces sorted by mode, each clipped to the card; walls of a depth merged (pulls merge
// into them only after their top edges are found, as webOAcard's makeModel does).
struct Drawn {
  Layers walls;
  std::vector<Layer> pulls, holes, forced_holes;
};

Drawn read_faces(const OaCard& oa, const Card& card, const std::string& source) {
  Drawn d;
  for (std::size_t i = 0; i < oa.faces.size(); ++i) {
    const OaFace& f = oa.faces[i];
    Layer l{exact_nm(f.t_mm), f.expolygons, face_region(f, card, source), {i}};
    switch (f.mode) {
      case OaMode::wall: merge_into(d.walls, std::move(l)); break;
      case OaMode::pull: d.pulls.push_back(std::move(l)); break;
      case OaMode::hole: (f.expolygons ? d.forced_holes : d.holes).push_back(std::move(l)); break;
    }
  }
  return d;
}

// makeModel: walls and pulls cut by holes, top faces from their edges, forced (text) holes last.
Layers derive(Drawn& d, const Card& card) {
  for (const Layer& hole : d.holes) {
    cut_hole(d.walls, hole);
    cut_hole(d.pulls, hole);
  }
  std::vector<Upper> uppers;
  for (const auto& [t, w] : d.walls) add_uppers(w, true, uppers);
  for (const Layer& p : d.pulls) add_uppers(p, false, uppers);
  for (Layer& p : d.pulls) merge_into(d.walls, std::move(p));
  std::vector<Boxed> walls;
  for (const auto& [t, w] : d.walls) walls.push_back({&w, bbox_of(w.region)});
  Layers tops;
  for (const Upper& e : uppers) {
    if (e.t_nm == 0) continue;  // a wall on the back board has no depth to roof
    Layer top = top_face(e, walls, card);
    if (!top.region.is_empty()) merge_into(tops, std::move(top));
  }
  for (const Layer& hole : d.forced_holes) {
    cut_hole(d.walls, hole);
    cut_hole(tops, hole);  // webOAcard compares a top face's height with the hole's depth
  }
  for (auto& [h, top] : tops) {
    top.region.intersection(card.rect(-card.half_nm, card.half_nm));
    std::sort(top.faces.begin(), top.faces.end());
    top.faces.erase(std::unique(top.faces.begin(), top.faces.end()), top.faces.end());
  }
  std::erase_if(tops, [](const auto& kv) { return kv.second.region.is_empty(); });
  return tops;
}

}  // namespace

FaceModel face_model_from_oa(const OaCard& oa, const std::string& source) {
  const Card card{exact_nm(oa.width_mm), exact_nm(oa.half_height_mm)};
  const std::vector<OaPiece> faces = guarded(source, "faces", [&] {
    Drawn d = read_faces(oa, card, source);
    const Layers tops = derive(d, card);
    std::vector<ExactPolygonWithHoles> covered = all_pieces(d.walls), roofs = all_pieces(tops);
    covered.insert(covered.end(), roofs.begin(), roofs.end());
    std::vector<OaPiece> out;
    Layers board;
    board[FT(0)] = Layer{FT(0), false, PolygonSet(card.rect(0, card.half_nm)), {}};
    emit(
        board, FaceKind::vertical, covered, [](const Layer&) { return std::string("the back board"); }, out);
    board[FT(0)].region = PolygonSet(card.rect(-card.half_nm, 0));
    emit(
        board, FaceKind::horizontal, covered, [](const Layer&) { return std::string("the floor"); }, out);
    emit(
        d.walls, FaceKind::vertical, roofs, [&](const Layer& l) { return wall_name(l, oa); }, out);
    emit(tops, FaceKind::horizontal, {}, top_name, out);
    return out;
  });
  return oa_face_model(faces, oa.width_mm, oa.half_height_mm, source);
}

}  // namespace popcut
