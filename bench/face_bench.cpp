// Face model speed: adding faces one by one up to 2,000, pattern and check, and the face path
// against the voxel path on the voxel paper's 80 × 40 × 40 model.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <random>

#include "bench_table.h"
#include "popcut/model/face_model.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "random_models.h"

namespace {

// A row of boxes (a VFace and its roof each), added one face at a time: 2 + faces faces in all.
popcut::FaceModel street(int faces) {
  const int boxes = faces / 2;
  popcut::FaceModel m(5.0 * boxes + 10, 60, 60);
  std::mt19937_64 rng(3);
  for (int i = 0; i < boxes; ++i) {
    const double x0 = 5.0 + 5.0 * i, x1 = x0 + 4;
    const double depth = 5 + static_cast<double>(rng() % 20), height = 5 + static_cast<double>(rng() % 30);
    m.apply({popcut::EditOp::add_vface, depth, {{x0, 0}, {x1, 0}, {x1, height}, {x0, height}}});
    m.apply({popcut::EditOp::add_hface, height, {{x0, 0}, {x1, 0}, {x1, depth}, {x0, depth}}});
  }
  return m;
}

// Building the model edit by edit, up to the finished faces (they are worked out on first use).
void BM_AddFaces(benchmark::State& state) {
  const int faces = static_cast<int>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(street(faces).face_count());
  state.counters["faces"] = faces;
}

void BM_FacePattern(benchmark::State& state) {
  const popcut::FaceModel m = street(static_cast<int>(state.range(0)));
  m.face_count();  // work the faces out first: BM_AddFaces measures that
  for (auto _ : state) benchmark::DoNotOptimize(popcut::make_pattern(m));
  state.counters["faces"] = static_cast<double>(m.face_count());
}

void BM_FaceCheck(benchmark::State& state) {
  const popcut::Pattern p = popcut::make_pattern(street(static_cast<int>(state.range(0))));
  for (auto _ : state) benchmark::DoNotOptimize(popcut::check_popup(p));
  state.counters["faces"] = static_cast<double>(p.faces.size());
}

popcut::VoxelModel paper_model() {
  std::mt19937_64 rng(42);
  return popcut::testing::random_staircase(rng, 80, 40, 40, 1.0);
}

void BM_PaperVoxelPath(benchmark::State& state) {
  const popcut::VoxelModel m = paper_model();
  for (auto _ : state) benchmark::DoNotOptimize(popcut::check_popup(popcut::make_pattern(m)));
}

void BM_PaperFacePath(benchmark::State& state) {
  const popcut::FaceModel m = popcut::to_face_model(paper_model());
  for (auto _ : state) benchmark::DoNotOptimize(popcut::check_popup(popcut::make_pattern(m)));
  state.counters["faces"] = static_cast<double>(m.face_count());
}

BENCHMARK(BM_AddFaces)
    ->Arg(250)
    ->Arg(500)
    ->Arg(1000)
    ->Arg(2000)
    ->Arg(8000)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK(BM_FacePattern)->Arg(500)->Arg(2000)->Arg(8000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FaceCheck)->Arg(500)->Arg(2000)->Arg(8000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PaperVoxelPath)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PaperFacePath)->Unit(benchmark::kMillisecond);

void print_table(const popcut::bench::CollectingReporter& reporter) {
  std::printf("\n%-24s %8s %12s %14s\n", "benchmark", "faces", "time (ms)", "ms per face");
  for (const auto& row : reporter.rows()) {
    const auto f = row.counters.find("faces");
    const double faces = f == row.counters.end() ? 0 : f->second;
    std::printf("%-24s %8.0f %12.3f %14s\n", row.name.c_str(), faces, row.ms,
                faces > 0 ? std::to_string(row.ms / faces).substr(0, 7).c_str() : "");
  }
  const auto* voxel = reporter.find("BM_PaperVoxelPath");
  const auto* face = reporter.find("BM_PaperFacePath");
  if (voxel && face) {
    const double ratio = face->ms / voxel->ms;
    std::printf("face path / voxel path on the paper's 80 x 40 x 40 model: %.1fx (target within 10x: %s)\n", ratio,
                ratio <= 10 ? "yes" : "NO");
  }
}

}  // namespace

int main(int argc, char** argv) { return popcut::bench::run_with_table(argc, argv, print_table); }
