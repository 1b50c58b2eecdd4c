// popcutd under load on loopback: submissions per second, API latency p50/p99, memory with 10,000 jobs queued.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <mutex>
#include <numeric>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include "bench_table.h"
#include "design_street.h"
#include "popcut/io/design_json.h"
#include "popcutd_process.h"

namespace {

using popcut::bench::percentile;
using popcut::testing::PopcutdProcess;
using popcut::testing::read_file;
using popcut::testing::TempDir;

const std::string kSource = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-0123456789abcdef";
const std::string kAdmin = "admin-0123456789abcdef";

// Two paused sim cutters: jobs are planned and wait, so the figures are the API's and the queue's.
std::string config(const TempDir& dir, int http_threads = 16) {
  return dir.write("bench.toml", "[server]\ndata_dir = \"x\"\nhttp_threads = " + std::to_string(http_threads) +
                                     "\n[limits]\nqueue_length = 1000000\n"
                                     "[[device]]\nname = \"a\"\nprofile = \"" +
                                     kSource +
                                     "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
                                     "[[device]]\nname = \"b\"\nprofile = \"" +
                                     kSource +
                                     "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
                                     "[[token]]\nname = \"kiosk\"\ntoken = \"" +
                                     kKiosk +
                                     "\"\n"
                                     "[[token]]\nname = \"admin\"\ntoken = \"" +
                                     kAdmin + "\"\nrole = \"admin\"\n");
}

double rss_mb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0;
}

// TcpExtListenOverflows from /proc/net/netstat: connections this machine's kernel dropped because a
// listening socket's accept queue was full (their client retries a second later). Machine-wide.
long long listen_overflows() {
  std::ifstream in("/proc/net/netstat");
  std::string names, values;
  while (std::getline(in, names) && std::getline(in, values)) {
    if (names.rfind("TcpExt:", 0) != 0) continue;
    std::istringstream n(names), v(values);
    std::string name, value;
    while (n >> name && v >> value) {
      if (name == "ListenOverflows") return std::stoll(value);
    }
  }
  return -1;
}

struct Load {
  double seconds = 0;
  std::vector<double> latency_ms;
  int failures = 0;
  std::map<std::string, int> failed_as;  // what went wrong ("status 503: ...", "no answer: Read"), how often
  long long listen_overflows = 0;
};

// "" when `r` is an answer with status `want`, else what it was instead.
std::string outcome(const httplib::Result& r, int want) {
  if (!r) return "no answer: " + httplib::to_string(r.error());
  if (r->status == want) return "";
  return "status " + std::to_string(r->status) + ": " + r->body.substr(0, 100);
}

// `count` requests from `threads` clients at once; `request(client, i)` returns outcome().
// Each client keeps its connection alive, or with `fresh` opens a new one for every request.
using Request = std::function<std::string(httplib::Client&, int)>;
Load run_load(const PopcutdProcess& d, int threads, int count, const Request& request, bool fresh = false) {
  Load load;
  std::mutex m;
  std::atomic<int> next{0};
  const long long overflows_before = listen_overflows();
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&] {
      httplib::Client kept = d.client(kKiosk);
      kept.set_keep_alive(true);
      std::vector<double> mine;
      std::map<std::string, int> failed;
      for (int i = next++; i < count; i = next++) {
        const auto s = std::chrono::steady_clock::now();
        std::string wrong;
        if (fresh) {
          httplib::Client once = d.client(kKiosk);
          wrong = request(once, i);
        } else {
          wrong = request(kept, i);
        }
        if (!wrong.empty()) ++failed[wrong];
        mine.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s).count());
      }
      std::lock_guard lock(m);
      load.latency_ms.insert(load.latency_ms.end(), mine.begin(), mine.end());
      for (const auto& [what, n] : failed) {
        load.failed_as[what] += n;
        load.failures += n;
      }
    });
  }
  for (auto& t : pool) t.join();
  load.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  load.listen_overflows = listen_overflows() - overflows_before;
  std::sort(load.latency_ms.begin(), load.latency_ms.end());
  return load;
}

