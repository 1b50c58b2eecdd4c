// The two fold traversals of polygon paper §3.6 and a component search for pieces cut free.
#include "popcut/pattern/popup_check.h"

#include <algorithm>

#include "popcut/error.h"

namespace popcut {
namespace {

// Marks every face reached from `start`, following each fold only from upper to lower face
// (downward) or only from lower to upper (upward).
std::vector<char> walk(const Pattern& p, int start, bool downward) {
  std::vector<std::vector<int>> next(p.faces.size());
  for (const FoldLink& f : p.folds) {
    if (downward) next[static_cast<std::size_t>(f.upper)].push_back(f.lower);
    else next[static_cast<std::size_t>(f.lower)].push_back(f.upper);
  }
  std::vector<char> seen(p.faces.size(), 0);
  if (start < 0) return seen;
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

}  // namespace

double face_area_mm2(const PatternFace& face) {
  double a = signed_area_mm2(face.outer);
  for (const Ring& h : face.holes) a += signed_area_mm2(h);  // holes are clockwise: negative
  return a;
}

PopupReport check_popup(const Pattern& p) {
  const std::size_t n = p.faces.size();
  if (p.back_face < 0 || p.floor_face < 0 || static_cast<std::size_t>(p.back_face) >= n ||
      static_cast<std::size_t>(p.floor_face) >= n) {
    throw Error(ErrorCode::invalid_input, "", "pattern", "the pattern names no back board or floor face");
  }
  for (const FoldLink& f : p.folds) {
    if (f.upper < 0 || f.lower < 0 || static_cast<std::size_t>(f.upper) >= n || static_cast<std::size_t>(f.lower) >= n) {
      throw Error(ErrorCode::invalid_input, "", "folds", "a fold names a face that does not exist");
    }
  }
  PopupReport report;

  // Pieces: faces joined by folds (any direction); the one holding the back board is the card.
  std::vector<std::vector<int>> adjacent(n);
  for (const FoldLink& l : p.folds) {
    adjacent[static_cast<std::size_t>(l.upper)].push_back(l.lower);
    adjacent[static_cast<std::size_t>(l.lower)].push_back(l.upper);
  }
  std::vector<int> piece(n, -1);
  int pieces = 0;
  std::vector<int> stack;
  for (std::size_t s = 0; s < n; ++s) {
    if (piece[s] >= 0) continue;
    piece[s] = pieces;
    stack.assign(1, static_cast<int>(s));
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int other : adjacent[static_cast<std::size_t>(f)]) {
        if (piece[static_cast<std::size_t>(other)] < 0) {
          piece[static_cast<std::size_t>(other)] = pieces;
          stack.push_back(other);
        }
      }
    }
    ++pieces;
  }
  const int card = piece[static_cast<std::size_t>(p.back_face)];
  std::vector<LoosePiece> loose(static_cast<std::size_t>(pieces));
  for (std::size_t f = 0; f < n; ++f) {
    const int k = piece[f];
    if (k == card) continue;
    LoosePiece& lp = loose[static_cast<std::size_t>(k)];
    const Rect b = bounds(p.faces[f].outer);
    if (lp.faces.empty()) lp.bounds = b;
    lp.bounds.min.x_mm = std::min(lp.bounds.min.x_mm, b.min.x_mm);
    lp.bounds.min.v_mm = std::min(lp.bounds.min.v_mm, b.min.v_mm);
    lp.bounds.max.x_mm = std::max(lp.bounds.max.x_mm, b.max.x_mm);
    lp.bounds.max.v_mm = std::max(lp.bounds.max.v_mm, b.max.v_mm);
    lp.area_mm2 += face_area_mm2(p.faces[f]);
    lp.faces.push_back(static_cast<int>(f));
  }
  for (LoosePiece& lp : loose) {
    if (!lp.faces.empty()) report.loose_pieces.push_back(std::move(lp));
  }

  const std::vector<char> from_back = walk(p, p.back_face, /*downward=*/true);
  const std::vector<char> from_floor = walk(p, p.floor_face, /*downward=*/false);
  for (std::size_t f = 0; f < n; ++f) {
    if (piece[f] != card || (from_back[f] && from_floor[f])) continue;
    const FaceProblem problem{static_cast<int>(f), from_back[f] != 0, from_floor[f] != 0};
    (p.faces[f].kind == FaceKind::vertical ? report.not_standing : report.flaps).push_back(problem);
  }
  return report;
}

}  // namespace popcut
