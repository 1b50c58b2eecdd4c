// Face model → typed lines and fold links from the exact map of face boundaries (polygon paper Fig. 10).
#include "popcut/pattern/face_pattern.h"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Polygon_set_2.h>

#include <algorithm>
#include <numeric>
#include <cmath>
#include <map>

#include "model/face_model_state.h"
#include "pattern/face_map.h"
#include "popcut/error.h"
#include "popcut/text.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
using namespace detail;

namespace {

using PolygonSet = CGAL::Polygon_set_2<Kernel>;

// One stretch of boundary between consecutive vertices on a line, with the face on each side.
struct Piece {
  ExactPoint a, b;       // a before b in (x, v) order
  int left = -1;         // face left of a→b (above a horizontal piece); -1: outside the sheet
  int right = -1;        // face on the other side
  int kind = -1;         // LineKind once typed; -1: no line (outline, or inside one face)
  std::size_t line = 0;  // which supporting line: pieces of one line are consecutive, in order
  int dir = 0;           // the line: 0 v constant (= key), 1 x constant (= key), 2 slanted
  FT key;
};

// One edge of a face's ring, ends in (x, v) order, with the line it lies on as keys.
struct Edge {
  ExactPoint lo, hi;
  int face;
  bool face_left;  // face lies left of lo→hi
  int dir;         // 0: v constant, 1: x constant, 2: slanted
  FT key, key2;    // v, x, or slope and intercept
};

// Every ring edge of every face. Vertices are read in place and coordinates taken once per edge:
// with lazy exact numbers, every constructed segment or coordinate is an allocation.
std::vector<Edge> face_edges(const std::vector<std::shared_ptr<const ExactFace>>& faces) {
  std::vector<Edge> edges;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto add_ring = [&](const ExactPolygon& ring) {
      const auto& v = ring.container();
      for (std::size_t k = 0; k < v.size(); ++k) {
        const ExactPoint& from = v[k];
        const ExactPoint& to = v[k + 1 == v.size() ? 0 : k + 1];
        const bool forward = CGAL::compare_xy(from, to) == CGAL::SMALLER;
        Edge edge{forward ? from : to, forward ? to : from, static_cast<int>(i), forward, 0, 0, 0};
        if (CGAL::compare_y(from, to) == CGAL::EQUAL) {
          edge.key = from.y();
        } else if (CGAL::compare_x(from, to) == CGAL::EQUAL) {
          edge.dir = 1;
          edge.key = from.x();
        } else {
          edge.dir = 2;
          edge.key = (edge.hi.y() - edge.lo.y()) / (edge.hi.x() - edge.lo.x());
          edge.key2 = edge.lo.y() - edge.key * edge.lo.x();
        }
        edges.push_back(std::move(edge));  // rings run with their face on the left (outer CCW, holes CW)
      }
    };
    add_ring(faces[i]->polygon.outer_boundary());
    for (const ExactPolygon& h : faces[i]->polygon.holes()) add_ring(h);
  }
  return edges;
}

// Edges of one line made consecutive. Sorted by index (an Edge is four lazy handles to move) on
// keys kept beside it: where a key's interval is one double that double is its exact value, and
// two such compare without touching the lazy numbers at all.
void sort_by_line(std::vector<Edge>& edges) {
  struct SortKey {
    int dir;
    bool exact;  // both keys are doubles exactly
    double key, key2;
  };
  std::vector<SortKey> keys;
  keys.reserve(edges.size());
  for (const Edge& e : edges) {
    const auto &k = e.key.approx(), &k2 = e.key2.approx();
    keys.push_back({e.dir, k.is_point() && k2.is_point(), k.inf(), k2.inf()});
  }
  std::vector<std::size_t> order(edges.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    const SortKey& a = keys[i];
    const SortKey& b = keys[j];
    if (a.dir != b.dir) return a.dir < b.dir;
    if (a.exact && b.exact) return a.key != b.key ? a.key < b.key : a.key2 < b.key2;
    const CGAL::Comparison_result c = CGAL::compare(edges[i].key, edges[j].key);
    return c != CGAL::EQUAL ? c == CGAL::SMALLER : CGAL::compare(edges[i].key2, edges[j].key2) == CGAL::SMALLER;
  });
  std::vector<Edge> sorted;
  sorted.reserve(edges.size());
  for (const std::size_t i : order) sorted.push_back(std::move(edges[i]));
  edges = std::move(sorted);
}

