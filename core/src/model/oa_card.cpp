// webOAcard's face derivation (OA.Clipper.makeModel in js/oa.clipper.js), exact: walls, holes, pulls and top faces.
#include "popcut/model/oa_card.h"

#include <CGAL/Boolean_set_operations_2.h>

#include <algorithm>
#include <cmath>

#include "model/exact_faces.h"
#include "popcut/text.h"

namespace popcut {
using namespace detail;

namespace {

// A set of pattern regions (x, v) in nm, and the plane they lie in.
struct Layer {
  FT t;                     // depth of a wall, height of a top face
  bool expolygons = false;  // the first face of this depth was text: top edges only
  PolygonSet region;
};

// A top edge (webOAcard's "upper"): a horizontal boundary edge with its face below it.
struct Upper {
  FT v, x_min, x_max, t;  // the edge at pattern height v from x_min to x_max, of a wall at depth t
  bool in_hole = false;   // on a hole's ring: its top face may spread across the card
};

struct Card {
  FT width, half;
  ExactPolygon rect(const FT& v0, const FT& v1) const { return rectangle(0, v0, width, v1); }
};

std::string mm_text(const FT& nm) { return format_significant(to_mm(nm)); }

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
    region.difference(exact_polygon(pattern(c.holes[h]), source, where + ".holes[" + std::to_string(h) + "]"));
  }
  return region;
}

// clipBoundary: the face on the card and above the floor (z = t - Y >= 0, i.e. v >= -t).
PolygonSet face_region(const OaFace& f, const Card& card, const std::string& source) {
  PolygonSet region;
  for (std::size_t i = 0; i < f.contours.size(); ++i)
    region.join(contour_region(f.contours[i], source, f.where + ".contours[" + std::to_string(i) + "]"));
  region.intersection(card.rect(-card.half, card.half));
  if (region.is_empty()) {
    fail(source, f.where + ".contours",
         "lies outside the card (X from 0 to " + mm_text(card.width) + " mm, Y from -" + mm_text(card.half) + " to " +
             mm_text(card.half) + " mm)");
  }
  const FT t = exact_nm(f.t_mm);
  region.intersection(card.rect(std::max(-t, -card.half), card.half));
  if (region.is_empty()) fail(source, f.where + ".contours", "lies below the floor: every point has Y > t");
  return region;
}

// Layers of one depth are one face (tryMergeFaces); the first keeps its kind of contours.
void merge_into(std::vector<Layer>& layers, Layer layer) {
  for (Layer& l : layers) {
    if (l.t == layer.t) {
      l.region.join(layer.region);
      return;
    }
  }
  layers.push_back(std::move(layer));
}

// A hole cuts every layer at its depth or behind it; layers left empty go.
void cut_hole(std::vector<Layer>& layers, const Layer& hole) {
  for (Layer& l : layers)
    if (l.t <= hole.t) l.region.difference(hole.region);
  layers.erase(std::remove_if(layers.begin(), layers.end(), [](const Layer& l) { return l.region.is_empty(); }),
               layers.end());
}

std::vector<ExactPolygonWithHoles> pieces(const PolygonSet& s) {
  std::vector<ExactPolygonWithHoles> out;
  s.polygons_with_holes(std::back_inserter(out));
  return out;
}

// Horizontal edges running towards -x (the face lies below them: left of the edge), merged where
// consecutive, as webOAcard's Clipper output has no collinear vertices.
std::vector<Upper> ring_uppers(const ExactPolygon& ring, const FT& t, bool in_hole) {
  std::vector<Upper> out;
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const ExactPoint& p = ring[i];
    const ExactPoint& q = ring[(i + 1) % n];
    if (p.y() != q.y() || q.x() >= p.x()) continue;
    out.push_back({p.y(), q.x(), p.x(), t, in_hole});
  }
  std::sort(out.begin(), out.end(),
            [](const Upper& a, const Upper& b) { return a.v != b.v ? a.v < b.v : a.x_min < b.x_min; });
  std::vector<Upper> merged;
  for (const Upper& u : out) {
    if (!merged.empty() && merged.back().v == u.v && merged.back().x_max == u.x_min)
      merged.back().x_max = u.x_max;
    else
      merged.push_back(u);
  }
  return merged;
}

// updateUpperLower2Ds: every top edge of the outer rings and holes; text (expolygons) only the
// topmost edges of each outer ring; a pull only those of its holes (its outer ones are "invalid").
std::vector<Upper> layer_uppers(const Layer& layer, bool outer_edges) {
  std::vector<Upper> out;
  for (const ExactPolygonWithHoles& p : pieces(layer.region)) {
    std::vector<Upper> outer = ring_uppers(p.outer_boundary(), layer.t, false);
    if (layer.expolygons && !outer.empty()) {
      const FT top =
          std::max_element(outer.begin(), outer.end(), [](const Upper& a, const Upper& b) { return a.v < b.v; })->v;
      std::erase_if(outer, [&](const Upper& u) { return u.v != top; });
    }
    if (outer_edges) out.insert(out.end(), outer.begin(), outer.end());
    if (layer.expolygons) continue;
    for (const ExactPolygon& h : p.holes()) {
      const std::vector<Upper> hole = ring_uppers(h, layer.t, true);
      out.insert(out.end(), hole.begin(), hole.end());
    }
  }
  return out;
}

