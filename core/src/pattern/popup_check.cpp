// The two fold traversals of polygon paper §3.6 and a component search for pieces cut free.
#include "popcut/pattern/popup_check.h"

#include <algorithm>

#include "popcut/error.h"

namespace popcut {
namespace {

using Adjacency = std::vector<std::vector<int>>;

// Marks every face reachable along `next` from the faces marked in `start`.
std::vector<char> reach(const Adjacency& next, const std::vector<char>& start) {
  std::vector<char> seen = start;
  std::vector<int> stack;
  for (std::size_t f = 0; f < start.size(); ++f) {
    if (start[f]) stack.push_back(static_cast<int>(f));
  }
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
  for (const FoldLink& f : p.folds) {
    if (bad(f.upper) || bad(f.lower))
      throw Error(ErrorCode::invalid_input, "", "folds", "a fold names a face that does not exist");
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

  // The boards the card is held by, found from the geometry (see PopupReport).
  std::vector<char> is_back(n, 0), is_floor(n, 0);
  for (std::size_t f = 0; f < n; ++f) {
    const PatternFace& face = p.faces[f];
    if (face.t_mm != 0 || face.outer.empty()) continue;
    const Rect b = bounds(face.outer);
    if (face.kind == FaceKind::vertical && b.max.v_mm == p.sheet.max.v_mm) is_back[f] = 1;
    if (face.kind == FaceKind::horizontal && b.min.v_mm == p.sheet.min.v_mm) is_floor[f] = 1;
  }
  report.no_back_board = std::count(is_back.begin(), is_back.end(), 1) == 0;
  report.no_floor = std::count(is_floor.begin(), is_floor.end(), 1) == 0;
  if (report.no_back_board || report.no_floor) return report;

  // Pieces: faces joined by folds. A piece with a back board part but no floor part (or the
  // reverse) means the sheet falls apart; one with neither falls out.
  const std::vector<int> piece = components(either);
  std::vector<char> piece_back(n, 0), piece_floor(n, 0);
  for (std::size_t f = 0; f < n; ++f) {
    piece_back[static_cast<std::size_t>(piece[f])] |= is_back[f];
    piece_floor[static_cast<std::size_t>(piece[f])] |= is_floor[f];
  }
  std::vector<int> slot(n, -1);  // piece label → index in loose_pieces
  for (std::size_t f = 0; f < n; ++f) {
    const std::size_t k = static_cast<std::size_t>(piece[f]);
    if (piece_back[k] != piece_floor[k]) report.sheet_split = true;
    if (piece_back[k] || piece_floor[k]) continue;
    if (slot[k] < 0) {
      slot[k] = static_cast<int>(report.loose_pieces.size());
      report.loose_pieces.push_back({{}, bounds(p.faces[f].outer), 0});
    }
    LoosePiece& lp = report.loose_pieces[static_cast<std::size_t>(slot[k])];
    const Rect b = bounds(p.faces[f].outer);
    lp.bounds.min.x_mm = std::min(lp.bounds.min.x_mm, b.min.x_mm);
    lp.bounds.min.v_mm = std::min(lp.bounds.min.v_mm, b.min.v_mm);
    lp.bounds.max.x_mm = std::max(lp.bounds.max.x_mm, b.max.x_mm);
    lp.bounds.max.v_mm = std::max(lp.bounds.max.v_mm, b.max.v_mm);
    lp.area_mm2 += face_area_mm2(p.faces[f]);
    lp.faces.push_back(static_cast<int>(f));
  }
  // An opening's paper that nothing holds simply drops out of the opening.
  const auto only_opening = [&](const LoosePiece& lp) {
    return std::all_of(lp.faces.begin(), lp.faces.end(),
                       [&](int f) { return p.faces[static_cast<std::size_t>(f)].opening_paper; });
  };
  const auto cut = std::stable_partition(report.loose_pieces.begin(), report.loose_pieces.end(),
                                         [&](const LoosePiece& lp) { return !only_opening(lp); });
  report.cut_out.assign(cut, report.loose_pieces.end());
  report.loose_pieces.erase(cut, report.loose_pieces.end());
  if (report.sheet_split) return report;

  const std::vector<char> from_back = reach(down, is_back);
  const std::vector<char> from_floor = reach(up, is_floor);
  for (std::size_t f = 0; f < n; ++f) {
    const std::size_t k = static_cast<std::size_t>(piece[f]);
    if (!piece_back[k] && !piece_floor[k]) continue;  // reported with its loose piece
    if (is_back[f] || is_floor[f] || (from_back[f] && from_floor[f])) continue;
    const FaceProblem problem{static_cast<int>(f), from_back[f] != 0, from_floor[f] != 0};
    (p.faces[f].kind == FaceKind::vertical ? report.not_standing : report.flaps).push_back(problem);
  }
  return report;
}

}  // namespace popcut