// Polygon paper Fig. 10: a boundary edge that another face's edge shares only in part is split
// at that edge's endpoints. Faces that partition the sheet never cross (eq. 4), so every vertex
// of the map lies on a line through collinear edges; splitting each supporting line at all the
// endpoints on it gives exactly the edges of the arrangement of all face boundaries, each with
// its two faces (the half-edge pair of the cut-sheet paper, §3), without a general intersection sweep.
std::vector<Piece> split_shared_edges(const std::vector<std::shared_ptr<const ExactFace>>& faces,
                                      const std::string& source) {
  std::vector<Edge> edges = face_edges(faces);
  sort_by_line(edges);
  const auto same_line = [](const Edge& a, const Edge& b) {
    return a.dir == b.dir && a.key == b.key && a.key2 == b.key2;
  };
  std::vector<Piece> pieces;
  std::vector<ExactPoint> stops;
  const auto before = [](const ExactPoint& p, const ExactPoint& q) { return CGAL::compare_xy(p, q) == CGAL::SMALLER; };
  std::size_t line = 0;
  for (std::size_t g = 0; g < edges.size(); ++line) {
    std::size_t end = g + 1;
    while (end < edges.size() && same_line(edges[g], edges[end])) ++end;
    stops.clear();
    for (std::size_t k = g; k < end; ++k) {
      stops.push_back(edges[k].lo);
      stops.push_back(edges[k].hi);
    }
    std::sort(stops.begin(), stops.end(), before);
    stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
    const std::size_t first = pieces.size();
    for (std::size_t k = 0; k + 1 < stops.size(); ++k) {
      pieces.push_back({stops[k], stops[k + 1], -1, -1, -1, line, edges[g].dir, edges[g].key});
    }
    for (std::size_t k = g; k < end; ++k) {
      const Edge& e = edges[k];
      const auto from = std::lower_bound(stops.begin(), stops.end(), e.lo, before) - stops.begin();
      const auto to = std::lower_bound(stops.begin(), stops.end(), e.hi, before) - stops.begin();
      for (auto at = from; at < to; ++at) {
        Piece& piece = pieces[first + static_cast<std::size_t>(at)];
        int& slot = e.face_left ? piece.left : piece.right;
        if (slot >= 0 && slot != e.face) {
          throw Error(ErrorCode::invalid_input, source, "faces",
                      "faces " + std::to_string(slot) + " and " + std::to_string(e.face) + " overlap (eq. 4)");
        }
        slot = e.face;
      }
    }
    // Stretches between edges that no face borders are not part of the map.
    pieces.erase(std::remove_if(pieces.begin() + static_cast<std::ptrdiff_t>(first), pieces.end(),
                                [](const Piece& p) { return p.left < 0 && p.right < 0; }),
                 pieces.end());
    g = end;
  }
  return pieces;
}

// Coplanar faces across an edge (not just a corner) are one piece of paper, so they are merged
// into one face with no line between; `groups` learns which input faces meet so.
std::vector<std::shared_ptr<const ExactFace>> merged_faces(const std::vector<std::shared_ptr<const ExactFace>>& input,
                                                           const std::vector<Piece>& pieces, CoplanarGroups& groups,
                                                           const std::string& source) {
  for (const Piece& pc : pieces) {
    if (pc.left >= 0 && pc.right >= 0) groups.meet(pc.left, pc.right);
  }
  std::vector<std::shared_ptr<const ExactFace>> faces;
  for (const std::vector<int>& group : groups.members()) {
    const ExactFace& first = *input[static_cast<std::size_t>(group.front())];
    if (group.size() == 1) {
      faces.push_back(input[static_cast<std::size_t>(group.front())]);
      continue;
    }
    // One aggregated join per plane (a sweep), not one Boolean per member.
    std::vector<ExactPolygonWithHoles> parts;
    bool opening_paper = true;  // merged with other paper, it is held with it
    for (int f : group) {
      parts.push_back(input[static_cast<std::size_t>(f)]->polygon);
      opening_paper = opening_paper && input[static_cast<std::size_t>(f)]->opening_paper;
    }
    PolygonSet set;
    set.join(parts.begin(), parts.end());
    std::vector<ExactPolygonWithHoles> joined;
    set.polygons_with_holes(std::back_inserter(joined));
    if (joined.size() != 1)
      throw Error(ErrorCode::internal, source, "faces", "faces joined by an edge did not merge into one");
    faces.push_back(std::make_shared<const ExactFace>(
        ExactFace{first.kind, first.t, std::move(joined.front()), {}, opening_paper}));
  }
  return faces;
}

