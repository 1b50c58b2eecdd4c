// Pattern oracle: recomputes tiling, line presence and line kinds from faces by point sampling.
#include "pattern_oracle.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

namespace popcut::testing {
namespace {

bool ring_contains(const Ring& ring, Point2 p) {
  bool inside = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Point2& a = ring[i];
    const Point2& b = ring[j];
    if ((a.v_mm > p.v_mm) != (b.v_mm > p.v_mm)) {
      const double x = a.x_mm + (p.v_mm - a.v_mm) * (b.x_mm - a.x_mm) / (b.v_mm - a.v_mm);
      if (p.x_mm < x) inside = !inside;
    }
  }
  return inside;
}

std::string pt(Point2 p) {
  std::ostringstream o;
  o << "(" << p.x_mm << ", " << p.v_mm << ")";
  return o.str();
}

long long key(double v, double step) { return std::llround(v / step); }

}  // namespace

bool face_contains(const PatternFace& face, Point2 p) {
  if (!ring_contains(face.outer, p)) return false;
  for (const Ring& h : face.holes) {
    if (ring_contains(h, p)) return false;
  }
  return true;
}

int face_at(const Pattern& pattern, Point2 p) {
  int found = -1;
  for (std::size_t i = 0; i < pattern.faces.size(); ++i) {
    const Rect b = bounds(pattern.faces[i].outer);
    if (p.x_mm < b.min.x_mm || p.x_mm > b.max.x_mm || p.v_mm < b.min.v_mm || p.v_mm > b.max.v_mm) continue;
    if (!face_contains(pattern.faces[i], p)) continue;
    if (found >= 0) return -2;
    found = static_cast<int>(i);
  }
  return found;
}

std::vector<std::string> check_tiling(const Pattern& p, double step) {
  std::vector<std::string> problems;
  double area = 0;
  for (std::size_t i = 0; i < p.faces.size(); ++i) {
    const PatternFace& f = p.faces[i];
    if (signed_area_mm2(f.outer) <= 0)
      problems.push_back("face " + std::to_string(i) + ": outer ring not counter-clockwise");
    for (const Ring& h : f.holes) {
      if (signed_area_mm2(h) >= 0) problems.push_back("face " + std::to_string(i) + ": hole not clockwise");
    }
    double a = signed_area_mm2(f.outer);
    for (const Ring& h : f.holes) a += signed_area_mm2(h);
    area += a;
    if (!face_contains(f, f.label)) problems.push_back("face " + std::to_string(i) + ": label outside the face");
  }
  const double sheet_area = (p.sheet.max.x_mm - p.sheet.min.x_mm) * (p.sheet.max.v_mm - p.sheet.min.v_mm);
  if (std::abs(area - sheet_area) > 1e-6 * sheet_area) {
    problems.push_back("face areas sum to " + std::to_string(area) + " mm² but the sheet is " +
                       std::to_string(sheet_area));
  }
  for (double x = p.sheet.min.x_mm + step / 2; x < p.sheet.max.x_mm; x += step) {
    for (double v = p.sheet.min.v_mm + step / 2; v < p.sheet.max.v_mm; v += step) {
      const int f = face_at(p, {x, v});
      if (f == -1) problems.push_back("no face covers " + pt({x, v}));
      if (f == -2) problems.push_back("faces overlap at " + pt({x, v}));
      if (problems.size() > 20) return problems;
    }
  }
  return problems;
}

