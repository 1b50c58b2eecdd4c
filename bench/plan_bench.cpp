// Stroke planning: time per segment count, and a table of lifts, travel and time against naive orders.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bench_table.h"
#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/voxel_pattern.h"
#include "popcut/plan/plan.h"
#include "popcut/plan/travel_bound.h"
#include "popcut/text.h"
#include "random_models.h"

namespace {

using namespace popcut;

const std::string kSource = POPCUT_SOURCE_DIR;

// A staircase whose pattern has roughly `segments` lines (the count is reported, not assumed).
Pattern pattern_of(int scale) {
  std::mt19937_64 rng(42);
  VoxelModel m = testing::random_staircase(rng, 4 * scale, 2 * scale, 2 * scale, 2.0);
  return make_pattern(m);
}

void BM_Plan(benchmark::State& state) {
  const Pattern p = pattern_of(static_cast<int>(state.range(0)));
  PlanOptions o;  // the default work budget: what `popcut plan` spends
  o.optimise_work = static_cast<std::uint64_t>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(plan_strokes(p, o));
  state.counters["segments"] = static_cast<double>(p.lines.size());
}

void BM_Encode(benchmark::State& state) {
  const Pattern p = pattern_of(static_cast<int>(state.range(0)));
  const drivers::DeviceProfile prof = drivers::load_profile(kSource + "/configs/devices/generic-hpgl.toml");
  HpglDialect d = prof.dialect;
  d.area_max_x_pu = d.area_max_y_pu = 40 * 100000;  // the big sheets must fit
  PlanOptions o;
  o.optimise_work = 0;
  const StrokePlan plan = plan_strokes(p, o);
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string job = encode_hpgl(plan, d, prof.tools);
    bytes = job.size();
    benchmark::DoNotOptimize(job);
  }
  state.counters["segments"] = static_cast<double>(p.lines.size());
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
}