// getConnectedPoly: the pieces with an outer vertex on the edge's line within its extent.
PolygonSet touching(const PolygonSet& s, const Upper& e) {
  PolygonSet out;
  for (const ExactPolygonWithHoles& p : pieces(s)) {
    const ExactPolygon& o = p.outer_boundary();
    if (std::any_of(o.vertices_begin(), o.vertices_end(),
                    [&](const ExactPoint& q) { return q.y() == e.v && e.x_min <= q.x() && q.x() <= e.x_max; })) {
      out.join(p);
    }
  }
  return out;
}

// createHFaces for one edge: a top face from the edge back to the back board (a hole's edge
// across the whole card), less every wall in front or at its depth, and less every wall behind
// where that wall stands above the top face's height; the pieces still on the edge.
Layer top_face(const Upper& e, const std::vector<Layer>& walls, const Card& card) {
  const bool wide = e.in_hole;
  PolygonSet region(rectangle(wide ? FT(0) : e.x_min, e.v, wide ? card.width : e.x_max, e.v + e.t));
  for (const Layer& w : walls) {
    if (w.t >= e.t) {
      region.difference(w.region);
    } else {
      PolygonSet above = w.region;
      above.difference(rectangle(e.x_min, e.v, e.x_max, e.v + (e.t - w.t)));
      region.difference(above);
    }
  }
  return {e.v + e.t, false, touching(region, e)};
}

// A face worked out exactly: its plane and region.
struct Piece {
  FaceKind kind;
  FT t;
  ExactPolygonWithHoles polygon;
};

// From the layers at hand, bottom to top, each face what no later one covers.
void emit(std::vector<Layer>& layers, FaceKind kind, const PolygonSet& over, std::vector<Piece>& out) {
  std::sort(layers.begin(), layers.end(), [](const Layer& a, const Layer& b) { return a.t < b.t; });
  PolygonSet above = over;
  for (std::size_t i = layers.size(); i-- > 0;) {
    PolygonSet shown = layers[i].region;
    shown.difference(above);
    above.join(layers[i].region);
    for (const ExactPolygonWithHoles& p : pieces(shown))
      for (ExactPolygonWithHoles& lobe : split_lobes(p)) out.push_back({kind, layers[i].t, std::move(lobe)});
  }
}

// Every vertex of the faces, to find those lying inside another face's edge: a crossing of two
// slanted edges is off the 1 nm grid, and rounding it in one face but not in the edge it touches
// would open a gap. With the vertex in both rings, both round it alike and the faces still tile.
class VertexIndex {
 public:
  explicit VertexIndex(const std::vector<Piece>& faces) {
    const auto add = [&](const ExactPolygon& ring) {
      for (const ExactPoint& p : ring.container()) v_.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), p});
    };
    for (const Piece& f : faces) {
      add(f.polygon.outer_boundary());
      for (const ExactPolygon& h : f.polygon.holes()) add(h);
    }
    std::sort(v_.begin(), v_.end(), [](const Vertex& a, const Vertex& b) { return a.x < b.x; });
  }

  // The vertices strictly inside segment ab, in order from a.
  std::vector<ExactPoint> inside(const ExactPoint& a, const ExactPoint& b) const {
    constexpr double kSlackNm = 1;  // far above the doubles' error, far below any feature
    const double ax = CGAL::to_double(a.x()), bx = CGAL::to_double(b.x());
    const double ay = CGAL::to_double(a.y()), by = CGAL::to_double(b.y());
    const double y0 = std::min(ay, by) - kSlackNm, y1 = std::max(ay, by) + kSlackNm;
    auto it = std::lower_bound(v_.begin(), v_.end(), std::min(ax, bx) - kSlackNm,
                               [](const Vertex& v, double x) { return v.x < x; });
    std::vector<ExactPoint> out;
    for (; it != v_.end() && it->x <= std::max(ax, bx) + kSlackNm; ++it) {
      if (it->y < y0 || it->y > y1 || it->p == a || it->p == b) continue;
      if (CGAL::collinear(a, b, it->p) && CGAL::collinear_are_strictly_ordered_along_line(a, it->p, b))
        out.push_back(it->p);
    }
    std::sort(out.begin(), out.end(),
              [&](const ExactPoint& p, const ExactPoint& q) { return CGAL::has_smaller_distance_to_point(a, p, q); });
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  struct Vertex {
    double x, y;
    ExactPoint p;
  };
  std::vector<Vertex> v_;
};

