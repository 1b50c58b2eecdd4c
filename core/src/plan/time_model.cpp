// The time model: trapezoidal moves, knife up and down per stroke, summed per kind over a plan.
#include "popcut/plan/time_model.h"

#include <cmath>

#include "plan/path_geometry.h"
#include "popcut/plan/plan.h"

namespace popcut {

double move_time_s(double length_mm, double speed_mm_s, double accel_mm_s2) {
  if (length_mm <= 0 || speed_mm_s <= 0) return 0;
  if (accel_mm_s2 <= 0) return length_mm / speed_mm_s;
  const double ramp_mm = speed_mm_s * speed_mm_s / accel_mm_s2;  // accelerate + decelerate
  if (length_mm >= ramp_mm) return length_mm / speed_mm_s + speed_mm_s / accel_mm_s2;
  return 2 * std::sqrt(length_mm / accel_mm_s2);
}

TimeEstimate estimate_time(const StrokePlan& plan, const Kinematics& k, const std::array<double, 4>& cut_speed_mm_s) {
  return estimate_time(plan, k, [&](const Stroke& s) { return cut_speed_mm_s[index_of(s.kind)]; });
}

TimeEstimate estimate_time(const StrokePlan& plan, const Kinematics& k,
                           const std::function<double(const Stroke&)>& cut_speed_mm_s) {
  using plan_detail::dist;
  TimeEstimate est;
  Point2 at = plan.home;
  for (const Stroke& s : plan.strokes) {
    double& t = est.kind_s[index_of(s.kind)];
    t += move_time_s(dist(at, s.points.front()), k.travel_speed_mm_s, k.accel_mm_s2) + k.knife_down_s + k.knife_up_s;
    const double speed_mm_s = cut_speed_mm_s(s);
    for (std::size_t i = 1; i < s.points.size(); ++i) {
      t += move_time_s(dist(s.points[i - 1], s.points[i]), speed_mm_s, k.accel_mm_s2);
    }
    at = s.points.back();
  }
  for (double t : est.kind_s) est.total_s += t;
  return est;
}

}  // namespace popcut