BENCHMARK(BM_Plan)
    ->ArgsProduct({{5, 10, 20, 40, 100, 120}, {0, static_cast<std::int64_t>(kDefaultOptimiseWork)}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Encode)->Arg(20)->Unit(benchmark::kMillisecond);

// (a) the pattern's own order: every line its own stroke, as given, kinds in the profile's order.
StrokePlan pattern_order(const Pattern& p, const PlanOptions& o) {
  StrokePlan plan;
  plan.sheet = p.sheet;
  plan.home = p.sheet.min;
  for (PlanKind k : o.order) {
    if (o.kinds[index_of(k)].mode == ToolMode::skip) continue;
    for (const Segment& s : kind_lines(p, k, o.fold_gap_mm)) plan.strokes.push_back({k, {s.a, s.b}});
  }
  return plan;
}

// (b) greedy nearest neighbour over the raw segments, with reversal, per kind: from where the
// knife stands, the nearest end of any segment not yet cut (ties: lower index, front end).
// Plain O(n²) and independent of the planner's own greedy, so improving popcut cannot move it.
StrokePlan greedy_segments(const Pattern& p, const PlanOptions& o) {
  StrokePlan plan;
  plan.sheet = p.sheet;
  plan.home = p.sheet.min;
  Point2 at = plan.home;
  const auto d = [](Point2 a, Point2 b) { return std::hypot(a.x_mm - b.x_mm, a.v_mm - b.v_mm); };
  for (PlanKind k : o.order) {
    if (o.kinds[index_of(k)].mode == ToolMode::skip) continue;
    std::vector<Segment> segs = kind_lines(p, k, o.fold_gap_mm);
    std::vector<char> done(segs.size(), 0);
    for (std::size_t step = 0; step < segs.size(); ++step) {
      std::size_t best = 0;
      bool best_back = false;
      double best_d = 1e300;
      for (std::size_t i = 0; i < segs.size(); ++i) {
        if (done[i]) continue;
        if (d(at, segs[i].a) < best_d) best_d = d(at, segs[i].a), best = i, best_back = false;
        if (d(at, segs[i].b) < best_d) best_d = d(at, segs[i].b), best = i, best_back = true;
      }
      done[best] = 1;
      const Segment& s = segs[best];
      plan.strokes.push_back({k, best_back ? std::vector<Point2>{s.b, s.a} : std::vector<Point2>{s.a, s.b}});
      at = plan.strokes.back().points.back();
    }
  }
  return plan;
}

std::vector<std::vector<Point2>> paths_of(const StrokePlan& plan) {
  std::vector<std::vector<Point2>> paths;
  for (const Stroke& s : plan.strokes) paths.push_back(s.points);
  return paths;
}

double travel(const StrokePlan& plan) { return travel_mm(paths_of(plan), plan.home); }

// Time spent on knife-up moves alone.
double travel_time_s(const StrokePlan& plan, const Kinematics& k) {
  double t = 0;
  Point2 at = plan.home;
  for (const Stroke& s : plan.strokes) {
    t += move_time_s(std::hypot(at.x_mm - s.points.front().x_mm, at.v_mm - s.points.front().v_mm), k.travel_speed_mm_s,
                     k.accel_mm_s2);
    at = s.points.back();
  }
  return t;
}

// The line graph of each kind in cutting order, as every plan at the Euler bound must cut it
// (perforated kinds: the plan's own dashes, each a stroke); `which` receives the kinds.
std::vector<std::vector<std::pair<Point2, Point2>>> kind_graphs(const Pattern& p, const PlanOptions& o,
                                                                const StrokePlan& c, std::vector<PlanKind>& which) {
  std::vector<std::vector<std::pair<Point2, Point2>>> kinds;
  for (PlanKind k : o.order) {
    const KindPlan& kp = o.kinds[index_of(k)];
    if (kp.mode == ToolMode::skip) continue;
    std::vector<std::pair<Point2, Point2>> edges;
    if (kp.mode == ToolMode::perforate) {
      for (const Stroke& s : c.strokes) {
        if (s.kind == k) edges.emplace_back(s.points.front(), s.points.back());
      }
    } else {
      for (const Segment& s : kind_lines(p, k, o.fold_gap_mm)) edges.emplace_back(s.a, s.b);
      edges = split_at_junctions(edges);
    }
    kinds.push_back(std::move(edges));
    which.push_back(k);
  }
  return kinds;
}

// Lengths of the maximal straight lines that `edges` make up (collinear edges that touch merged).
std::vector<double> straight_runs_mm(const std::vector<std::pair<Point2, Point2>>& edges) {
  std::map<std::pair<long long, long long>, std::vector<std::pair<double, double>>>
      lines;  // (angle, offset) -> intervals
  for (auto [a, b] : edges) {
    double dx = b.x_mm - a.x_mm, dv = b.v_mm - a.v_mm;
    const double len = std::hypot(dx, dv);
    if (len <= 0) continue;
    dx /= len, dv /= len;
    if (dv < 0 || (dv == 0 && dx < 0)) dx = -dx, dv = -dv;  // one direction per line
    const double offset = dx * a.v_mm - dv * a.x_mm, s0 = dx * a.x_mm + dv * a.v_mm, s1 = dx * b.x_mm + dv * b.v_mm;
    lines[{std::llround(std::atan2(dv, dx) * 1e6), std::llround(offset * 1e4)}].emplace_back(std::min(s0, s1),
                                                                                             std::max(s0, s1));
  }
  std::vector<double> runs;
  for (auto& [line, spans] : lines) {
    std::sort(spans.begin(), spans.end());
    double lo = spans.front().first, hi = spans.front().second;
    for (const auto& [s0, s1] : spans) {
      if (s0 > hi + 1e-6) runs.push_back(hi - lo), lo = s0;
      hi = std::max(hi, s1);
    }
    runs.push_back(hi - lo);
  }
  return runs;
}

// A lower bound on the time every plan at the Euler bound spends with the knife down or going up
// and down: each maximal straight line at least in one move (the model stops at every vertex, and
// move_time_s is subadditive: pieces never take less than the whole), and one knife down and up
// per stroke of the Euler bound. Single pass, no blade offset (generic-hpgl).
double fixed_time_lower_bound_s(const std::vector<std::vector<std::pair<Point2, Point2>>>& kinds,
                                const std::vector<PlanKind>& which, const Kinematics& k,
                                const std::array<double, 4>& speed_mm_s) {
  double t = 0;
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    for (double run : straight_runs_mm(kinds[i])) t += move_time_s(run, speed_mm_s[index_of(which[i])], k.accel_mm_s2);
    t += euler_bound(kinds[i]) * (k.knife_down_s + k.knife_up_s);
  }
  return t;
}