void report(benchmark::State& state, const Load& l, int count) {
  state.counters["per_s"] = count / l.seconds;
  state.counters["p50_ms"] = percentile(l.latency_ms, 0.50);
  state.counters["p99_ms"] = percentile(l.latency_ms, 0.99);
  state.counters["max_ms"] = l.latency_ms.empty() ? 0 : l.latency_ms.back();
  // A dropped SYN is sent again after 1 s: requests this slow waited for a retransmit.
  state.counters["over_1s"] =
      static_cast<double>(l.latency_ms.end() - std::lower_bound(l.latency_ms.begin(), l.latency_ms.end(), 1000.0));
  state.counters["listen_overflows"] = static_cast<double>(l.listen_overflows);
  state.counters["failures"] = l.failures;
  if (l.failures) {
    std::string what = std::to_string(l.failures) + " of " + std::to_string(count) + " requests failed:";
    for (const auto& [why, n] : l.failed_as) what += " " + std::to_string(n) + " x (" + why + ");";
    state.SkipWithError(what.c_str());
  }
}

std::string submission(int i) {
  static const std::string box = read_file(kSource + "/examples/voxel/box.json");
  return "{\"profile\": \"sim\", \"name\": \"bench-" + std::to_string(i) + "\", \"model\": " + box + "}";
}

struct Daemon {
  explicit Daemon(int http_threads = 16) : process{POPCUTD, config(dir, http_threads), (dir.path() / "data").string()} {
    httplib::Client admin = process.client(kAdmin);
    admin.Post("/api/v1/devices/a/pause", "", "application/json");
    admin.Post("/api/v1/devices/b/pause", "", "application/json");
  }
  TempDir dir{"popcutd-bench"};
  PopcutdProcess process;
};

// args: concurrent clients, submissions
void BM_Submit(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0)), count = static_cast<int>(state.range(1));
  for (auto _ : state) {
    Daemon d;
    const Load l = run_load(d.process, threads, count, [](httplib::Client& c, int i) {
      return outcome(c.Post("/api/v1/jobs", submission(i), "application/json"), 201);
    });
    report(state, l, count);
  }
}
BENCHMARK(BM_Submit)
    ->Args({1, 200})
    ->Args({1, 2000})
    ->Args({8, 2000})
    ->Args({32, 2000})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Every submission with an Idempotency-Key, as popcut submit and the kiosk send them: the key, its
// request digest and the job in one transaction. args: concurrent clients, submissions, and 1 to
// send each key twice (a retry: the second answer is the first job, 200 Idempotent-Replayed).
void BM_SubmitKeyed(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0)), count = static_cast<int>(state.range(1));
  const bool twice = state.range(2) != 0;
  for (auto _ : state) {
    Daemon d;
    const Load l = run_load(d.process, threads, count, [twice](httplib::Client& c, int i) {
      const int n = twice ? i / 2 : i;
      const httplib::Headers key = {{"Idempotency-Key", "bench-" + std::to_string(n)}};
      const httplib::Result r = c.Post("/api/v1/jobs", key, submission(n), "application/json");
      // Under concurrency either copy of a pair may come first: one is created, the other replayed.
      return r && r->status == 200 ? std::string() : outcome(r, 201);
    });
    report(state, l, count);
  }
}
BENCHMARK(BM_SubmitKeyed)
    ->Args({1, 2000, 0})
    ->Args({32, 2000, 0})
    ->Args({32, 2000, 1})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// Every submission on a connection of its own, as scripts running `popcut submit` at once make
// them: bursts of connections the daemon must take up. args: concurrent clients, submissions
void BM_SubmitFresh(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0)), count = static_cast<int>(state.range(1));
  for (auto _ : state) {
    Daemon d;
    const Load l = run_load(
        d.process, threads, count,
        [](httplib::Client& c, int i) {
          return outcome(c.Post("/api/v1/jobs", submission(i), "application/json"), 201);
        },
        true);
    report(state, l, count);
  }
}
BENCHMARK(BM_SubmitFresh)
    ->Args({8, 1000})
    ->Args({64, 1000})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// GET one job (its place in line and ETA computed) with 1000 jobs queued.
void BM_GetJob(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0)), count = static_cast<int>(state.range(1));
  for (auto _ : state) {
    Daemon d;
    const Load queued = run_load(d.process, 8, 1000, [](httplib::Client& c, int i) {
      return outcome(c.Post("/api/v1/jobs", submission(i), "application/json"), 201);
    });
    if (queued.failures) {
      report(state, queued, 1000);
      continue;
    }
    const Load l = run_load(d.process, threads, count, [](httplib::Client& c, int i) {
      return outcome(c.Get(("/api/v1/jobs/" + std::to_string(1 + i % 1000)).c_str()), 200);
    });
    report(state, l, count);
  }
}
BENCHMARK(BM_GetJob)->Args({1, 2000})->Args({8, 4000})->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);

