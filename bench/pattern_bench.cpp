// Pattern generation speed: the voxel paper's size (80 × 40 × 40) up to ten times it per axis.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "bench_table.h"
#include "random_models.h"

namespace {

// Width × depth × height; the paper's model is 80 wide, 40 deep, 40 high (§4).
struct Size {
  int width, depth, height;
};

popcut::VoxelModel model_of(int scale) {
  std::mt19937_64 rng(42);
  popcut::VoxelModel m = popcut::testing::random_staircase(rng, 8 * scale, 4 * scale, 4 * scale, 1.0);
  // Windows on a tenth of the rows, as a designed card might have.
  for (int x = 0; x < m.width; ++x)
    for (int z = 0; z < m.h(x, 0); ++z) m.set_window(x, z, rng() % 10 == 0);
  return m;
}

std::int64_t cells_of(const popcut::VoxelModel& m) {
  const popcut::SheetVoxels s = popcut::resolve_sheet(m, "");
  return std::int64_t{m.width + 2 * s.side} * (s.back + s.floor);
}

void BM_Pattern(benchmark::State& state) {
  const popcut::VoxelModel m = model_of(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(popcut::make_pattern(m));
  state.counters["cells"] = static_cast<double>(cells_of(m));
}

void BM_PatternAndCheck(benchmark::State& state) {
  const popcut::VoxelModel m = model_of(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const popcut::Pattern p = popcut::make_pattern(m);
    benchmark::DoNotOptimize(popcut::check_popup(p));
  }
  state.counters["cells"] = static_cast<double>(cells_of(m));
}

BENCHMARK(BM_Pattern)->Arg(10)->Arg(20)->Arg(40)->Arg(60)->Arg(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PatternAndCheck)->Arg(10)->Arg(100)->Unit(benchmark::kMillisecond);

void print_table(const popcut::bench::CollectingReporter& reporter) {
  std::printf("\n%-28s %12s %12s %10s %12s  %s\n", "benchmark", "pattern cells", "time (ms)", "ns/cell", "target",
              "met");
  for (const auto& row : reporter.rows()) {
    const double cells = row.counters.at("cells");
    const bool paper = row.name.size() >= 3 && row.name.compare(row.name.size() - 3, 3, "/10") == 0;
    const bool big = row.name.find("/100") != std::string::npos;
    const double ns_per_cell = row.ms * 1e6 / cells;
    std::string met = paper ? (row.ms < 5 ? "yes" : "NO") : "";
    if (big) {
      // Linear growth: ns per cell at 10x per axis within 2x of the paper size's.
      const auto* base = reporter.find(row.name.substr(0, row.name.find('/')) + "/10");
      if (base) met = ns_per_cell <= 2 * base->ms * 1e6 / base->counters.at("cells") ? "yes" : "NO";
    }
    std::printf("%-28s %12.0f %12.3f %10.1f %12s  %s\n", row.name.c_str(), cells, row.ms, ns_per_cell,
                paper ? "< 5 ms" : (big ? "linear" : ""), met.c_str());
  }
  std::printf("(scale 10 = the voxel paper's 80 x 40 x 40 model; scale 100 = 800 x 400 x 400)\n");
}

}  // namespace

int main(int argc, char** argv) { return popcut::bench::run_with_table(argc, argv, print_table); }
