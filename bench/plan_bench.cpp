// Stroke planning: time per segment count, and a table of lifts, travel and time against naive orders.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bench_table.h"
#include "popcut/drivers/profile.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/voxel_pattern.h"
#include "popcut/plan/plan.h"
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
  PlanOptions o;
  o.optimise_budget = std::chrono::milliseconds(0);  // the time budget is extra, measured apart
  for (auto _ : state) benchmark::DoNotOptimize(plan_strokes(p, o));
  state.counters["segments"] = static_cast<double>(p.lines.size());
}

void BM_Encode(benchmark::State& state) {
  const Pattern p = pattern_of(static_cast<int>(state.range(0)));
  const drivers::DeviceProfile prof = drivers::load_profile(kSource + "/configs/devices/generic-hpgl.toml");
  HpglDialect d = prof.dialect;
  d.area_max_x_pu = d.area_max_y_pu = 40 * 100000;  // the big sheets must fit
  PlanOptions o;
  o.optimise_budget = std::chrono::milliseconds(0);
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

BENCHMARK(BM_Plan)->Arg(5)->Arg(10)->Arg(20)->Arg(40)->Arg(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Encode)->Arg(20)->Unit(benchmark::kMillisecond);

// (a) the pattern's own order: every line its own stroke, as given, kinds in the profile's order.
StrokePlan pattern_order(const Pattern& p, const PlanOptions& o) {
  StrokePlan plan;
  plan.sheet = p.sheet;
  plan.home = p.sheet.min;
  for (PlanKind k : o.order) {
    for (const Segment& s : kind_lines(p, k, o.fold_gap_mm)) plan.strokes.push_back({k, {s.a, s.b}});
  }
  return plan;
}

// (b) greedy nearest neighbour over the raw segments, with reversal, per kind.
StrokePlan greedy_segments(const Pattern& p, const PlanOptions& o) {
  StrokePlan plan;
  plan.sheet = p.sheet;
  plan.home = p.sheet.min;
  Point2 at = plan.home;
  for (PlanKind k : o.order) {
    std::vector<std::vector<Point2>> paths;
    for (const Segment& s : kind_lines(p, k, o.fold_gap_mm)) paths.push_back({s.a, s.b});
    for (auto& path : order_paths(paths, at, std::chrono::milliseconds(0))) {
      at = path.back();
      plan.strokes.push_back({k, std::move(path)});
    }
  }
  return plan;
}

double travel(const StrokePlan& plan) {
  std::vector<std::vector<Point2>> paths;
  for (const Stroke& s : plan.strokes) paths.push_back(s.points);
  return travel_mm(paths, plan.home);
}

void print_table(const bench::CollectingReporter& reporter) {
  std::printf("\nPlanning time (greedy + chaining, no 2-opt budget); target: under 100 ms for 10,000 segments\n");
  for (const auto& row : reporter.rows()) {
    if (row.name.rfind("BM_Plan", 0) == 0) {
      std::printf("  %-14s %8.0f segments %9.2f ms\n", row.name.c_str(), row.counters.at("segments"), row.ms);
    }
  }
  const drivers::DeviceProfile prof = drivers::load_profile(kSource + "/configs/devices/generic-hpgl.toml");
  std::vector<std::pair<std::string, Pattern>> cases;
  for (const char* ex : {"voxel/box.json", "voxel/pyramid.json", "voxel/castle.json", "voxel/townhouse.json", "faces/porch.json",
                         "faces/openings.json"}) {
    cases.emplace_back(ex, make_pattern(load_model(kSource + "/examples/" + ex)));
  }
  std::mt19937_64 rng(9);
  testing::RandomModelSpec spec;
  spec.max_width = 30;
  spec.max_depth = 10;
  spec.max_height = 20;
  spec.window_probability = 0.2;
  for (int i = 0; i < 3; ++i) cases.emplace_back("random-" + std::to_string(i), make_pattern(testing::random_model(rng, spec)));
  std::printf("\nProfile generic-hpgl; travel = knife-up mm; time = estimated s. (a) pattern order, (b) greedy over raw segments,\n"
              "(c) popcut. Targets: lifts at the bound, travel(c) <= 0.75 x travel(b), time(c) <= 0.6 x time(a).\n");
  std::printf("%-22s %6s %6s %6s %6s | %9s %9s %9s %6s | %8s %8s %6s\n", "model", "lines", "lifts", "bound", "lift(a)", "travel(a)",
              "travel(b)", "travel(c)", "c/b", "time(a)", "time(c)", "c/a");
  const auto speeds = prof.cut_speed_mm_s();
  for (const auto& [name, p] : cases) {
    PlanOptions o = prof.plan;
    const StrokePlan a = pattern_order(p, o), b = greedy_segments(p, o), c = plan_strokes(p, o);
    const double ta = estimate_time(a, prof.kinematics, speeds).total_s, tc = estimate_time(c, prof.kinematics, speeds).total_s;
    const double tra = travel(a), trb = travel(b), trc = travel(c);
    std::printf("%-22s %6zu %6d %6d %6zu | %9.0f %9.0f %9.0f %6.2f | %8.1f %8.1f %6.2f\n", name.c_str(), p.lines.size(), c.total().pen_lifts,
                c.total().pen_lift_bound, a.strokes.size(), tra, trb, trc, trb > 0 ? trc / trb : 0.0, ta, tc, ta > 0 ? tc / ta : 0.0);
  }
  std::printf("\nHP-GL bytes per mm cut, townhouse, per profile\n");
  const Pattern town = make_pattern(load_model(kSource + "/examples/voxel/townhouse.json"));
  for (const char* f : {"generic-hpgl", "roland-gx24", "graphtec-ce", "uscutter-mh", "secabo", "sim"}) {
    const drivers::DeviceProfile pr = drivers::load_profile(kSource + "/configs/devices/" + f + ".toml");
    const StrokePlan plan = plan_strokes(town, pr.plan);
    const std::string job = encode_hpgl(plan, pr.dialect, pr.tools);
    std::printf("  %-14s %6zu bytes %8.0f mm %6.2f bytes/mm\n", f, job.size(), plan.total().cut_mm, double(job.size()) / plan.total().cut_mm);
  }
}

}  // namespace

int main(int argc, char** argv) { return popcut::bench::run_with_table(argc, argv, print_table); }
