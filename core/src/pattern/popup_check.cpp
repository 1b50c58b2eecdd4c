// The two fold traversals of polygon paper §3.6 and a component search for pieces cut free.
#include "popcut/pattern/popup_check.h"

#include <algorithm>

#include "popcut/error.h"

namespace popcut {
namespace {

using Adjacency = std::vector<std::vector<int>>;

// Marks every face reachable from `start` along `next`.
std::vector<char> reach(const Adjacency& next, int start) {
  std::vector<char> seen(next.size(), 0);
  std::vector<int> stack{start};
  seen[static_cast<std::size_t>(start)] = 1;
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    for (int g : next[static_cast<std::size_t>(f)]) {
      if (!seen[static_cast<std::size_t>(g)]) {
        seen[static_cast<std::size_t>(g)] = 1;
        stack.push_back(g);
      }
    }
  }
  return seen;
}

// Labels the connected components of `adj` in one pass.
std::vector<int> components(const Adjacency& adj) {
  std::vector<int> label(adj.size(), -1);
  std::vector<int> stack;
  int next = 0;
  for (std::size_t s = 0; s < adj.size(); ++s) {
    if (label[s] >= 0) continue;
    label[s] = next;
    stack.assign(1, static_cast<int>(s));
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int g : adj[static_cast<std::size_t>(f)]) {
        if (label[static_cast<std::size_t>(g)] < 0) {
          label[static_cast<std::size_t>(g)] = next;
          stack.push_back(g);
        }
      }
    }
    ++next;
  }
  return label;
}

void require_consistent(const Pattern& p) {
  const auto bad = [&](int f) { return f < 0 || static_cast<std::size_t>(f) >= p.faces.size(); };
  if (bad(p.back_face) || bad(p.floor_face)) {
    throw Error(ErrorCode::invalid_input, "", "pattern", "the pattern names no back board or floor face");
  }
  for (const FoldLink& f : p.folds) {
    if (bad(f.upper) || bad(f.lower)) throw Error(ErrorCode::invalid_input, "", "folds", "a fold names a face that does not exist");
  }
}

}  // namespace

double face_area_mm2(const PatternFace& face) {
  double a = signed_area_mm2(face.outer);
  for (const Ring& h : face.holes) a += signed_area_mm2(h);  // holes are clockwise: negative
  return a;
}

PopupReport check_popup(const Pattern& p) {
  require_consistent(p);
  const std::size_t n = p.faces.size();
  // Walk (a) crosses every fold from its upper face to its lower one (V→H over a valley is
  // always downward, as is H→V over a mountain); walk (b) crosses them upward.
  Adjacency down(n), up(n), either(n);
  for (const FoldLink& l : p.folds) {
    down[static_cast<std::size_t>(l.upper)].push_back(l.lower);
    up[static_cast<std::size_t>(l.lower)].push_back(l.upper);
    either[static_cast<std::size_t>(l.upper)].push_back(l.lower);
    either[static_cast<std::size_t>(l.lower)].push_back(l.upper);
  }
  PopupReport report;

  // Pieces: faces joined by folds; the one holding the back board is the card.
  const std::vector<int> piece = components(either);
  const int card = piece[static_cast<std::size_t>(p.back_face)];
  const int floor_piece = piece[static_cast<std::size_t>(p.floor_face)];
  report.sheet_split = floor_piece != card;
  std::vector<int> slot(n, -1);  // piece label → index in loose_pieces
  for (std::size_t f = 0; f < n; ++f) {
    const int k = piece[f];
    if (k == card || k == floor_piece) continue;
    if (slot[static_cast<std::size_t>(k)] < 0) {
      slot[static_cast<std::size_t>(k)] = static_cast<int>(report.loose_pieces.size());
      report.loose_pieces.push_back({{}, bounds(p.faces[f].outer), 0});
    }
    LoosePiece& lp = report.loose_pieces[static_cast<std::size_t>(slot[static_cast<std::size_t>(k)])];
    const Rect b = bounds(p.faces[f].outer);
    lp.bounds.min.x_mm = std::min(lp.bounds.min.x_mm, b.min.x_mm);
    lp.bounds.min.v_mm = std::min(lp.bounds.min.v_mm, b.min.v_mm);
    lp.bounds.max.x_mm = std::max(lp.bounds.max.x_mm, b.max.x_mm);
    lp.bounds.max.v_mm = std::max(lp.bounds.max.v_mm, b.max.v_mm);
    lp.area_mm2 += face_area_mm2(p.faces[f]);
    lp.faces.push_back(static_cast<int>(f));
  }
  if (report.sheet_split) return report;

  const std::vector<char> from_back = reach(down, p.back_face);
  const std::vector<char> from_floor = reach(up, p.floor_face);
  for (std::size_t f = 0; f < n; ++f) {
    if (piece[f] != card || (from_back[f] && from_floor[f])) continue;
    const FaceProblem problem{static_cast<int>(f), from_back[f] != 0, from_floor[f] != 0};
    (p.faces[f].kind == FaceKind::vertical ? report.not_standing : report.flaps).push_back(problem);
  }
  return report;
}

}  // namespace popcut
