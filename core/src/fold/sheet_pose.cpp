// Each region's rigid pose from the hinge angles, the closure check around cycles, and the folded mesh.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include "popcut/fold/sheet_fold.h"
#include "popcut/text.h"

namespace popcut {
namespace {

using Mat = std::array<double, 9>;

constexpr int kMaxMotionFrames = 10000;

Mat multiply(const Mat& a, const Mat& b) {
  Mat m{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        m[static_cast<std::size_t>(3 * i + j)] +=
            a[static_cast<std::size_t>(3 * i + k)] * b[static_cast<std::size_t>(3 * k + j)];
  return m;
}

Point3 rotate(const Mat& m, Point3 p) {
  return {m[0] * p.x_mm + m[1] * p.y_mm + m[2] * p.z_mm, m[3] * p.x_mm + m[4] * p.y_mm + m[5] * p.z_mm,
          m[6] * p.x_mm + m[7] * p.y_mm + m[8] * p.z_mm};
}

// Rotation by `deg` about the in-plane unit axis (ux, uv, 0) (Rodrigues), exact at 0, ±90 and ±180.
Mat axis_rotation(double ux, double uv, double deg) {
  const double th = deg * std::numbers::pi / 180;
  const double c = std::abs(deg) == 90 ? 0.0 : (std::abs(deg) == 180 ? -1.0 : std::cos(th));
  const double s = std::abs(deg) == 180 ? 0.0 : (std::abs(deg) == 90 ? (deg > 0 ? 1.0 : -1.0) : std::sin(th));
  const double k = 1 - c;
  return {c + ux * ux * k, ux * uv * k, uv * s, ux * uv * k, c + uv * uv * k, -ux * s, -uv * s, ux * s, c};
}

// The pose of `child` given its neighbour across hinge h: turned about the hinge line so that a
// positive (valley) angle lifts it toward +z.
Pose across(const Pose& parent, const SheetHinge& h, int child, double progress) {
  const double dx = h.b.x_mm - h.a.x_mm, dv = h.b.v_mm - h.a.v_mm, len = std::hypot(dx, dv);
  // Turning about +d lifts the side on d's left; the right side lifts turning about −d.
  const double sign = child == h.left ? 1.0 : -1.0;
  const Mat r = axis_rotation(sign * dx / len, sign * dv / len, h.angle_deg * progress);
  // Local map: p ↦ r (p − a) + a, then the parent's pose.
  const Point3 a{h.a.x_mm, h.a.v_mm, 0};
  const Point3 ra = rotate(r, a);
  const Point3 local_t{a.x_mm - ra.x_mm, a.y_mm - ra.y_mm, a.z_mm - ra.z_mm};
  const Point3 pt = rotate(parent.r, local_t);
  return {multiply(parent.r, r), {pt.x_mm + parent.t.x_mm, pt.y_mm + parent.t.y_mm, pt.z_mm + parent.t.z_mm}};
}

double distance(Point3 a, Point3 b) { return std::hypot(a.x_mm - b.x_mm, a.y_mm - b.y_mm, a.z_mm - b.z_mm); }

// The hinges on the walk's path from region r up to its piece's fixed region.
std::vector<int> path_up(int r, const std::vector<int>& parent_hinge, const std::vector<SheetHinge>& hinges) {
  std::vector<int> path;
  for (int h = parent_hinge[static_cast<std::size_t>(r)]; h >= 0; h = parent_hinge[static_cast<std::size_t>(r)]) {
    path.push_back(h);
    const SheetHinge& hh = hinges[static_cast<std::size_t>(h)];
    r = hh.left == r ? hh.right : hh.left;
  }
  return path;
}

// The cycle a closing hinge makes with the walk: both paths up, without their common part.
std::vector<int> cycle_of(int h, const std::vector<int>& parent_hinge, const std::vector<SheetHinge>& hinges) {
  std::vector<int> a = path_up(hinges[static_cast<std::size_t>(h)].left, parent_hinge, hinges);
  std::vector<int> b = path_up(hinges[static_cast<std::size_t>(h)].right, parent_hinge, hinges);
  while (!a.empty() && !b.empty() && a.back() == b.back()) {
    a.pop_back();
    b.pop_back();
  }
  std::vector<int> cycle{h};
  cycle.insert(cycle.end(), a.begin(), a.end());
  cycle.insert(cycle.end(), b.rbegin(), b.rend());
  return cycle;
}

SheetProblem open_cycle(const FoldableSheet& s, int h, double gap_mm, const std::vector<int>& parent_hinge) {
  SheetProblem p;
  p.hinges = cycle_of(h, parent_hinge, s.hinges);
  std::string names;
  for (int k : p.hinges) {
    const SheetHinge& hk = s.hinges[static_cast<std::size_t>(k)];
    p.regions.insert(p.regions.end(), {hk.left, hk.right});
    names += (names.empty() ? "" : ", ") + hk.where + " " + format_significant(hk.angle_deg, 6) + "°";
  }
  std::sort(p.regions.begin(), p.regions.end());
  p.regions.erase(std::unique(p.regions.begin(), p.regions.end()), p.regions.end());
  const SheetHinge& closing = s.hinges[static_cast<std::size_t>(h)];
  p.at = {(closing.a.x_mm + closing.b.x_mm) / 2, (closing.a.v_mm + closing.b.v_mm) / 2};
  p.what = "the folds around a cycle of " + std::to_string(p.regions.size()) + " regions cannot all hold (" + names +
           "): the cycle misses closing by " + format_decimal(gap_mm, 3) + " mm";
  return p;
}

// "at 62.5% of the motion (stage 2 of 2)"
std::string when(double fraction, int stages) {
  std::string out = "at " + format_decimal(fraction * 100, 1) + "% of the motion";
  if (stages > 1)
    out += " (stage " + std::to_string(std::clamp(static_cast<int>(std::ceil(fraction * stages)), 1, stages)) + " of " +
           std::to_string(stages) + ")";
  return out;
}

}  // namespace

int stage_count(const FoldableSheet& s) {
  int k = 1;
  for (const SheetHinge& h : s.hinges) k = std::max(k, h.stage);
  return k;
}

double hinge_progress(const SheetHinge& h, int stages, double fraction) {
  return std::clamp(fraction * stages - (h.stage - 1), 0.0, 1.0);
}

Point3 apply(const Pose& pose, Point2 p) {
  const Point3 q = rotate(pose.r, {p.x_mm, p.v_mm, 0});
  return {q.x_mm + pose.t.x_mm, q.y_mm + pose.t.y_mm, q.z_mm + pose.t.z_mm};
}

SheetState fold_sheet(const FoldableSheet& s, double fraction, double closure_tolerance_mm) {
  const std::size_t n = s.map.regions.size();
  std::vector<std::vector<int>> at(n);  // hinges at each region
  for (std::size_t h = 0; h < s.hinges.size(); ++h) {
    at[static_cast<std::size_t>(s.hinges[h].left)].push_back(static_cast<int>(h));
    at[static_cast<std::size_t>(s.hinges[h].right)].push_back(static_cast<int>(h));
  }
  const int stages = stage_count(s);
  SheetState state;
  state.fraction = fraction;
  state.poses.assign(n, Pose{});
  std::vector<int> parent_hinge(n, -1);
  std::vector<bool> placed(n, false), walked(s.hinges.size(), false);
  std::vector<int> closing;
  for (const int root : s.piece_fixed) {
    std::vector<int> queue{root};
    placed[static_cast<std::size_t>(root)] = true;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int r = queue[q];
      for (const int h : at[static_cast<std::size_t>(r)]) {
        if (walked[static_cast<std::size_t>(h)]) continue;
        walked[static_cast<std::size_t>(h)] = true;
        const SheetHinge& hinge = s.hinges[static_cast<std::size_t>(h)];
        const int other = hinge.left == r ? hinge.right : hinge.left;
        if (placed[static_cast<std::size_t>(other)]) {
          closing.push_back(h);
          continue;
        }
        placed[static_cast<std::size_t>(other)] = true;
        parent_hinge[static_cast<std::size_t>(other)] = h;
        state.poses[static_cast<std::size_t>(other)] =
            across(state.poses[static_cast<std::size_t>(r)], hinge, other, hinge_progress(hinge, stages, fraction));
        queue.push_back(other);
      }
    }
  }
  for (const int h : closing) {
    const SheetHinge& hinge = s.hinges[static_cast<std::size_t>(h)];
    const Pose via = across(state.poses[static_cast<std::size_t>(hinge.left)], hinge, hinge.right,
                            hinge_progress(hinge, stages, fraction));
    const Pose& walked_pose = state.poses[static_cast<std::size_t>(hinge.right)];
    double gap = 0;
    for (Point2 p : s.map.regions[static_cast<std::size_t>(hinge.right)].outer)
      gap = std::max(gap, distance(apply(via, p), apply(walked_pose, p)));
    if (gap > closure_tolerance_mm) state.open_cycles.push_back(open_cycle(s, h, gap, parent_hinge));
  }
  return state;
}

CardMesh sheet_mesh(const FoldableSheet& s, const SheetState& state, double layer_gap_mm) {
  CardMesh mesh;
  mesh.face_kind.assign(s.map.regions.size(), FaceKind::horizontal);
  // Up the stack is +z in the flat-folded end state: a region turned over there lifts along −normal.
  const bool layered = layer_gap_mm > 0 && s.layer.size() == s.triangles.size();
  const SheetState end = layered ? fold_sheet(s, 1) : SheetState{};
  for (std::size_t r = 0; r < s.triangles.size(); ++r) {
    Point3 lift{};
    if (layered) {
      const double k = layer_gap_mm * s.layer[r] * (end.poses[r].r[8] > 0 ? 1 : -1);
      const Pose& p = state.poses[r];
      lift = {k * p.r[2], k * p.r[5], k * p.r[8]};
    }
    for (const auto& tri : s.triangles[r]) {
      std::array<std::uint32_t, 3> idx{};
      for (std::size_t k = 0; k < 3; ++k) {
        idx[k] = static_cast<std::uint32_t>(mesh.vertices.size());
        // Card coordinates, as for a card at 0° (y = −v): the writers' and the renderer's frame.
        const Point3 q = apply(state.poses[r], tri[k]);
        mesh.vertices.push_back({q.x_mm + lift.x_mm, -(q.y_mm + lift.y_mm), q.z_mm + lift.z_mm});
        mesh.pattern_points.push_back(tri[k]);
      }
      mesh.triangles.push_back(idx);
      mesh.triangle_face.push_back(static_cast<int>(r));
    }
  }
  return mesh;
}

SheetMotionReport check_sheet_motion(const FoldableSheet& s, int frames) {
  const int stages = stage_count(s);
  SheetMotionReport report;
  report.frames = std::clamp(frames, 2, kMaxMotionFrames);
  std::set<std::vector<int>> seen_cycles;
  std::set<std::pair<int, int>> seen_pairs;
  const auto region = [&](int r) {
    const Point2 p = s.map.regions[static_cast<std::size_t>(r)].label;
    return "region " + std::to_string(r) + " (around " + describe_place(p) + " on the sheet)";
  };
  for (int i = 0; i < report.frames; ++i) {
    const double f = static_cast<double>(i) / (report.frames - 1);
    const SheetState state = fold_sheet(s, f);
    for (SheetProblem p : state.open_cycles) {
      std::vector<int> key = p.hinges;
      std::sort(key.begin(), key.end());
      if (!seen_cycles.insert(key).second) continue;
      p.what += " " + when(f, stages);
      report.open_cycles.push_back({p, f});
    }
    for (const SheetCollision& c : find_collisions(s, state)) {
      if (!seen_pairs.insert({c.region_a, c.region_b}).second) continue;
      const std::string what = region(c.region_a) + " and " + region(c.region_b) + " pass through each other " +
                               when(f, stages) + ", near (" + format_decimal(c.at.x_mm, 1) + ", " +
                               format_decimal(c.at.y_mm, 1) + ", " + format_decimal(c.at.z_mm, 1) + ") mm in 3D";
      report.collisions.push_back(
          {{what, s.map.regions[static_cast<std::size_t>(c.region_a)].label, {c.region_a, c.region_b}, {}}, f});
    }
  }
  return report;
}

}  // namespace popcut
