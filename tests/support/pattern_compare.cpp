// Canonical forms of patterns so two generators can be compared as sets.
#include "pattern_compare.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <tuple>
#include <vector>

#include "popcut/pattern/popup_check.h"

namespace popcut::testing {
namespace {

using Key = std::vector<long long>;

long long q(double v) { return std::llround(v * 1e6); }

Key ring_key(const Ring& ring) {
  // Start at the smallest vertex so rotations compare equal.
  std::size_t start = 0;
  for (std::size_t i = 1; i < ring.size(); ++i) {
    if (std::make_pair(q(ring[i].x_mm), q(ring[i].v_mm)) < std::make_pair(q(ring[start].x_mm), q(ring[start].v_mm)))
      start = i;
  }
  Key k;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point2& p = ring[(start + i) % ring.size()];
    k.push_back(q(p.x_mm));
    k.push_back(q(p.v_mm));
  }
  return k;
}

Key face_key(const PatternFace& f) {
  Key k{f.kind == FaceKind::vertical ? 0 : 1, q(f.t_mm)};
  const Key outer = ring_key(f.outer);
  k.insert(k.end(), outer.begin(), outer.end());
  std::vector<Key> holes;
  for (const Ring& h : f.holes) holes.push_back(ring_key(h));
  std::sort(holes.begin(), holes.end());
  for (const Key& h : holes) {
    k.push_back(-1);
    k.insert(k.end(), h.begin(), h.end());
  }
  return k;
}

std::multiset<Key> lines_of(const Pattern& p) {
  std::multiset<Key> out;
  for (const Segment& s : p.lines) {
    auto a = std::make_pair(q(s.a.x_mm), q(s.a.v_mm));
    auto b = std::make_pair(q(s.b.x_mm), q(s.b.v_mm));
    if (b < a) std::swap(a, b);
    out.insert({static_cast<long long>(s.kind), a.first, a.second, b.first, b.second});
  }
  return out;
}

std::multiset<Key> faces_of(const Pattern& p, const std::vector<int>& which) {
  std::multiset<Key> out;
  for (int i : which) out.insert(face_key(p.faces[static_cast<std::size_t>(i)]));
  return out;
}

std::vector<int> all_faces(const Pattern& p) {
  std::vector<int> v(p.faces.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<int>(i);
  return v;
}

std::vector<int> problem_faces(const std::vector<FaceProblem>& problems) {
  std::vector<int> v;
  for (const FaceProblem& f : problems) v.push_back(f.face);
  return v;
}

}  // namespace

std::string compare_patterns(const Pattern& a, const Pattern& b) {
  if (a.sheet != b.sheet) return "sheets differ";
  if (lines_of(a) != lines_of(b)) {
    return "lines differ: " + std::to_string(a.lines.size()) + " vs " + std::to_string(b.lines.size()) + " segments";
  }
  if (faces_of(a, all_faces(a)) != faces_of(b, all_faces(b))) {
    return "faces differ: " + std::to_string(a.faces.size()) + " vs " + std::to_string(b.faces.size());
  }
  if (face_key(a.faces[static_cast<std::size_t>(a.back_face)]) !=
      face_key(b.faces[static_cast<std::size_t>(b.back_face)])) {
    return "back boards differ";
  }
  const PopupReport ra = check_popup(a), rb = check_popup(b);
  if (ra.pops_up() != rb.pops_up() || ra.sheet_split != rb.sheet_split) return "pop-up verdicts differ";
  if (faces_of(a, problem_faces(ra.not_standing)) != faces_of(b, problem_faces(rb.not_standing)))
    return "failing faces differ";
  if (faces_of(a, problem_faces(ra.flaps)) != faces_of(b, problem_faces(rb.flaps))) return "flaps differ";
  if (ra.loose_pieces.size() != rb.loose_pieces.size()) return "loose pieces differ";
  return "";
}

}  // namespace popcut::testing
