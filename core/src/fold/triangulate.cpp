// Triangulation of a face with holes: CGAL's constrained Delaunay triangulation, triangles kept
// by nesting depth (inside the outer ring, outside every hole), the problem 003 §3.2 solves by hand.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <list>

#include "popcut/error.h"
#include "popcut/fold/fold.h"

namespace popcut {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int depth = -1;  // nesting: 0 outside, 1 inside the outer ring, 2 inside a hole, ...
};
using Vb = CGAL::Triangulation_vertex_base_2<K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

void insert_ring(CDT& cdt, const Ring& ring) {
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point2& a = ring[i];
    const Point2& b = ring[(i + 1) % ring.size()];
    cdt.insert_constraint(K::Point_2(a.x_mm, a.v_mm), K::Point_2(b.x_mm, b.v_mm));
  }
}

// Flood fill from the infinite face, adding one level each time a constrained edge is crossed.
void mark_depths(CDT& cdt) {
  std::list<CDT::Face_handle> border{cdt.infinite_face()};
  int depth = 0;
  while (!border.empty()) {
    std::list<CDT::Face_handle> next_border;
    while (!border.empty()) {
      std::list<CDT::Face_handle> queue{border.front()};
      border.pop_front();
      if (queue.front()->info().depth != -1) continue;
      while (!queue.empty()) {
        CDT::Face_handle f = queue.front();
        queue.pop_front();
        if (f->info().depth != -1) continue;
        f->info().depth = depth;
        for (int i = 0; i < 3; ++i) {
          CDT::Face_handle n = f->neighbor(i);
          if (n->info().depth != -1) continue;
          (cdt.is_constrained(CDT::Edge(f, i)) ? next_border : queue).push_back(n);
        }
      }
    }
    border.swap(next_border);
    ++depth;
  }
}

}  // namespace

std::vector<std::array<Point2, 3>> triangulate(const PatternFace& face) { return triangulate(face.outer, face.holes); }

std::vector<std::array<Point2, 3>> triangulate(const Ring& outer, const std::vector<Ring>& holes) {
  try {
    CDT cdt;
    insert_ring(cdt, outer);
    for (const Ring& h : holes) insert_ring(cdt, h);
    mark_depths(cdt);
    std::vector<std::array<Point2, 3>> out;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      if (f->info().depth % 2 != 1) continue;  // odd depth: inside the face
      std::array<Point2, 3> t;
      for (int k = 0; k < 3; ++k)
        t[static_cast<std::size_t>(k)] = {f->vertex(k)->point().x(), f->vertex(k)->point().y()};
      out.push_back(t);  // CGAL's faces are counter-clockwise
    }
    return out;
  } catch (const std::exception& e) {
    throw Error(ErrorCode::internal, "", "triangulate", std::string("geometry kernel failure: ") + e.what());
  }
}

}  // namespace popcut