std::vector<std::string> check_lines(const Pattern& p, double step) {
  std::vector<std::string> problems;
  // Unit edges covered by lines: (horizontal?, fixed coordinate, start along the line) → kind.
  std::map<std::tuple<bool, long long, long long>, LineKind> covered;
  std::set<std::tuple<bool, long long, long long, int>> endpoints;  // for maximality
  for (const Segment& s : p.lines) {
    const bool horizontal = s.a.v_mm == s.b.v_mm;
    if (!horizontal && s.a.x_mm != s.b.x_mm) {
      problems.push_back("line " + pt(s.a) + "-" + pt(s.b) + " is neither x-parallel nor across x");
      continue;
    }
    if (!horizontal && s.kind != LineKind::cut)
      problems.push_back("fold " + pt(s.a) + "-" + pt(s.b) + " is not x-parallel");
    const long long fixed = horizontal ? key(s.a.v_mm, step) : key(s.a.x_mm, step);
    long long lo = horizontal ? key(s.a.x_mm, step) : key(s.a.v_mm, step);
    long long hi = horizontal ? key(s.b.x_mm, step) : key(s.b.v_mm, step);
    if (lo > hi) std::swap(lo, hi);
    if (lo == hi) problems.push_back("zero-length line at " + pt(s.a));
    for (long long i = lo; i < hi; ++i) {
      if (!covered.emplace(std::make_tuple(horizontal, fixed, i), s.kind).second) {
        problems.push_back("two lines cover the same edge near " + pt(s.a));
      }
    }
    for (long long e : {lo, hi}) {
      const auto k = std::make_tuple(horizontal, fixed, e, static_cast<int>(s.kind));
      if (!endpoints.insert(k).second)
        problems.push_back("lines of one kind touch end to end at " + pt(s.a) + ": not maximal");
    }
  }
  // Every unit edge inside the sheet: faces on both sides decide whether a line belongs there.
  const double eps = step * 1e-3;
  const long long x0 = key(p.sheet.min.x_mm, step), x1 = key(p.sheet.max.x_mm, step);
  const long long v0 = key(p.sheet.min.v_mm, step), v1 = key(p.sheet.max.v_mm, step);
  for (int horizontal = 0; horizontal < 2; ++horizontal) {
    for (long long a = (horizontal ? v0 + 1 : x0 + 1); a < (horizontal ? v1 : x1); ++a) {
      for (long long b = (horizontal ? x0 : v0); b < (horizontal ? x1 : v1); ++b) {
        const double fixed = static_cast<double>(a) * step, mid = (static_cast<double>(b) + 0.5) * step;
        const Point2 m = horizontal ? Point2{mid, fixed} : Point2{fixed, mid};
        const Point2 one = horizontal ? Point2{mid, fixed + eps} : Point2{fixed - eps, mid};  // above / left
        const Point2 two = horizontal ? Point2{mid, fixed - eps} : Point2{fixed + eps, mid};  // below / right
        const int fa = face_at(p, one), fb = face_at(p, two);
        const auto it = covered.find(std::make_tuple(horizontal == 1, a, b));
        if (fa < 0 || fb < 0) continue;  // reported by check_tiling
        if (fa == fb) {
          if (it != covered.end()) problems.push_back("line inside face " + std::to_string(fa) + " at " + pt(m));
          continue;
        }
        if (it == covered.end()) {
          problems.push_back("no line between faces " + std::to_string(fa) + " and " + std::to_string(fb) + " at " +
                             pt(m));
          continue;
        }
        // The kind from 3D: both faces' images of the edge must coincide for a fold.
        const PatternFace& up = p.faces[static_cast<std::size_t>(fa)];
        const PatternFace& lo = p.faces[static_cast<std::size_t>(fb)];
        LineKind expect = LineKind::cut;
        if (horizontal && up.kind != lo.kind) {
          const Point3 pu = to_card(up.kind, up.t_mm, m), pl = to_card(lo.kind, lo.t_mm, m);
          if (std::abs(pu.y_mm - pl.y_mm) < 1e-9 && std::abs(pu.z_mm - pl.z_mm) < 1e-9) {
            expect = up.kind == FaceKind::vertical ? LineKind::valley : LineKind::mountain;
          }
        }
        if (it->second != expect) {
          problems.push_back(std::string("line at ") + pt(m) + " is " + to_string(it->second) +
                             " but the faces make it " + to_string(expect));
        }
        if (problems.size() > 20) return problems;
      }
    }
  }
  return problems;
}

std::vector<std::string> check_folds(const Pattern& p) {
  std::vector<std::string> problems;
  for (const FoldLink& f : p.folds) {
    const PatternFace& up = p.faces[static_cast<std::size_t>(f.upper)];
    const PatternFace& lo = p.faces[static_cast<std::size_t>(f.lower)];
    const bool ok = (f.kind == LineKind::valley && up.kind == FaceKind::vertical && lo.kind == FaceKind::horizontal) ||
                    (f.kind == LineKind::mountain && up.kind == FaceKind::horizontal && lo.kind == FaceKind::vertical);
    if (!ok)
      problems.push_back("fold link " + std::to_string(f.upper) + "→" + std::to_string(f.lower) +
                         " has the wrong kind");
    if (f.length_mm <= 0) problems.push_back("fold link with no length");
  }
  return problems;
}

}  // namespace popcut::testing
