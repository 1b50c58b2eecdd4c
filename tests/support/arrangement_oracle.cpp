// CGAL arrangement of all face boundaries, typed edge by edge: the test oracle for make_pattern's lines.
#include "arrangement_oracle.h"

#include <CGAL/Arr_consolidated_curve_data_traits_2.h>
#include <CGAL/Arr_segment_traits_2.h>
#include <CGAL/Arrangement_2.h>

#include <algorithm>
#include <map>
#include <unordered_map>

#include "model/face_model_state.h"
#include "pattern/face_map.h"
#include "popcut/error.h"

namespace popcut::testing {
using namespace popcut::detail;

namespace {

using SegmentTraits = CGAL::Arr_segment_traits_2<Kernel>;
// Each input edge carries 2·face + side: side 0 when its face lies left of the edge walked
// from its lexicographically smaller end, 1 when right. Overlapping edges pool their data.
using Traits = CGAL::Arr_consolidated_curve_data_traits_2<SegmentTraits, int>;
using Arrangement = CGAL::Arrangement_2<Traits>;

struct EdgeInfo {
  int left = -1;         // face left of the edge walked left-to-right (above a horizontal edge)
  int right = -1;        // face on the other side
  int kind = -1;         // -1: outline (one side is outside the sheet); else LineKind
  bool chained = false;  // already part of an emitted maximal line
};

}  // namespace

Pattern arrangement_lines(const FaceModel& model) {
  const FaceModelState& s = model.state();
  const std::string source = "oracle";
  {
    const auto& input = s.faces;  // shared with the model, read in place
    std::vector<Traits::Curve_2> curves;
    for (std::size_t i = 0; i < input.size(); ++i) {
      const auto add_ring = [&](const ExactPolygon& ring) {
        for (auto e = ring.edges_begin(); e != ring.edges_end(); ++e) {
          const bool forward = CGAL::compare_xy(e->source(), e->target()) == CGAL::SMALLER;
          // Rings run with their face on the left (outer CCW, holes CW).
          curves.emplace_back(SegmentTraits::Curve_2(e->source(), e->target()),
                              static_cast<int>(2 * i + (forward ? 0 : 1)));
        }
      };
      add_ring(input[i]->polygon.outer_boundary());
      for (const ExactPolygon& h : input[i]->polygon.holes()) add_ring(h);
    }
    Arrangement arr;
    CGAL::insert(arr, curves.begin(), curves.end());

    // The faces on each side of every edge; coplanar faces across an edge (not just a corner)
    // are one piece of paper, so they are merged into one face with no line between.
    std::unordered_map<const void*, EdgeInfo> info;
    CoplanarGroups groups(input);
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      EdgeInfo ei;
      for (int d : e->curve().data()) {
        int& slot = d % 2 == 0 ? ei.left : ei.right;
        if (slot >= 0 && slot != d / 2) {
          throw Error(ErrorCode::invalid_input, source, "faces",
                      "faces " + std::to_string(slot) + " and " + std::to_string(d / 2) + " overlap (eq. 4)");
        }
        slot = d / 2;
      }
      if (ei.left >= 0 && ei.right >= 0) groups.meet(ei.left, ei.right);
      info[&*e] = ei;
    }
    const std::vector<std::vector<int>> members = groups.members();
    const auto face_of = [&](int input_face) { return groups.group_of(input_face); };
    // Each merged face's plane is its first member's.
    std::vector<const ExactFace*> faces;
    for (const std::vector<int>& group : members) faces.push_back(input[static_cast<std::size_t>(group.front())].get());
    Pattern p;
    // Type every edge by where its two faces meet in 3D.
    std::map<std::pair<int, int>, std::size_t> link_index;
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      EdgeInfo& ei = info[&*e];
      if (ei.left >= 0) ei.left = face_of(ei.left);
      if (ei.right >= 0) ei.right = face_of(ei.right);
      const ExactPoint& a = e->curve().left();
      const ExactPoint& b = e->curve().right();
      const bool horizontal = a.y() == b.y();
      if (ei.left < 0 || ei.right < 0) {
        const bool on_outline = (horizontal && (a.y() == s.max_v || a.y() == s.min_v)) ||
                                (a.x() == b.x() && (a.x() == s.min_x || a.x() == s.max_x));
        if (!on_outline) {
          throw Error(ErrorCode::invalid_input, source, "faces",
                      "no face covers the sheet beside (" + std::to_string(to_point2(a).x_mm) + ", " +
                          std::to_string(to_point2(a).v_mm) + "): faces must cover the sheet (eq. 4)");
        }
        continue;
      }
      if (ei.left == ei.right) continue;  // inside one merged face: no line
      const LineKind kind = line_between(*faces[static_cast<std::size_t>(ei.left)],
                                         *faces[static_cast<std::size_t>(ei.right)], horizontal, a.y());
      ei.kind = static_cast<int>(kind);
      if (kind != LineKind::cut) {
        auto [it, fresh] = link_index.emplace(std::make_pair(ei.left, ei.right), p.folds.size());
        if (fresh) p.folds.push_back({ei.left, ei.right, kind, 0});
        p.folds[it->second].length_mm += to_mm(b.x() - a.x());
      }
    }

    // Maximal lines: chain edges of one kind through vertices where they continue straight on.
    const auto edge_key = [&](Arrangement::Halfedge_const_handle h) -> const void* {
      // info is keyed by the halfedge the edge iterator yields; find it from either twin.
      return info.count(&*h) ? static_cast<const void*>(&*h) : static_cast<const void*>(&*h->twin());
    };
    for (auto e = arr.edges_begin(); e != arr.edges_end(); ++e) {
      EdgeInfo& ei = info[&*e];
      if (ei.kind < 0 || ei.chained) continue;
      ei.chained = true;
      ExactPoint lo = e->curve().left(), hi = e->curve().right();
      // Extend from one end while a collinear edge of the same kind leaves it the other way.
      const auto extend = [&](Arrangement::Vertex_const_handle v, ExactPoint& end, const ExactPoint& other) {
        for (;;) {
          bool moved = false;
          auto circ = v->incident_halfedges();
          if (circ == Arrangement::Halfedge_around_vertex_const_circulator()) return;
          auto first = circ;
          do {
            Arrangement::Halfedge_const_handle h = circ;  // points into v
            EdgeInfo& next = info[edge_key(h)];
            const ExactPoint& far = h->source()->point();
            if (!next.chained && next.kind == ei.kind && CGAL::collinear(other, end, far) &&
                CGAL::collinear_are_ordered_along_line(other, end, far)) {
              next.chained = true;
              end = far;
              v = h->source();
              moved = true;
              break;
            }
          } while (++circ != first);
          if (!moved) return;
        }
      };
      const ExactPoint lo0 = lo, hi0 = hi;
      Arrangement::Vertex_const_handle vl = e->source()->point() == lo0 ? e->source() : e->target();
      Arrangement::Vertex_const_handle vr = e->source()->point() == lo0 ? e->target() : e->source();
      extend(vl, lo, hi0);
      extend(vr, hi, lo);
      p.lines.push_back({static_cast<LineKind>(ei.kind), to_point2(lo), to_point2(hi)});
    }
    sort_lines_and_folds(p);

    return p;
  }
}

}  // namespace popcut::testing
