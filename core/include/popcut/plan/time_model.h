// The time model: how long a plotter takes over a plan (trapezoidal speed profile, a stop at every vertex).
#pragma once

#include <array>
#include <functional>

namespace popcut {

struct StrokePlan;
struct Stroke;

// Motion-time model of a plotter.
struct Kinematics {
  double travel_speed_mm_s = 300;
  double accel_mm_s2 = 2000;
  double knife_up_s = 0.03;
  double knife_down_s = 0.03;
};
double move_time_s(double length_mm, double speed_mm_s, double accel_mm_s2);
struct TimeEstimate {
  double total_s = 0;
  std::array<double, 4> kind_s{};  // travel to a kind's strokes counts for that kind
};
// cut_speed_mm_s per kind (indexed by index_of); every stroke also pays knife down and up.
TimeEstimate estimate_time(const StrokePlan& plan, const Kinematics& k, const std::array<double, 4>& cut_speed_mm_s);
// The same with each stroke's own knife-down speed (per-pass speeds differ within a kind).
TimeEstimate estimate_time(const StrokePlan& plan, const Kinematics& k,
                           const std::function<double(const Stroke&)>& cut_speed_mm_s);

}  // namespace popcut
