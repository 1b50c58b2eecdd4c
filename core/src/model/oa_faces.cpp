// A webOAcard card's exact faces rounded to the 1 nm grid and checked as a FaceModel, errors naming the .oa faces.
#include "model/oa_faces.h"

#include <algorithm>
#include <cmath>

namespace popcut::detail {
namespace {

// Every vertex of the faces, to find those lying inside another face's edge: a crossing of two
// slanted edges is off the 1 nm grid, and rounding it in one face but not in the edge it touches
// would open a gap. With the vertex in both rings, both round it alike.
class VertexIndex {
 public:
  explicit VertexIndex(const std::vector<OaPiece>& faces) {
    const auto add = [&](const ExactPolygon& ring) {
      for (const ExactPoint& p : ring.container()) by_x_.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), p});
    };
    for (const OaPiece& f : faces) {
      add(f.polygon.outer_boundary());
      for (const ExactPolygon& h : f.polygon.holes()) add(h);
    }
    by_y_ = by_x_;
    std::sort(by_x_.begin(), by_x_.end(), [](const Vertex& a, const Vertex& b) { return a.x < b.x; });
    std::sort(by_y_.begin(), by_y_.end(), [](const Vertex& a, const Vertex& b) { return a.y < b.y; });
  }

  // The vertices strictly inside segment ab, in order from a.
  std::vector<ExactPoint> inside(const ExactPoint& a, const ExactPoint& b) const {
    constexpr double kSlackNm = 1;  // far above the doubles' error, far below any feature
    const double ax = CGAL::to_double(a.x()), bx = CGAL::to_double(b.x());
    const double ay = CGAL::to_double(a.y()), by = CGAL::to_double(b.y());
    const double x0 = std::min(ax, bx) - kSlackNm, x1 = std::max(ax, bx) + kSlackNm;
    const double y0 = std::min(ay, by) - kSlackNm, y1 = std::max(ay, by) + kSlackNm;
    // The narrower of the two sorted ranges: a card-wide horizontal edge is narrow in y, a tall
    // vertical one in x, so neither scans every vertex.
    const auto range = [](const std::vector<Vertex>& s, double lo, double hi, double Vertex::*c) {
      const auto first = std::lower_bound(s.begin(), s.end(), lo, [&](const Vertex& v, double k) { return v.*c < k; });
      const auto last = std::upper_bound(first, s.end(), hi, [&](double k, const Vertex& v) { return k < v.*c; });
      return std::pair(first, last);
    };
    const auto [fx, lx] = range(by_x_, x0, x1, &Vertex::x);
    const auto [fy, ly] = range(by_y_, y0, y1, &Vertex::y);
    const bool use_x = lx - fx <= ly - fy;
    const double len = std::hypot(bx - ax, by - ay);
    std::vector<ExactPoint> out;
    for (auto it = use_x ? fx : fy, end = use_x ? lx : ly; it != end; ++it) {
      if (it->x < x0 || it->x > x1 || it->y < y0 || it->y > y1 || it->p == a || it->p == b) continue;
      // Far from the line in doubles: no exact test needed.
      if (std::abs((bx - ax) * (it->y - ay) - (by - ay) * (it->x - ax)) > kSlackNm * len) continue;
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
  std::vector<Vertex> by_x_, by_y_;
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

// True when every exact vertex already lies on the 1 nm grid, so rounding moves nothing and the
// rings are the exact subdivision's loops. A crossing of slanted edges is a quotient whose
// interval is not one whole number; rounding it may move it across an edge nearby.
bool exactly_on_grid(const std::vector<OaPiece>& pieces) {
  const auto whole = [](const CGAL::Interval_nt<false>& i) { return i.is_point() && std::floor(i.inf()) == i.inf(); };
  const auto on = [&](const ExactPolygon& ring) {
    return std::all_of(ring.vertices_begin(), ring.vertices_end(), [&](const ExactPoint& p) {
      const auto a = CGAL::approx(p);
      return whole(a.x()) && whole(a.y());
    });
  };
  return std::all_of(pieces.begin(), pieces.end(), [&](const OaPiece& f) {
    return on(f.polygon.outer_boundary()) && std::all_of(f.polygon.holes_begin(), f.polygon.holes_end(), on);
  });
}

// "faces[12]…" of the derived faces as the .oa faces that made them.
std::string with_names(const std::string& text, const std::vector<OaPiece>& pieces) {
  std::string out;
  std::size_t pos = 0;
  for (std::size_t at = text.find("faces["); at != std::string::npos; at = text.find("faces[", pos)) {
    const std::size_t first = at + 6, close = text.find(']', first);
    const bool index =
        close != std::string::npos && close > first && close - first <= 9 &&
        std::all_of(text.begin() + static_cast<std::ptrdiff_t>(first),
                    text.begin() + static_cast<std::ptrdiff_t>(close), [](char c) { return c >= '0' && c <= '9'; });
    const std::size_t k = index ? std::stoul(text.substr(first, close - first)) : pieces.size();
    if (k >= pieces.size()) {
      out += text.substr(pos, first - pos);
      pos = first;
      continue;
    }
    out += text.substr(pos, at - pos) + pieces[k].drawn_by;
    pos = close + 1;
  }
  return out + text.substr(pos);
}

}  // namespace

FaceModel oa_face_model(const std::vector<OaPiece>& pieces, double width_mm, double half_height_mm,
                        const std::string& source) {
  const bool on_grid = guarded(source, "faces", [&] { return exactly_on_grid(pieces); });
  std::vector<OAFace> faces = guarded(source, "faces", [&] {
    const VertexIndex index(pieces);
    std::vector<OAFace> out;
    out.reserve(pieces.size());
    for (const OaPiece& f : pieces) {
      OAFace o{f.kind, to_mm(f.t_nm), {grid_ring(f.polygon.outer_boundary(), index), {}}};
      for (const ExactPolygon& h : f.polygon.holes()) o.polygon.holes.push_back(grid_ring(h, index));
      out.push_back(std::move(o));
    }
    return out;
  });
  std::vector<std::string> names;
  names.reserve(pieces.size());
  for (const OaPiece& p : pieces) names.push_back(p.drawn_by);
  try {
    // Off the grid, every check of from_faces runs: the rounding may have moved a corner across
    // an edge, which only the exact union of the rounded faces sees.
    FaceModel m = FaceModel::from_subdivision(width_mm, half_height_mm, half_height_mm, faces, source, on_grid);
    m.name_given_faces(std::move(names));
    return m;
  } catch (const Error& e) {
    if (e.code() != ErrorCode::invalid_input) throw;
    // A face named: the rounding broke it, so the drawn edges meet within 1 nm there.
    if (e.location().rfind("faces[", 0) == 0) {
      throw Error(ErrorCode::invalid_input, source, with_names(e.location(), pieces),
                  with_names(e.message(), pieces) +
                      ", once the derived faces' corners are rounded to 1 nm: the drawn edges there cross or pass "
                      "within 1 nm of each other; move them apart");
    }
    throw Error(ErrorCode::internal, source, e.location(), "the derived faces do not tile the card: " + e.message());
  }
}

}  // namespace popcut::detail