// The best order of (c)'s own strokes per kind, from where (c) starts each kind: Held-Karp over
// (strokes cut, last stroke, how it was entered); -1 when a kind is too big to solve exactly.
double exact_order_travel(const StrokePlan& c) {
  constexpr std::size_t kMaxStrokes = 10, kMaxOptions = 8;
  const auto d = [](Point2 a, Point2 b) { return std::hypot(a.x_mm - b.x_mm, a.v_mm - b.v_mm); };
  double total = 0;
  Point2 at = c.home;
  for (std::size_t first = 0; first < c.strokes.size();) {
    std::size_t end = first;
    while (end < c.strokes.size() && c.strokes[end].kind == c.strokes[first].kind) ++end;
    const std::size_t n = end - first;
    if (n > kMaxStrokes) return -1;
    std::vector<std::vector<std::pair<Point2, Point2>>> opts(n);  // (knife down, knife up)
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = c.strokes[first + i].points;
      if (p.size() > 2 && d(p.front(), p.back()) < 1e-9) {
        if (p.size() - 1 > kMaxOptions) return -1;
        for (std::size_t k = 0; k + 1 < p.size(); ++k) opts[i].emplace_back(p[k], p[k]);
      } else {
        opts[i] = {{p.front(), p.back()}, {p.back(), p.front()}};
      }
    }
    const std::size_t full = (std::size_t{1} << n) - 1;
    std::vector<double> dp((full + 1) * n * kMaxOptions, 1e300);
    const auto at_ = [&](std::size_t mask, std::size_t s, std::size_t o) -> double& {
      return dp[(mask * n + s) * kMaxOptions + o];
    };
    for (std::size_t s = 0; s < n; ++s) {
      for (std::size_t o = 0; o < opts[s].size(); ++o) at_(std::size_t{1} << s, s, o) = d(at, opts[s][o].first);
    }
    for (std::size_t mask = 1; mask <= full; ++mask) {
      for (std::size_t s = 0; s < n; ++s) {
        if (!(mask >> s & 1)) continue;
        for (std::size_t o = 0; o < opts[s].size(); ++o) {
          const double v = at_(mask, s, o);
          if (v >= 1e300) continue;
          for (std::size_t t = 0; t < n; ++t) {
            if (mask >> t & 1) continue;
            for (std::size_t u = 0; u < opts[t].size(); ++u) {
              double& w = at_(mask | std::size_t{1} << t, t, u);
              w = std::min(w, v + d(opts[s][o].second, opts[t][u].first));
            }
          }
        }
      }
    }
    double best = 1e300;
    for (std::size_t s = 0; s < n; ++s) {
      for (std::size_t o = 0; o < opts[s].size(); ++o) best = std::min(best, at_(full, s, o));
    }
    total += best;
    at = c.strokes[end - 1].points.back();
    first = end;
  }
  return total;
}