// How much of the sheet's top and bottom edges each face holds.
struct EdgeLengths {
  std::map<int, FT> top, bottom;
};

// Types every piece by where its two faces meet in 3D (pieces' faces renumbered to the merged
// faces), adding the folds to `p`; pieces on the sheet's outline count towards `edges`.
EdgeLengths type_pieces(std::vector<Piece>& pieces, CoplanarGroups& groups,
                        const std::vector<std::shared_ptr<const ExactFace>>& faces, const FaceModelState& s, Pattern& p,
                        const std::string& source) {
  EdgeLengths edges;
  std::map<std::pair<int, int>, std::size_t> link_index;
  for (Piece& pc : pieces) {
    if (pc.left >= 0) pc.left = groups.group_of(pc.left);
    if (pc.right >= 0) pc.right = groups.group_of(pc.right);
    const ExactPoint& a = pc.a;
    const ExactPoint& b = pc.b;
    const bool horizontal = pc.dir == 0;
    if (pc.left < 0 || pc.right < 0) {
      const bool on_outline = (horizontal && (pc.key == s.max_v || pc.key == s.min_v)) ||
                              (pc.dir == 1 && (pc.key == s.min_x || pc.key == s.max_x));
      if (!on_outline) {
        throw Error(ErrorCode::invalid_input, source, "faces",
                    "no face covers the sheet beside (" + std::to_string(to_point2(a).x_mm) + ", " +
                        std::to_string(to_point2(a).v_mm) + "): faces must cover the sheet (eq. 4)");
      }
      if (horizontal && pc.key == s.max_v && pc.right >= 0) edges.top[pc.right] += b.x() - a.x();
      if (horizontal && pc.key == s.min_v && pc.left >= 0) edges.bottom[pc.left] += b.x() - a.x();
      continue;
    }
    if (pc.left == pc.right) continue;  // inside one merged face: no line
    const LineKind kind = line_between(*faces[static_cast<std::size_t>(pc.left)],
                                       *faces[static_cast<std::size_t>(pc.right)], horizontal, pc.key);
    pc.kind = static_cast<int>(kind);
    if (kind != LineKind::cut) {
      auto [it, fresh] = link_index.emplace(std::make_pair(pc.left, pc.right), p.folds.size());
      if (fresh) p.folds.push_back({pc.left, pc.right, kind, 0});
      p.folds[it->second].length_mm += to_mm(b.x() - a.x());
    }
  }
  return edges;
}

// Maximal lines: runs of touching pieces of one kind along one supporting line.
void add_maximal_lines(const std::vector<Piece>& pieces, Pattern& p) {
  for (std::size_t k = 0; k < pieces.size();) {
    const Piece& start = pieces[k];
    std::size_t end = k + 1;
    if (start.kind >= 0) {
      while (end < pieces.size() && pieces[end].line == start.line && pieces[end].kind == start.kind &&
             pieces[end].a == pieces[end - 1].b) {
        ++end;
      }
      const ExactPoint& lo = start.a;
      const ExactPoint& hi = pieces[end - 1].b;
      p.lines.push_back({static_cast<LineKind>(start.kind), to_point2(lo), to_point2(hi)});
    }
    k = end;
  }
}

// The face holding most of an edge, the first of equals; -1 for none.
int longest(const std::map<int, FT>& lengths) {
  int best = -1;
  FT best_len = -1;
  for (const auto& [f, len] : lengths) {
    if (len > best_len) {
      best = f;
      best_len = len;
    }
  }
  return best;
}

}  // namespace

