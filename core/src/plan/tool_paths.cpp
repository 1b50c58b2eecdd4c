// Tool paths along one ordered path: perforation dashes, passes, overcut, precut and the drag knife's axis path.
#include "popcut/plan/tool_paths.h"

#include <algorithm>
#include <cmath>

#include "plan/path_geometry.h"

namespace popcut {

using plan_detail::dist;
using plan_detail::kEps;
using plan_detail::kPi;
using plan_detail::lerp;

double path_length_mm(const std::vector<Point2>& path) {
  double l = 0;
  for (std::size_t i = 1; i < path.size(); ++i) l += dist(path[i - 1], path[i]);
  return l;
}

std::vector<std::vector<Point2>> perforate(const std::vector<Point2>& path, double on_mm, double off_mm) {
  const double length = path_length_mm(path);
  if (!(length > 0)) return {};
  const double n_real = std::floor((length - off_mm) / (on_mm + off_mm));
  int n = 1;
  double on = on_mm;
  if (n_real < 1) {
    // Shorter than one dash and its gaps: one shorter dash, still with uncut ends, so the
    // fold is still made (dropping it would leave a short fold unscored without a word).
    on = length - 2 * std::min(off_mm, length / 4);
  } else {
    n = static_cast<int>(n_real);
  }
  const double gap = (length - n * on) / (n + 1);
  // Walk the polyline once, cutting out [start_i, start_i + on] for each dash.
  std::vector<std::vector<Point2>> dashes;
  std::size_t seg = 0;
  double seg_start = 0;  // arc length at path[seg]
  const auto point_at = [&](double s) {
    while (seg + 2 < path.size() && seg_start + dist(path[seg], path[seg + 1]) < s) {
      seg_start += dist(path[seg], path[seg + 1]);
      ++seg;
    }
    const double l = dist(path[seg], path[seg + 1]);
    return lerp(path[seg], path[seg + 1], l > 0 ? std::clamp((s - seg_start) / l, 0.0, 1.0) : 0.0);
  };
  for (int i = 0; i < n; ++i) {
    const double s0 = gap + i * (on + gap), s1 = s0 + on;
    std::vector<Point2> dash{point_at(s0)};
    // Keep the path's corners that fall inside the dash.
    while (seg + 1 < path.size() && seg_start + dist(path[seg], path[seg + 1]) < s1) {
      seg_start += dist(path[seg], path[seg + 1]);
      ++seg;
      dash.push_back(path[seg]);
    }
    dash.push_back(point_at(s1));
    dashes.push_back(std::move(dash));
  }
  return dashes;
}

std::vector<Point2> without_straight_vertices(const std::vector<Point2>& path) {
  if (path.size() < 3) return path;
  std::vector<Point2> out{path.front()};
  for (std::size_t i = 1; i + 1 < path.size(); ++i) {
    const Point2 a = out.back(), b = path[i], c = path[i + 1];
    const double ux = b.x_mm - a.x_mm, uv = b.v_mm - a.v_mm, wx = c.x_mm - b.x_mm, wv = c.v_mm - b.v_mm;
    const double len = dist(a, c);
    const bool straight =
        len > 0 && std::abs(ux * (c.v_mm - a.v_mm) - uv * (c.x_mm - a.x_mm)) / len <= kEps && ux * wx + uv * wv > 0;
    if (!straight) out.push_back(b);
  }
  out.push_back(path.back());
  return out;
}

std::vector<Point2> with_passes(const std::vector<Point2>& path, int passes) {
  std::vector<Point2> out = path;
  std::vector<Point2> last = path;
  for (int p = 1; p < passes; ++p) {
    last = plan_detail::reversed(last);  // alternate direction: the knife never lifts between passes
    out.insert(out.end(), last.begin() + 1, last.end());
  }
  return out;
}

std::vector<std::vector<Point2>> separate_passes(const std::vector<Point2>& path, int passes) {
  std::vector<std::vector<Point2>> out;
  for (int p = 0; p < passes; ++p) out.push_back(p == 0 ? path : plan_detail::reversed(out.back()));
  return out;
}

std::vector<Point2> precut_path(const std::vector<Point2>& tip_path, double precut_mm) {
  if (precut_mm <= 0 || tip_path.size() < 2) return {};
  const Point2 a = tip_path[0], b = tip_path[1];
  const double len = dist(a, b);
  if (!(len > 0)) return {};
  return {a, lerp(a, b, std::min(1.0, precut_mm / len))};
}

std::vector<Point2> with_overcut(const std::vector<Point2>& path, double overcut_mm) {
  if (overcut_mm <= 0 || !plan_detail::is_closed(path)) return path;
  std::vector<Point2> out = path;
  double left = overcut_mm;
  for (std::size_t i = 1; i < path.size() && left > 0; ++i) {
    const double l = dist(path[i - 1], path[i]);
    if (l >= left) {
      out.push_back(lerp(path[i - 1], path[i], left / l));
      break;
    }
    out.push_back(path[i]);
    left -= l;
  }
  return out;
}

std::vector<Point2> blade_offset_path(const std::vector<Point2>& tip, double offset_mm, double swivel_step_deg) {
  std::vector<Point2> pts;
  for (Point2 p : tip) {
    if (pts.empty() || !plan_detail::same(pts.back(), p)) pts.push_back(p);
  }
  if (offset_mm <= 0 || pts.size() < 2) return pts;
  const auto unit = [](Point2 a, Point2 b) {
    const double l = dist(a, b);
    return Point2{(b.x_mm - a.x_mm) / l, (b.v_mm - a.v_mm) / l};
  };
  const auto ahead = [&](Point2 p, Point2 d) {
    return Point2{p.x_mm + offset_mm * d.x_mm, p.v_mm + offset_mm * d.v_mm};
  };
  const double step = std::max(1.0, swivel_step_deg) * kPi / 180;
  std::vector<Point2> out{ahead(pts[0], unit(pts[0], pts[1]))};
  for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
    const Point2 d0 = unit(pts[i - 1], pts[i]), d1 = unit(pts[i], pts[i + 1]);
    out.push_back(ahead(pts[i], d0));
    // Swivel: the axis circles the tip (which stays at the corner) from the old heading to the
    // new, the short way round, so the blade turns in place.
    const double a0 = std::atan2(d0.v_mm, d0.x_mm);
    const double turn = std::atan2(d0.x_mm * d1.v_mm - d0.v_mm * d1.x_mm, d0.x_mm * d1.x_mm + d0.v_mm * d1.v_mm);
    const int n = static_cast<int>(std::ceil(std::abs(turn) / step));
    for (int k = 1; k <= n; ++k) {
      const double a = a0 + turn * k / n;
      out.push_back({pts[i].x_mm + offset_mm * std::cos(a), pts[i].v_mm + offset_mm * std::sin(a)});
    }
  }
  out.push_back(ahead(pts.back(), unit(pts[pts.size() - 2], pts.back())));
  return out;
}

}  // namespace popcut
