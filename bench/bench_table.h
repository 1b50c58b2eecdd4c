// A console reporter that also keeps each run, so a benchmark can end with its comparison table.
#pragma once

#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

namespace popcut::bench {

struct Row {
  std::string name;
  double ms = 0;
  std::map<std::string, double> counters;
};

class CollectingReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration || r.error_occurred) continue;
      Row row{r.benchmark_name(), r.GetAdjustedRealTime(), {}};
      for (const auto& [k, v] : r.counters) row.counters[k] = v;
      rows_.push_back(row);
    }
  }
  const std::vector<Row>& rows() const { return rows_; }
  const Row* find(const std::string& name) const {
    for (const Row& r : rows_) {
      if (r.name == name) return &r;
    }
    return nullptr;
  }

 private:
  std::vector<Row> rows_;
};

// The p-quantile (0..1) of latencies sorted ascending: the sample at rank p·n; 0 for none.
inline double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0;
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(p * static_cast<double>(sorted.size())))];
}

// The usual benchmark main, then `table(reporter)`.
template <typename Table>
int run_with_table(int argc, char** argv, Table table) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  CollectingReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  table(reporter);
  benchmark::Shutdown();
  return 0;
}

}  // namespace popcut::bench