Pattern make_pattern(const FaceModel& model, const std::string& source) {
  const FaceModelState& s = model.state();
  try {
    const auto& input = s.faces;  // shared with the model, read in place
    std::vector<Piece> pieces = split_shared_edges(input, source);
    CoplanarGroups groups(input);
    const std::vector<std::shared_ptr<const ExactFace>> faces = merged_faces(input, pieces, groups, source);
    Pattern p;
    p.sheet = model.sheet();
    for (const auto& fp : faces) {
      const ExactFace& f = *fp;
      PatternFace pf{f.kind, to_mm(f.t), to_ring(f.polygon.outer_boundary()), {}, {}};
      for (const ExactPolygon& h : f.polygon.holes()) pf.holes.push_back(to_ring(h));
      pf.label = interior_point(pf.outer, pf.holes);
      pf.opening_paper = f.opening_paper;
      p.faces.push_back(std::move(pf));
    }
    const EdgeLengths edges = type_pieces(pieces, groups, faces, s, p, source);
    add_maximal_lines(pieces, p);
    sort_lines_and_folds(p);
    // The back board and floor: the faces holding most of the sheet's top and bottom edges.
    p.back_face = longest(edges.top);
    p.floor_face = longest(edges.bottom);
    return p;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(ErrorCode::internal, source, "pattern", std::string("geometry kernel failure: ") + e.what());
  }
}

void require_attached(const FaceModel& model, const Pattern& pattern, const PopupReport& report,
                      const std::string& source) {
  if (report.loose_pieces.empty()) return;
  const LoosePiece& piece = report.loose_pieces.front();
  const PatternFace& face = pattern.faces.at(static_cast<std::size_t>(piece.faces.front()));
  const auto mm = [](double v) { return format_decimal(v, 2); };
  std::string message = "leaves a piece cut free of the sheet (" + std::to_string(piece.faces.size()) +
                        (piece.faces.size() == 1 ? " face" : " faces") + ", x " + mm(piece.bounds.min.x_mm) + " to " +
                        mm(piece.bounds.max.x_mm) + " mm, v " + mm(piece.bounds.min.v_mm) + " to " +
                        mm(piece.bounds.max.v_mm) + " mm, " + mm(piece.area_mm2) +
                        " mm²): no fold joins it to the back board or the floor, so it "
                        "would fall out; give it a face that meets the card along a fold";
  if (report.loose_pieces.size() > 1)
    message += " (" + std::to_string(report.loose_pieces.size() - 1) + " more loose pieces)";
  throw Error(ErrorCode::invalid_input, source, model.drawn_by(face.label), message);
}

FaceModel to_face_model(const VoxelModel& model, const std::string& source) {
  const Pattern p = make_pattern(model, source);
  // Every coordinate is a whole number of voxels. Face models snap lengths to 1 nm, so a voxel
  // size with endless decimals (120/42 mm) would snap t_h, t_v and v apart and lose folds;
  // rebuilding each length from its voxel count and one snapped voxel size keeps them exact.
  const double voxel = model.voxel_mm;
  const double snapped = std::round(voxel * kNmPerMm) / kNmPerMm;
  const auto whole = [&](double mm) { return std::round(mm / voxel) * snapped; };
  const auto ring = [&](const Ring& r) {
    Ring out;
    out.reserve(r.size());
    for (const Point2& q : r) out.push_back({whole(q.x_mm), whole(q.v_mm)});
    return out;
  };
  std::vector<OAFace> faces;
  faces.reserve(p.faces.size());
  for (const PatternFace& f : p.faces) {
    OAFace face{f.kind, whole(f.t_mm), {ring(f.outer), {}}};
    for (const Ring& h : f.holes) face.polygon.holes.push_back(ring(h));
    faces.push_back(std::move(face));
  }
  return FaceModel::from_faces(whole(p.sheet.max.x_mm - p.sheet.min.x_mm), whole(p.sheet.max.v_mm),
                               whole(-p.sheet.min.v_mm), faces, source);
}

}  // namespace popcut