void print_table(const bench::CollectingReporter& reporter) {
  std::printf(
      "\nPlanning time, whole plan_strokes (BM_Plan/scale/work: work 0 = greedy only, %llu = the default budget);\n"
      "target: under 100 ms for 10,000 segments\n",
      static_cast<unsigned long long>(kDefaultOptimiseWork));
  for (const auto& row : reporter.rows()) {
    if (row.name.rfind("BM_Plan", 0) == 0) {
      std::printf("  %-14s %8.0f segments %9.2f ms\n", row.name.c_str(), row.counters.at("segments"), row.ms);
    }
  }
  const drivers::DeviceProfile prof = drivers::load_profile(kSource + "/configs/devices/generic-hpgl.toml");
  std::vector<std::pair<std::string, Pattern>> cases;
  for (const char* ex : {"voxel/box.json", "voxel/pyramid.json", "voxel/castle.json", "voxel/townhouse.json",
                         "faces/porch.json", "faces/openings.json"}) {
    cases.emplace_back(ex, make_pattern(load_model(kSource + "/examples/" + ex)));
  }
  std::mt19937_64 rng(9);
  testing::RandomModelSpec spec;
  spec.max_width = 30;
  spec.max_depth = 10;
  spec.max_height = 20;
  spec.window_probability = 0.2;
  for (int i = 0; i < 3; ++i)
    cases.emplace_back("random-" + std::to_string(i), make_pattern(testing::random_model(rng, spec)));
  std::printf(
      "\nProfile generic-hpgl; travel = knife-up mm; time = estimated s. (a) pattern order, (b) greedy over raw "
      "segments,\n"
      "(c) popcut. Targets: lifts at the bound, travel(c) <= 0.75 x travel(b), time(c) <= 0.6 x time(a).\n"
      "LB: a lower bound on knife-up travel over ALL plans at the Euler bound (any trail decomposition, order, "
      "direction,\n"
      "loop start; kinds in the profile's order, from home): min-weight perfect matching of stroke ends (match) raised "
      "by\n"
      "connectivity cuts (Lagrangian); see knife_up_lower_bound. t-LB: a lower bound on time for all such plans: that\n"
      "bound over move times, plus each maximal straight line cut in one move and one knife down/up per stroke.\n"
      "LB/b > 0.75 or t-LB/a > 0.6: no plan at the Euler bound meets that target on that model (under this time "
      "model).\n"
      "opt: the best order of (c)'s own strokes per kind (exhaustive, kinds of at most 10 strokes); c x100: (c) with "
      "100x\n"
      "the work budget (equal to travel(c): the search converged).\n");
  std::printf("%-20s %5s %5s %5s %6s | %9s %9s %9s %7s %6s %6s %6s %5s %5s | %7s %7s %6s %5s %5s | %7s\n", "model",
              "lines", "lifts", "bound", "lift(a)", "travel(a)", "travel(b)", "travel(c)", "c x100", "opt", "match",
              "LB", "c/b", "LB/b", "time(a)", "time(c)", "t-LB", "c/a", "LB/a", "plan ms");
  const auto speeds = prof.cut_speed_mm_s();
  std::vector<std::string> split_rows;  // where the time goes, printed after the table
  for (const auto& [name, p] : cases) {
    PlanOptions o = prof.plan;
    const auto t0 = std::chrono::steady_clock::now();
    const StrokePlan c = plan_strokes(p, o);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const StrokePlan a = pattern_order(p, o), b = greedy_segments(p, o);
    const double ta = estimate_time(a, prof.kinematics, speeds).total_s,
                 tc = estimate_time(c, prof.kinematics, speeds).total_s;
    const double tra = travel(a), trb = travel(b), trc = travel(c);
    std::vector<PlanKind> which;
    const auto kinds = kind_graphs(p, o, c, which);
    const Kinematics& kin = prof.kinematics;
    const KnifeUpBound lb = knife_up_lower_bound(
        kinds, c.home, [](double mm) { return mm; }, trc);
    const double up_s = travel_time_s(c, kin);
    const auto move_s = [&](double mm) { return move_time_s(mm, kin.travel_speed_mm_s, kin.accel_mm_s2); };
    const double fixed_lb = fixed_time_lower_bound_s(kinds, which, kin, speeds);
    const double up_lb = knife_up_lower_bound(kinds, c.home, move_s, up_s).value, t_lb = fixed_lb + up_lb;
    const double up_a = travel_time_s(a, kin),
                 knife_a = static_cast<double>(a.strokes.size()) * (kin.knife_down_s + kin.knife_up_s);
    char row[200];
    std::snprintf(row, sizeof row, "%-20s | %7.1f %7.1f %7.1f | %7.1f %7.1f | %7.1f %7.1f | %5.2f\n", name.c_str(),
                  ta - up_a - knife_a, knife_a, up_a, tc - up_s, up_s, fixed_lb, up_lb, fixed_lb / ta);
    split_rows.emplace_back(row);
    PlanOptions more = o;
    more.optimise_work = 100 * o.optimise_work;
    const double tr_more = travel(plan_strokes(p, more)), opt = exact_order_travel(c);
    const std::string opt_text = opt >= 0 ? format_fixed(opt, 0) : "-";
    std::printf(
        "%-20s %5zu %5d %5d %6zu | %9.0f %9.0f %9.0f %7.0f %6s %6.0f %6.0f %5.2f %5.2f | %7.1f %7.1f %6.1f %5.2f %5.2f "
        "| %7.1f\n",
        name.c_str(), p.lines.size(), c.total().pen_lifts, c.total().pen_lift_bound, a.strokes.size(), tra, trb, trc,
        tr_more, opt_text.c_str(), lb.matching, lb.value, trb > 0 ? trc / trb : 0.0, trb > 0 ? lb.value / trb : 0.0, ta,
        tc, t_lb, ta > 0 ? tc / ta : 0.0, ta > 0 ? t_lb / ta : 0.0, ms);
  }
  std::printf(
      "\nWhere the time goes (s): knife down (cutting), knife up/down, knife-up moves; for (a), (c) and the bounds\n"
      "(fixed LB: cutting each straight line in one move plus knife up/down at the Euler bound, the same for every "
      "plan;\n"
      "fixed LB/time(a) > 0.6: even with no knife-up moves at all, no plan meets time <= 0.6 x time(a)).\n");
  std::printf("%-20s | %7s %7s %7s | %7s %7s | %7s %7s | %5s\n", "model", "cut(a)", "knife(a)", "up(a)", "cut+k(c)",
              "up(c)", "fixed LB", "up LB", "fixed/a");
  for (const std::string& row : split_rows) std::fputs(row.c_str(), stdout);
  std::printf("\nHP-GL bytes per mm cut, townhouse, per profile\n");
  const Pattern town = make_pattern(load_model(kSource + "/examples/voxel/townhouse.json"));
  for (const char* f : {"generic-hpgl", "roland-gx24", "graphtec-ce", "uscutter-mh", "secabo", "sim"}) {
    const drivers::DeviceProfile pr = drivers::load_profile(kSource + "/configs/devices/" + f + ".toml");
    const StrokePlan plan = plan_strokes(town, pr.plan);
    const std::string job = encode_hpgl(plan, pr.dialect, pr.tools);
    std::printf("  %-14s %6zu bytes %8.0f mm %6.2f bytes/mm\n", f, job.size(), plan.total().cut_mm,
                double(job.size()) / plan.total().cut_mm);
  }
}

}  // namespace

int main(int argc, char** argv) { return popcut::bench::run_with_table(argc, argv, print_table); }
