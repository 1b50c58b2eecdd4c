// Patterns drawn elsewhere: SVG and DXF read + sheet map + card inference for 100 to 10,000 segments (target < 200 ms
// at 10,000).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <random>
#include <sstream>

#include "bench_table.h"
#include "popcut/io/drawing_io.h"
#include "popcut/io/pattern_io.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"

namespace {

// A random staircase card `width` voxels across as popcut's own SVG: its lines are the drawing.
// 1 mm voxels put every coordinate on a double; 0.7 mm ones give decimals no double holds, as
// drawings from elsewhere mostly have.
const std::string& staircase_svg(int width, double voxel_mm = 1.0) {
  static std::map<std::pair<int, double>, std::string> made;
  auto& svg = made[{width, voxel_mm}];
  if (svg.empty()) {
    std::mt19937_64 rng(42);
    svg = popcut::to_pattern_svg(popcut::make_pattern(popcut::testing::random_staircase(rng, width, 40, 40, voxel_mm)));
  }
  return svg;
}

// The same card as popcut's own DXF, as CAD software would get it.
const std::string& staircase_dxf(int width) {
  static std::map<int, std::string> made;
  auto& dxf = made[width];
  if (dxf.empty()) {
    std::mt19937_64 rng(42);
    std::ostringstream out;
    popcut::write_pattern_dxf(out, popcut::make_pattern(popcut::testing::random_staircase(rng, width, 40, 40, 1.0)));
    dxf = out.str();
  }
  return dxf;
}

double segments(const popcut::LineDrawing& d) { return static_cast<double>(popcut::segment_count(d)); }

void BM_ReadSvg(benchmark::State& state) {
  const std::string& svg = staircase_svg(static_cast<int>(state.range(0)));
  popcut::LineDrawing d;
  for (auto _ : state) benchmark::DoNotOptimize(d = popcut::read_svg_drawing(svg, "bench.svg"));
  state.counters["segments"] = segments(d);
}

void BM_ReadDxf(benchmark::State& state) {
  const std::string& dxf = staircase_dxf(static_cast<int>(state.range(0)));
  popcut::LineDrawing d;
  for (auto _ : state) benchmark::DoNotOptimize(d = popcut::read_dxf_drawing(dxf, "bench.dxf"));
  state.counters["segments"] = segments(d);
}

void BM_SheetMap(benchmark::State& state) {
  const popcut::LineDrawing d = popcut::read_svg_drawing(staircase_svg(static_cast<int>(state.range(0))), "bench.svg");
  for (auto _ : state) benchmark::DoNotOptimize(popcut::build_sheet_map(d));
  state.counters["segments"] = segments(d);
}

void BM_InferCard(benchmark::State& state) {
  const popcut::LineDrawing d = popcut::read_svg_drawing(staircase_svg(static_cast<int>(state.range(0))), "bench.svg");
  const popcut::SheetMap map = popcut::build_sheet_map(d);
  for (auto _ : state) benchmark::DoNotOptimize(popcut::infer_card(d, map));
  state.counters["segments"] = segments(d);
}

// The whole import, text to face model.
void import_card(benchmark::State& state, double voxel_mm) {
  const std::string& svg = staircase_svg(static_cast<int>(state.range(0)), voxel_mm);
  double n = 0;
  for (auto _ : state) {
    const popcut::LineDrawing d = popcut::read_svg_drawing(svg, "bench.svg");
    const popcut::InferredCard card = popcut::infer_card(d, popcut::build_sheet_map(d));
    if (!card.model) state.SkipWithError("the staircase did not import as a card");
    n = segments(d);
  }
  state.counters["segments"] = n;
}

void BM_ImportCard(benchmark::State& state) { import_card(state, 1.0); }
void BM_ImportDecimalCard(benchmark::State& state) { import_card(state, 0.7); }

BENCHMARK(BM_ReadSvg)->Arg(8)->Arg(80)->Arg(720)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadDxf)->Arg(8)->Arg(80)->Arg(720)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SheetMap)->Arg(8)->Arg(80)->Arg(720)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_InferCard)->Arg(8)->Arg(80)->Arg(720)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImportCard)->Arg(8)->Arg(80)->Arg(720)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ImportDecimalCard)->Arg(720)->Unit(benchmark::kMillisecond);

void print_table(const popcut::bench::CollectingReporter& reporter) {
  std::printf("\n%-22s %10s %12s %16s\n", "benchmark", "segments", "time (ms)", "us per segment");
  for (const auto& row : reporter.rows()) {
    const auto s = row.counters.find("segments");
    const double n = s == row.counters.end() ? 0 : s->second;
    std::printf("%-22s %10.0f %12.3f %16.2f\n", row.name.c_str(), n, row.ms, n > 0 ? 1000 * row.ms / n : 0);
  }
  for (const auto& row : reporter.rows()) {
    if (row.name.rfind("BM_Import", 0) != 0) continue;
    const double n = row.counters.at("segments");
    std::printf("%s, %.0f segments: %.1f ms (target at 10,000 segments: < 200 ms, scaled %.1f ms)\n", row.name.c_str(),
                n, row.ms, row.ms * 10000 / n);
  }
}

}  // namespace

int main(int argc, char** argv) { return popcut::bench::run_with_table(argc, argv, print_table); }