double snapped_mm(const FT& nm) { return static_cast<double>(std::llround(CGAL::to_double(nm))) / kNmPerMm; }

// A ring in mm on the 1 nm grid, with every vertex of another face that lies on its edges.
Ring grid_ring(const ExactPolygon& ring, const VertexIndex& index) {
  Ring out;
  const auto put = [&](const ExactPoint& p) {
    const Point2 q{snapped_mm(p.x()), snapped_mm(p.y())};
    if (out.empty() || !(out.back() == q)) out.push_back(q);
  };
  const auto& v = ring.container();
  for (std::size_t i = 0; i < v.size(); ++i) {
    put(v[i]);
    for (const ExactPoint& p : index.inside(v[i], v[(i + 1) % v.size()])) put(p);
  }
  while (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

std::vector<OAFace> grid_faces(const std::vector<Piece>& pieces_in) {
  const VertexIndex index(pieces_in);
  std::vector<OAFace> out;
  out.reserve(pieces_in.size());
  for (const Piece& f : pieces_in) {
    OAFace o{f.kind, to_mm(f.t), {grid_ring(f.polygon.outer_boundary(), index), {}}};
    for (const ExactPolygon& h : f.polygon.holes()) o.polygon.holes.push_back(grid_ring(h, index));
    out.push_back(std::move(o));
  }
  return out;
}

PolygonSet union_of(const std::vector<Layer>& layers) {
  PolygonSet all;
  for (const Layer& l : layers) all.join(l.region);
  return all;
}

// The drawn faces sorted by mode, each clipped to the card; walls and pulls of a depth merged.
struct Drawn {
  std::vector<Layer> walls, pulls, holes, forced_holes;
};

Drawn read_faces(const OaCard& card_in, const Card& card, const std::string& source) {
  Drawn d;
  for (const OaFace& f : card_in.faces) {
    Layer l{exact_nm(f.t_mm), f.expolygons, face_region(f, card, source)};
    switch (f.mode) {
      case OaMode::wall: merge_into(d.walls, std::move(l)); break;
      case OaMode::pull: d.pulls.push_back(std::move(l)); break;
      case OaMode::hole: (f.expolygons ? d.forced_holes : d.holes).push_back(std::move(l)); break;
    }
  }
  return d;
}

// makeModel: walls and pulls cut by holes, top faces from their edges, forced (text) holes last.
void derive(Drawn& d, const Card& card, std::vector<Layer>& tops) {
  for (const Layer& hole : d.holes) {
    cut_hole(d.walls, hole);
    cut_hole(d.pulls, hole);
  }
  std::vector<Upper> uppers;
  for (const Layer& w : d.walls) std::ranges::copy(layer_uppers(w, true), std::back_inserter(uppers));
  for (const Layer& p : d.pulls) std::ranges::copy(layer_uppers(p, false), std::back_inserter(uppers));
  for (Layer& p : d.pulls) merge_into(d.walls, std::move(p));
  for (const Upper& e : uppers) {
    if (e.t == 0) continue;  // a wall on the back board has no depth to roof
    Layer top = top_face(e, d.walls, card);
    if (!top.region.is_empty()) merge_into(tops, std::move(top));
  }
  for (const Layer& hole : d.forced_holes) {
    cut_hole(d.walls, hole);
    cut_hole(tops, hole);  // webOAcard compares a top face's height with the hole's depth
  }
  for (Layer& top : tops) top.region.intersection(card.rect(-card.half, card.half));
}

}  // namespace

FaceModel face_model_from_oa(const OaCard& oa, const std::string& source) {
  const Card card{exact_nm(oa.width_mm), exact_nm(oa.half_height_mm)};
  std::vector<OAFace> faces = guarded(source, "faces", [&] {
    Drawn d = read_faces(oa, card, source);
    std::vector<Layer> tops;
    derive(d, card, tops);
    const PolygonSet hs = union_of(tops);
    PolygonSet covered = union_of(d.walls);
    covered.join(hs);
    std::vector<Piece> out;
    std::vector<Layer> boards;
    boards.push_back({FT(0), false, PolygonSet(card.rect(0, card.half))});
    emit(boards, FaceKind::vertical, covered, out);
    boards.front().region = PolygonSet(card.rect(-card.half, 0));
    emit(boards, FaceKind::horizontal, covered, out);
    emit(d.walls, FaceKind::vertical, hs, out);
    emit(tops, FaceKind::horizontal, PolygonSet(), out);
    return grid_faces(out);
  });
  try {
    // The faces tile the card by construction, every vertex on the grid and shared by the faces
    // that meet there: a subdivision, whose cover from_subdivision still checks.
    return FaceModel::from_subdivision(oa.width_mm, oa.half_height_mm, oa.half_height_mm, faces, source, true);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    throw Error(ErrorCode::internal, source, e.location(), "the derived faces do not tile the card: " + e.message());
  }
}

}  // namespace popcut
