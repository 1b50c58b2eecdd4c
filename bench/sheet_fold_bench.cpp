// Rigid folding of drawn sheets: building the hinges, and each frame's poses, mesh and collision check, to 1,000 faces.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <string>

#include "bench_table.h"
#include "popcut/fold/sheet_fold.h"

namespace {

using popcut::DrawnKind;
using popcut::DrawnLine;
using popcut::LineDrawing;

DrawnLine drawn(DrawnKind kind, std::vector<popcut::Point2> points, std::string where, bool closed = false) {
  return {kind, std::move(points), closed, std::move(where), "bench", {}};
}

// `rows` strips of `panels` panels 10 mm wide, cut apart and each hinged to a spine on the left;
// the panels' creases zig-zag (alternate mountain and valley), so the folded comb is collision-free
// and every frame checks every pair of nearby panels. Faces: rows × panels + 1.
const LineDrawing& comb(int rows, int panels) {
  static std::map<std::pair<int, int>, LineDrawing> made;
  LineDrawing& d = made[{rows, panels}];
  if (!d.lines.empty()) return d;
  d.source = "comb";
  const double row_mm = 20, w = 10 * (panels + 1), h = row_mm * rows;
  d.lines.push_back(drawn(DrawnKind::outline, {{0, 0}, {w, 0}, {w, h}, {0, h}}, "edge", true));
  for (int r = 1; r < rows; ++r)
    d.lines.push_back(drawn(DrawnKind::cut, {{10, r * row_mm}, {w, r * row_mm}}, "cut " + std::to_string(r)));
  for (int r = 0; r < rows; ++r)
    for (int p = 0; p < panels; ++p) {
      const double x = 10.0 * (p + 1);
      d.lines.push_back(drawn(p % 2 ? DrawnKind::mountain : DrawnKind::valley, {{x, r * row_mm}, {x, (r + 1) * row_mm}},
                              "crease " + std::to_string(r) + "." + std::to_string(p)));
    }
  return d;
}

const popcut::FoldableSheet& sheet(int rows, int panels) {
  static std::map<std::pair<int, int>, popcut::FoldableSheet> made;
  auto it = made.find({rows, panels});
  if (it == made.end()) {
    const LineDrawing& d = comb(rows, panels);
    popcut::SheetFoldOptions o;
    o.angle_deg = 60;
    it = made.emplace(std::pair(rows, panels), popcut::make_foldable_sheet(d, popcut::build_sheet_map(d), o)).first;
  }
  return it->second;
}

void BM_Build(benchmark::State& state) {
  const LineDrawing& d = comb(static_cast<int>(state.range(0)), 50);
  popcut::SheetFoldOptions o;
  o.angle_deg = 60;
  std::size_t faces = 0;
  for (auto _ : state) faces = popcut::make_foldable_sheet(d, popcut::build_sheet_map(d), o).map.regions.size();
  state.counters["faces"] = static_cast<double>(faces);
}

void BM_Poses(benchmark::State& state) {
  const popcut::FoldableSheet& s = sheet(static_cast<int>(state.range(0)), 50);
  for (auto _ : state) benchmark::DoNotOptimize(popcut::fold_sheet(s, 0.7));
  state.counters["faces"] = static_cast<double>(s.map.regions.size());
}

// One animation frame: poses, the mesh the writers and renderer take, and the collision check.
void BM_Frame(benchmark::State& state) {
  const popcut::FoldableSheet& s = sheet(static_cast<int>(state.range(0)), 50);
  std::size_t collisions = 0;
  for (auto _ : state) {
    const popcut::SheetState st = popcut::fold_sheet(s, 0.7);
    benchmark::DoNotOptimize(popcut::sheet_mesh(s, st));
    collisions = popcut::find_collisions(s, st).size();
  }
  if (collisions) state.SkipWithError("the comb collided");
  state.counters["faces"] = static_cast<double>(s.map.regions.size());
}

BENCHMARK(BM_Build)->Arg(2)->Arg(20)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Poses)->Arg(2)->Arg(20)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Frame)->Arg(2)->Arg(20)->Unit(benchmark::kMillisecond);

void print_table(const popcut::bench::CollectingReporter& reporter) {
  std::printf("\n%-16s %8s %12s %14s\n", "benchmark", "faces", "time (ms)", "per second");
  for (const auto& row : reporter.rows()) {
    const auto f = row.counters.find("faces");
    std::printf("%-16s %8.0f %12.3f %14.1f\n", row.name.c_str(), f == row.counters.end() ? 0 : f->second, row.ms,
                row.ms > 0 ? 1000 / row.ms : 0);
  }
  if (const auto* frame = reporter.find("BM_Frame/20"))
    std::printf("fold simulation at %.0f faces: %.1f frames per second with collisions checked\n",
                frame->counters.at("faces"), 1000 / frame->ms);
}

}  // namespace

int main(int argc, char** argv) { return popcut::bench::run_with_table(argc, argv, print_table); }
