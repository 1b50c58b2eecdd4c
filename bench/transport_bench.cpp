// Streaming over a real pseudo-terminal (popcut sim-plotter) as a fraction of line rate; encoder bytes per cut mm.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bench_table.h"
#include "popcut/drivers/device.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/io/model_io.h"
#include "popcut/plan/plan.h"
#include "shipped_profiles.h"
#if POPCUT_BENCH_USB
#include "usb_mock.h"
#endif

namespace {

using namespace popcut;
namespace fs = std::filesystem;
const std::string kSource = POPCUT_SOURCE_DIR;

StrokePlan plan_of(const std::string& model, const drivers::DeviceProfile& p) {
  PlanOptions o = p.plan;
  o.optimise_work = 10000;  // ordering quality does not matter for streaming
  return plan_strokes(make_pattern(load_model(kSource + "/examples/voxel/" + model)), o);
}

// `popcut sim-plotter` in its own process; its port from the first line of its output.
class Plotter {
 public:
  Plotter(int baud, long buffer, const std::string& profile, const std::string& slowdown = "0.0001",
          const std::string& report = "") {
    out_ = fs::temp_directory_path() / ("popcut-bench-" + std::to_string(::getpid()) + ".port");
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 2);
      const std::string b = std::to_string(baud), buf = std::to_string(buffer);
      if (report.empty()) {
        ::execl(POPCUT_CLI, POPCUT_CLI, "sim-plotter", "--profile", profile.c_str(), "--baud", b.c_str(), "--buffer",
                buf.c_str(), "--slowdown", slowdown.c_str(), static_cast<char*>(nullptr));
      } else {
        ::execl(POPCUT_CLI, POPCUT_CLI, "sim-plotter", "--profile", profile.c_str(), "--baud", b.c_str(), "--buffer",
                buf.c_str(), "--slowdown", slowdown.c_str(), "--report", report.c_str(), static_cast<char*>(nullptr));
      }
      ::_exit(127);
    }
    for (int i = 0; i < 500 && port_.empty(); ++i) {
      std::ifstream in(out_);
      std::getline(in, port_);
      if (port_.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  ~Plotter() {
    ::kill(pid_, SIGTERM);
    ::waitpid(pid_, nullptr, 0);
    fs::remove(out_);
  }
  Plotter(const Plotter&) = delete;
  Plotter& operator=(const Plotter&) = delete;
  const std::string& port() const { return port_; }

 private:
  pid_t pid_ = -1;
  fs::path out_;
  std::string port_;
};

// sim.toml paced by XON/XOFF (as shipped) or by asking ESC.B before each chunk; the plotter
// process reads the same file, so both ends agree.
std::string profile_file(bool esc_b) {
  const std::string shipped = kSource + "/configs/devices/sim.toml";
  if (!esc_b) return shipped;
  std::ifstream in(shipped);
  std::stringstream text;
  text << in.rdbuf();
  std::string t = text.str();
  const auto set = [&](const std::string& from, const std::string& to) {
    const std::size_t at = t.find(from);
    if (at == std::string::npos) throw std::runtime_error("transport_bench: sim.toml has no " + from);
    t.replace(at, from.size(), to);
  };
  set("flow_control = \"xon_xoff\"", "flow_control = \"esc_b\"");
  set("drain_query = \"esc_o\"", "drain_query = \"esc_b\"");
  const fs::path out = fs::temp_directory_path() / ("popcut-bench-" + std::to_string(::getpid()) + "-escb.toml");
  std::ofstream(out) << t;
  return out.string();
}

// Sends a job of at least 2 s of line time; reports achieved bytes/s against the line's.
void BM_Stream(benchmark::State& state) {
  const int baud = static_cast<int>(state.range(0));
  const long buffer = state.range(1);
  const bool esc_b = state.range(2) != 0;
  const std::string profile = profile_file(esc_b);
  drivers::DeviceProfile p = drivers::load_profile(profile);
  p.transport.baud = baud;
  p.transport.buffer_bytes = static_cast<std::size_t>(buffer);
  // The profile's ESC.O status queries stay on: they are what a real job carries.
  const EncodedJob one = encode_job(plan_of("pyramid.json", p), p.dialect, p.tools);
  EncodedJob job = one;
  while (static_cast<double>(job.bytes.size()) * 10 / baud < 2.0) {  // repeat the strokes, never the init
    job.bytes += one.bytes;
    job.command_end.push_back(job.bytes.size());
  }
  double fraction = 0;
  for (auto _ : state) {
    Plotter plotter(baud, buffer, profile);
    drivers::MadeTransport t = drivers::make_transport("serial:" + plotter.port(), p);
    if (!t.status.ok() || !t.transport->open().ok()) {
      state.SkipWithError("cannot open the sim-plotter's port");
      return;
    }
    const auto start = std::chrono::steady_clock::now();
    const drivers::SendResult r = drivers::send_job(*t.transport, job, drivers::send_options(p));
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(s);
    if (!r.complete()) state.SkipWithError(r.status.message.c_str());
    fraction = static_cast<double>(r.bytes_sent) * 10 / baud / s;
    t.transport->close();
  }
  state.counters["baud"] = baud;
  state.counters["buffer"] = static_cast<double>(buffer);
  state.counters["bytes"] = static_cast<double>(job.bytes.size());
  state.counters["line_fraction"] = fraction;
  state.counters["esc_b"] = esc_b ? 1 : 0;
  if (esc_b) fs::remove(profile);
}

void BM_BytesPerMm(benchmark::State& state) {
  const std::vector<std::string> files = testing::shipped_profiles();
  const drivers::DeviceProfile p = drivers::load_profile(files[static_cast<std::size_t>(state.range(0))]);
  const StrokePlan plan = plan_of("townhouse.json", p);
  std::size_t bytes = 0;
  for (auto _ : state) {
    const EncodedJob j = drivers::encode_for_device(plan, p);
    bytes = j.bytes.size();
    benchmark::DoNotOptimize(j);
  }
  state.SetLabel(fs::path(files[static_cast<std::size_t>(state.range(0))]).stem().string());
  state.counters["bytes"] = static_cast<double>(bytes);
  state.counters["cut_mm"] = plan.total().cut_mm;
  state.counters["bytes_per_cut_mm"] = static_cast<double>(bytes) / plan.total().cut_mm;
}

// Time pacing (flow none) on the in-process simulator, whose virtual clock makes the figure exact:
// how much longer the job takes than the device's own motion (it waits for bytes), and the most
// the 256-byte buffer held, with the shipped margin (range 1: 25 %) or a calibrated device's
// (10 %), for a device as fast as the plan (range 2: 0) or exactly the margin slower (1), that
// cannot be asked or answers its language's status query (range 3: ESC.O, ESC ENQ in GP-GL),
// starting anywhere or (range 4: 1) where its finish parks the head ([kinematics] starts_at
// "origin", an HP-GL finish made absolute where the shipped one is not).
// Timed: building the motion schedule the pacing follows.
void BM_TimePaced(benchmark::State& state) {
  const std::vector<std::string> files = testing::shipped_profiles();
  drivers::DeviceProfile p = drivers::load_profile(files[static_cast<std::size_t>(state.range(0))]);
  p.transport.flow = drivers::FlowControl::none;
  p.transport.buffer_bytes = 256;
  // Asked: the language's own status query (GP-GL: ESC ENQ), else ESC.O.
  const drivers::DrainQuery own = drivers::language_unit(p.language).host().default_query();
  const drivers::DrainQuery asked = own == drivers::DrainQuery::none ? drivers::DrainQuery::esc_o : own;
  p.transport.drain_query = state.range(3) ? asked : drivers::DrainQuery::none;
  p.transport.error_query = false;
  if (state.range(4)) {
    if (p.language == CutterLanguage::hpgl) p.dialect.finish = "PU;PA0,0;SP0;";
    p.starts_at = drivers::StartsAt::origin;
  }
  const EncodedJob job = drivers::encode_for_device(plan_of("townhouse.json", p), p);
  drivers::SendOptions o = drivers::send_options(p);
  o.pace_margin_percent = static_cast<int>(state.range(1));
  for (auto _ : state) {
    o.motion = drivers::motion_schedule(job, p);
    benchmark::DoNotOptimize(o.motion);
  }
  const double slowdown = state.range(2) ? 1 + o.pace_margin_percent / 100.0 : 1.0;
  auto cutter = std::make_shared<drivers::SimCutter>(p, drivers::SimFaults{std::nullopt, std::nullopt, slowdown});
  // Where the last job's finish left it (nothing: at the origin).
  if (state.range(4)) cutter->preload(drivers::language_unit(p.language).park(p));
  cutter->run_to_end();
  const double start_s = cutter->now_s();
  drivers::SimTransport t(cutter);
  if (!t.open().ok()) throw std::runtime_error("sim transport did not open");
  const drivers::SendResult r = drivers::send_job(t, job, o);
  cutter->run_to_end();
  state.SetLabel(fs::path(files[static_cast<std::size_t>(state.range(0))]).stem().string());
  state.counters["margin"] = static_cast<double>(o.pace_margin_percent);
  state.counters["slowdown"] = slowdown;
  state.counters["esc_o"] = static_cast<double>(state.range(3));
  state.counters["parked"] = static_cast<double>(state.range(4));
  state.counters["complete"] = r.complete() ? 1 : 0;
  const double motion_s = cutter->report().motion_time_s;
  state.counters["job_over_motion"] = (cutter->report().clock_s - start_s) / motion_s;
  // The schedule over the device's motion at the plan's pace: the first-travel allowance.
  state.counters["schedule_over_motion"] = o.motion.back().start_s * slowdown / motion_s;
  state.counters["max_used"] = static_cast<double>(cutter->report().max_buffer_used);
  state.counters["overflow"] = static_cast<double>(cutter->report().overflow_bytes);
}

// A GP-GL profile's copy whose flow is "status" (paced by the motion model, corrected by ESC ENQ
// answers), as a Cameo on a serial line would be; both ends read it.
std::string status_flow_profile(const std::string& shipped) {
  std::ifstream in(shipped);
  std::stringstream text;
  text << in.rdbuf();
  std::string t = text.str();
  // Always a copy: the caller removes it afterwards. The Cameo 4 ships with status flow already.
  if (t.find("flow_control = \"status\"") == std::string::npos) {
    const std::string from = "flow_control = \"none\"";
    const std::size_t at = t.find(from);
    if (at == std::string::npos) throw std::runtime_error("transport_bench: " + shipped + " has no " + from);
    t.replace(at, from.size(), "flow_control = \"status\"");
  }
  const fs::path out = fs::temp_directory_path() / ("popcut-bench-" + std::to_string(::getpid()) + "-status.toml");
  std::ofstream(out) << t;
  return out.string();
}

void gpgl_counters(benchmark::State& state, const drivers::SendResult& r, const EncodedJob& job, const StrokePlan& plan,
                   double clock_s, double motion_s) {
  if (!r.complete()) state.SkipWithError(r.status.message.c_str());
  state.counters["job_over_motion"] = clock_s / motion_s;
  state.counters["motion_s"] = motion_s;
  state.counters["status_queries"] = r.status_queries;
  state.counters["bytes_per_cut_mm"] = static_cast<double>(job.bytes.size()) / plan.total().cut_mm;
}

#if POPCUT_BENCH_USB
// The Cameo 4 profile over USB: the unmodified libusb backend against the umockdev description
// and a simulated cutter running 10 times faster than the wall clock (run under umockdev's
// preload, which main() arranges). Job time in the device's time, from the first byte to popcut's
// "done", over its motion time.
void BM_GpglUsb(benchmark::State& state) {
  const drivers::DeviceProfile p = drivers::load_profile(kSource + "/configs/devices/silhouette-cameo4.toml");
  const StrokePlan plan = plan_of("townhouse.json", p);
  const EncodedJob job = drivers::encode_for_device(plan, p);
  for (auto _ : state) {
    testing::UsbTestbed bed;
    testing::UsbMockDevice device;
    device.time_scale = 10;
    drivers::DeviceProfile far = p;
    far.transport.flow = drivers::FlowControl::rts_cts;  // NAKs while its buffer is full
    device.cutter = std::make_shared<drivers::SimCutter>(far);
    std::string error;
    if (!bed.add(kSource + "/tests/data/umockdev/silhouette-cameo4.umockdev", "/dev/bus/usb/001/003", device, error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    drivers::MadeTransport t = drivers::make_transport("usb:0b4d:1137", p);
    if (!t.status.ok() || !t.transport->open().ok()) {
      state.SkipWithError("cannot open the mocked Cameo");
      return;
    }
    drivers::SendOptions o = drivers::send_options(p);
    o.motion = drivers::motion_schedule(job.bytes, p);
    const auto start = std::chrono::steady_clock::now();
    const drivers::SendResult r = drivers::send_job(*t.transport, job, o);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(s);
    t.transport->close();
    std::lock_guard<std::mutex> lock(device.mutex);
    gpgl_counters(state, r, job, plan, s * device.time_scale, device.cutter->report().motion_time_s);
  }
}

#endif

// The Cameo 4 profile with status flow over a pseudo-terminal to popcut sim-plotter, in real time
// (box: a few seconds of motion). Job time by the wall clock over the plotter's motion time.
void BM_GpglPty(benchmark::State& state) {
  const std::string profile = status_flow_profile(kSource + "/configs/devices/silhouette-cameo4.toml");
  const drivers::DeviceProfile p = drivers::load_profile(profile);
  const StrokePlan plan = plan_of("box.json", p);
  const EncodedJob job = drivers::encode_for_device(plan, p);
  const fs::path report = fs::temp_directory_path() / ("popcut-bench-" + std::to_string(::getpid()) + "-plotter.json");
  for (auto _ : state) {
    drivers::SendResult r;
    double s = 0;
    {
      Plotter plotter(p.transport.baud, static_cast<long>(p.transport.buffer_bytes), profile, "1", report.string());
      drivers::MadeTransport t = drivers::make_transport("serial:" + plotter.port(), p);
      if (!t.status.ok() || !t.transport->open().ok()) {
        state.SkipWithError("cannot open the sim-plotter's port");
        return;
      }
      drivers::SendOptions o = drivers::send_options(p);
      o.motion = drivers::motion_schedule(job.bytes, p);
      const auto start = std::chrono::steady_clock::now();
      r = drivers::send_job(*t.transport, job, o);
      s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      state.SetIterationTime(s);
      t.transport->close();
      std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the plotter writes its report on hang-up
    }
    std::ifstream in(report);
    std::stringstream text;
    text << in.rdbuf();
    const std::string t = text.str();
    const std::size_t at = t.find("\"motion_time_s\":");
    const double motion_s = at == std::string::npos ? 0 : std::stod(t.substr(at + 16));
    gpgl_counters(state, r, job, plan, s, motion_s);
  }
  fs::remove(profile);
  fs::remove(report);
}

BENCHMARK(BM_Stream)
    ->Args({9600, 1024, 0})
    ->Args({115200, 1024, 0})
    ->Args({115200, 256, 0})
    ->Args({9600, 1024, 1})
    ->Args({115200, 1024, 1})
    ->Args({115200, 256, 1})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TimePaced)
    ->ArgsProduct({benchmark::CreateDenseRange(0, static_cast<int>(testing::shipped_profiles().size()) - 1, 1),
                   {25, 10},
                   {0, 1},
                   {0, 1},
                   {0}})
    ->MinTime(0.05)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TimePaced)
    ->ArgsProduct({benchmark::CreateDenseRange(0, static_cast<int>(testing::shipped_profiles().size()) - 1, 1),
                   {10},
                   {0, 1},
                   {0},
                   {1}})
    ->MinTime(0.05)
    ->Unit(benchmark::kMillisecond);
#if POPCUT_BENCH_USB
BENCHMARK(BM_GpglUsb)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
#endif
BENCHMARK(BM_GpglPty)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BytesPerMm)
    ->DenseRange(0, static_cast<int>(testing::shipped_profiles().size()) - 1)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  // The serial transport is libserialport, which opens a pty only under the test shim: run
  // again with it preloaded (as the pty tests run popcut).
  // The USB rows run libusb unmodified against umockdev's testbed, which needs its preload too
  // (harmless to the pty rows: it redirects nothing while no testbed exists).
  const char* preload = std::getenv("LD_PRELOAD");
  const std::string wanted = std::string(POPCUT_PTY_PRELOAD) + (POPCUT_BENCH_USB ? ":libumockdev-preload.so.0" : "");
  if (!preload || std::string(preload).find(wanted) == std::string::npos) {
    ::setenv("LD_PRELOAD", wanted.c_str(), 1);
    ::execv("/proc/self/exe", argv);
    std::perror("transport_bench: cannot re-run itself with the pty shim");
    return 1;
  }
  return popcut::bench::run_with_table(argc, argv, [](const popcut::bench::CollectingReporter& rep) {
    std::printf("\nstreaming over a pseudo-terminal to popcut sim-plotter (target >= 95%% of line rate)\n");
    std::printf("%-9s %-8s %-8s %-8s %-10s\n", "pacing", "baud", "buffer", "bytes", "of line");
    for (const auto& r : rep.rows()) {
      if (r.name.rfind("BM_Stream", 0) != 0) continue;
      std::printf("%-9s %-8.0f %-8.0f %-8.0f %5.1f %%\n", r.counters.at("esc_b") != 0 ? "ESC.B" : "XON/XOFF",
                  r.counters.at("baud"), r.counters.at("buffer"), r.counters.at("bytes"),
                  100 * r.counters.at("line_fraction"));
    }
    std::printf("\ntime pacing (flow none) on the simulator's virtual clock, townhouse, 256-byte buffer\n");
    std::printf("%-16s %-7s %-9s %-7s %-7s %-9s %-12s %-13s %-9s %-9s %-12s\n", "profile", "margin", "slowdown",
                "ESC.O", "start", "complete", "job/motion", "sched/motion", "max used", "overflow", "schedule ms");
    const std::vector<std::string> names = popcut::testing::shipped_profiles();
    for (const auto& r : rep.rows()) {
      if (r.name.rfind("BM_TimePaced", 0) != 0) continue;
      const std::size_t i = static_cast<std::size_t>(std::stoi(r.name.substr(r.name.find('/') + 1)));
      std::printf("%-16s %-7s %-9.2f %-7s %-7s %-9s %-12.3f %-13.3f %-9.0f %-9.0f %-12.2f\n",
                  fs::path(names[i]).stem().c_str(),
                  (std::to_string(static_cast<int>(r.counters.at("margin"))) + " %").c_str(), r.counters.at("slowdown"),
                  r.counters.at("esc_o") != 0 ? "asked" : "-", r.counters.at("parked") != 0 ? "parked" : "any",
                  r.counters.at("complete") != 0 ? "yes" : "NO", r.counters.at("job_over_motion"),
                  r.counters.at("schedule_over_motion"), r.counters.at("max_used"), r.counters.at("overflow"), r.ms);
    }
    std::printf(
        "\nGP-GL (silhouette-cameo4) next to HP-GL's streaming above: job time over the device's motion time\n");
    std::printf("%-34s %-10s %-12s %-10s %-9s\n", "transport", "motion s", "job/motion", "ESC ENQ", "B/mm");
    for (const auto& r : rep.rows()) {
      const bool usb = r.name.rfind("BM_GpglUsb", 0) == 0;
      if (!usb && r.name.rfind("BM_GpglPty", 0) != 0) continue;
      std::printf("%-34s %-10.2f %-12.3f %-10.0f %-9.2f\n",
                  usb ? "USB (umockdev), townhouse, none" : "pty (sim-plotter), box, status", r.counters.at("motion_s"),
                  r.counters.at("job_over_motion"), r.counters.at("status_queries"), r.counters.at("bytes_per_cut_mm"));
    }
    std::printf("\nencoder: bytes per cut mm, townhouse, per profile\n%-16s %-8s %-8s %-8s\n", "profile", "bytes",
                "cut mm", "B/mm");
    const std::vector<std::string> files = popcut::testing::shipped_profiles();
    for (const auto& r : rep.rows()) {
      if (r.name.rfind("BM_BytesPerMm", 0) != 0) continue;
      const std::size_t i = static_cast<std::size_t>(std::stoi(r.name.substr(r.name.find('/') + 1)));
      std::printf("%-16s %-8.0f %-8.0f %-8.2f\n", fs::path(files[i]).stem().c_str(), r.counters.at("bytes"),
                  r.counters.at("cut_mm"), r.counters.at("bytes_per_cut_mm"));
    }
  });
}