// Resident memory of popcutd before and after 10,000 jobs are queued (and planned: ready).
void BM_Memory(benchmark::State& state) {
  const int count = static_cast<int>(state.range(0));
  for (auto _ : state) {
    Daemon d;
    const double before = rss_mb(d.process.pid());
    const Load l = run_load(d.process, 8, count, [](httplib::Client& c, int i) {
      return outcome(c.Post("/api/v1/jobs", submission(i), "application/json"), 201);
    });
    httplib::Client admin = d.process.client(kAdmin);
    // Wait for the planner to reach the last job, so the figure includes planning's footprint.
    while (admin.Get(("/api/v1/jobs/" + std::to_string(count)).c_str())->body.find("\"ready\"") == std::string::npos) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    state.counters["rss_mb_empty"] = before;
    state.counters["rss_mb_queued"] = rss_mb(d.process.pid());
    state.counters["jobs"] = count;
    report(state, l, count);
  }
}
BENCHMARK(BM_Memory)->Arg(10000)->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);

// /healthz from a fresh connection, once every 100 ms for 3 s, while `idle` connections that
// never send a byte stay open and `pollers` kiosk-like clients GET their jobs every 0.5 s on
// kept-alive connections. args: idle connections, pollers, http_threads.
void BM_HealthzUnderIdle(benchmark::State& state) {
  const int idle = static_cast<int>(state.range(0)), pollers = static_cast<int>(state.range(1));
  for (auto _ : state) {
    Daemon d(static_cast<int>(state.range(2)));
    std::vector<int> sockets;
    for (int i = 0; i < idle; ++i) {
      if (const int s = popcut::testing::connect_loopback(d.process.port()); s >= 0) sockets.push_back(s);
    }
    std::atomic<bool> stop{false};
    std::atomic<int> poll_failures{0};
    std::vector<std::thread> poll_threads;
    for (int i = 0; i < pollers; ++i) {
      poll_threads.emplace_back([&] {
        httplib::Client c = d.process.client(kKiosk);
        c.set_keep_alive(true);
        while (!stop) {
          const httplib::Result r = c.Get("/api/v1/jobs?limit=20");
          if (!r || r->status != 200) ++poll_failures;
          std::this_thread::sleep_for(std::chrono::milliseconds(500));
        }
      });
    }
    std::vector<double> ms;
    int failures = 0;
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(3)) {
      httplib::Client c = d.process.client("");
      c.set_read_timeout(30);
      const auto s = std::chrono::steady_clock::now();
      const httplib::Result r = c.Get("/healthz");
      if (!r || r->status != 200) ++failures;
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s).count());
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    const double rss = rss_mb(d.process.pid());
    stop = true;
    for (auto& t : poll_threads) t.join();
    for (const int s : sockets) ::close(s);
    std::sort(ms.begin(), ms.end());
    state.counters["p50_ms"] = percentile(ms, 0.5);
    state.counters["max_ms"] = ms.empty() ? 0 : ms.back();
    state.counters["rss_mb"] = rss;
    state.counters["failures"] = failures + poll_failures;
    state.counters["idle"] = idle;
    state.counters["pollers"] = pollers;
    state.counters["threads"] = static_cast<double>(state.range(2));
  }
}
BENCHMARK(BM_HealthzUnderIdle)
    ->Args({0, 0, 8})
    ->Args({8, 0, 8})
    ->Args({20, 0, 8})
    ->Args({0, 8, 8})
    ->Args({0, 0, 64})
    ->Args({8, 0, 64})
    ->Args({20, 0, 64})
    ->Args({0, 30, 64})
    ->Args({20, 30, 64})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// A designer's edit through popcutd: a street of walls opened as a draft, then walls added in
// front, each answered with the design, the pattern and the check (and undone, untimed, so
// every edit meets the same card). args: faces, edits.
void BM_DesignEdit(benchmark::State& state) {
  const int faces = static_cast<int>(state.range(0)), count = static_cast<int>(state.range(1));
  for (auto _ : state) {
    Daemon d;
    httplib::Client c = d.process.client(kKiosk);
    c.set_keep_alive(true);
    c.set_read_timeout(120);
    const httplib::Result made = c.Post(
        "/api/v1/designs", popcut::to_design_json(popcut::bench::design_street(faces), "street"), "application/json");
    Load l;
    if (!made || made->status != 201) {
      l.failures = count;
      l.failed_as[made ? "create " + std::to_string(made->status) : "create: no answer"] = count;
      report(state, l, count);
      continue;
    }
    const std::string at = "/api/v1/designs/" + std::to_string(nlohmann::json::parse(made->body)["id"].get<int>());
    std::mt19937_64 rng(11);
    const double width = 5.0 * (faces / 2) + 10;
    for (int i = 0; i < count; ++i) {
      const double x = std::round(std::uniform_real_distribution<double>(0, width - 30)(rng));
      const std::string item = "{\"tool\": \"wall\", \"t\": 30, \"outline\": [[" + std::to_string(x) + ", 0], [" +
                               std::to_string(x + 20) + ", 0], [" + std::to_string(x + 20) + ", 12], [" +
                               std::to_string(x) + ", 12]]}";
      const auto s = std::chrono::steady_clock::now();
      const std::string wrong = outcome(c.Post(at + "/items", item, "application/json"), 200);
      l.latency_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - s).count());
      if (!wrong.empty()) {
        ++l.failures;
        ++l.failed_as[wrong];
      }
      c.Post(at + "/undo", "", "application/json");
    }
    // Edits per second of edit time: the undos between are not counted.
    l.seconds = std::accumulate(l.latency_ms.begin(), l.latency_ms.end(), 0.0) / 1000;
    std::sort(l.latency_ms.begin(), l.latency_ms.end());
    report(state, l, count);
  }
}
BENCHMARK(BM_DesignEdit)
    ->Args({500, 40})
    ->Args({2000, 40})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  return popcut::bench::run_with_table(argc, argv, [](const popcut::bench::CollectingReporter& r) {
    std::printf(
        "\npopcutd on loopback (box model, devices paused so jobs stay queued; DesignEdit/FACES/N: N walls added to a "
        "draft\n"
        "of a street of FACES faces, one client, each answered with design, pattern and check; over 1 s: requests that "
        "took a second "
        "or\n"
        "more, as a dropped connection retried by TCP does; overflows: connections the kernel dropped because an "
        "accept\n"
        "queue was full, TcpExtListenOverflows, machine-wide, during the case)\n");
    std::printf("%-26s %12s %10s %10s %10s %8s %10s %12s %14s\n", "case", "per second", "p50 ms", "p99 ms", "max ms",
                "over 1 s", "overflows", "RSS empty MB", "RSS queued MB");
    for (const popcut::bench::Row& row : r.rows()) {
      const auto c = [&](const char* k) { return row.counters.count(k) ? row.counters.at(k) : 0.0; };
      if (row.name.rfind("BM_HealthzUnderIdle", 0) == 0) continue;
      std::printf("%-26s %12.0f %10.2f %10.2f %10.2f %8.0f %10.0f %12.1f %14.1f\n", row.name.c_str(), c("per_s"),
                  c("p50_ms"), c("p99_ms"), c("max_ms"), c("over_1s"), c("listen_overflows"), c("rss_mb_empty"),
                  c("rss_mb_queued"));
    }
    std::printf(
        "\n/healthz (fresh connection every 100 ms for 3 s) with idle sockets and kiosk pollers (keep-alive, every 0.5 "
        "s)\n");
    std::printf("%8s %8s %12s %10s %10s %8s %10s\n", "threads", "idle", "pollers", "p50 ms", "max ms", "RSS MB",
                "failures");
    for (const popcut::bench::Row& row : r.rows()) {
      const auto c = [&](const char* k) { return row.counters.count(k) ? row.counters.at(k) : 0.0; };
      if (row.name.rfind("BM_HealthzUnderIdle", 0) != 0) continue;
      std::printf("%8.0f %8.0f %12.0f %10.2f %10.2f %8.1f %10.0f\n", c("threads"), c("idle"), c("pollers"), c("p50_ms"),
                  c("max_ms"), c("rss_mb"), c("failures"));
    }
  });
}
