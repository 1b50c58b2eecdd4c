// Serial cutting for real: `popcut cut --device serial:` against `popcut sim-plotter` on a pseudo-terminal.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcutd_process.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A child process with its stdout and stderr in files; killed (and reaped) when dropped.
class Child {
 public:
  // `shim`: popcut opens the pty through libserialport, under the modem-line shim (tests/support).
  Child(const std::vector<std::string>& args, const fs::path& out, const fs::path& err, bool shim = false) {
    pid_ = ::fork();
    if (pid_ == 0) {
      if (shim) ::setenv("LD_PRELOAD", POPCUT_PTY_PRELOAD, 1);
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644),
                e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(o, 1);
      ::dup2(e, 2);
      std::vector<char*> argv;
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
  }
  ~Child() {
    if (pid_ > 0 && !done_) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  void signal(int sig) const { ::kill(pid_, sig); }
  // Exit code, waiting at most `limit` (then -1: a hang is a failure, not a stuck test).
  int wait(std::chrono::seconds limit = std::chrono::seconds(120)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        done_ = true;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  bool done_ = false;
};

class SerialPty : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("popcut-pty-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    // The host's profile: the simulator's (1024-byte buffer, XON/XOFF, ESC.O), with shorter
    // timeouts. The plotters below have 256 bytes: smaller than the profile says.
    std::string p = slurp(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/sim.toml");
    replace(p, "timeout_ms = 5000", "timeout_ms = 3000\nhold_timeout_ms = 8000");
    profile_ = (dir_ / "host.toml").string();
    std::ofstream(profile_) << p;
  }
  void TearDown() override { fs::remove_all(dir_); }

  static void replace(std::string& s, const std::string& from, const std::string& to) {
    const std::size_t at = s.find(from);
    ASSERT_NE(at, std::string::npos) << "sim.toml has " << from;
    s.replace(at, from.size(), to);
  }

  // Starts a sim-plotter (256-byte buffer unless `extra` says, XON/XOFF) and returns its port.
  std::unique_ptr<Child> plotter(const std::string& name, const std::vector<std::string>& extra, std::string& port) {
    std::vector<std::string> args = {POPCUT_CLI, "sim-plotter", "--report", (dir_ / (name + ".json")).string()};
    if (std::find(extra.begin(), extra.end(), "--buffer") == extra.end()) args.insert(args.end(), {"--buffer", "256"});
    args.insert(args.end(), extra.begin(), extra.end());
    auto c = std::make_unique<Child>(args, dir_ / (name + ".out"), dir_ / (name + ".err"));
    for (int i = 0; i < 500 && port.empty(); ++i) {
      const std::string out = slurp(dir_ / (name + ".out"));
      if (out.find('\n') != std::string::npos)
        port = out.substr(0, out.find('\n'));
      else
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_EQ(port.rfind("/dev/pts/", 0), 0u) << "sim-plotter prints its port first: " << slurp(dir_ / (name + ".err"));
    return c;
  }

  struct Cut {
    int code;
    std::string err;
    json report;
  };
  Cut cut(const std::string& model, const std::string& device, const std::string& extra = "",
          const std::string& name = "cut") {
    Child c({"/bin/sh", "-c",
             std::string(POPCUT_CLI) + " cut " + std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/" + model +
                 " --profile " + profile_ + " --device " + device + " --out " + (dir_ / name).string() + " " + extra},
            dir_ / (name + ".stdout"), dir_ / (name + ".stderr"), true);
    Cut r{c.wait(), "", {}};
    r.err = slurp(dir_ / (name + ".stderr"));
    if (fs::exists(dir_ / name / "report.json")) r.report = json::parse(slurp(dir_ / name / "report.json"));
    return r;
  }

  // The strokes a device cuts from `hpgl`, by the in-process simulator (the reference).
  std::vector<popcut::PlotterPath> strokes_of(const std::string& hpgl) const {
    popcut::drivers::DeviceProfile p = popcut::drivers::load_profile(profile_);
    p.transport.flow = popcut::drivers::FlowControl::rts_cts;  // held line: nothing lost, whatever the size
    p.transport.buffer_bytes = 1 << 20;
    popcut::drivers::SimCutter c(p);
    c.receive(reinterpret_cast<const std::uint8_t*>(hpgl.data()), hpgl.size(), 1e9);
    c.run_to_end();
    std::vector<popcut::PlotterPath> out;
    for (const auto& s : c.strokes()) out.push_back(s.points_pu);
    return out;
  }
  static std::vector<popcut::PlotterPath> strokes_of(const json& plotter_report) {
    return popcut::testing::sim_plotter_strokes(plotter_report);
  }
  json plotter_report(const std::string& name) { return json::parse(slurp(dir_ / (name + ".json"))); }
  // Sets the port up as a raw host at the simulator's 115200 baud (a pty starts at 38400 with line
  // editing: the plotter would hear garbage), for tests that write bytes themselves.
  static void set_up_host(int fd) {
    termios tio{};
    ::tcgetattr(fd, &tio);
    ::cfmakeraw(&tio);
    ::cfsetspeed(&tio, B115200);
    ::tcsetattr(fd, TCSANOW, &tio);
  }
  static int open_host(const std::string& port) {
    const int fd = ::open(port.c_str(), O_RDWR | O_NOCTTY);
    if (fd >= 0) set_up_host(fd);
    return fd;
  }
  static long first_difference_at(const std::vector<popcut::PlotterPath>& a,
                                  const std::vector<popcut::PlotterPath>& b) {
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
      if (a[i] != b[i]) return static_cast<long>(i);
    }
    return a.size() == b.size() ? -1 : static_cast<long>(std::min(a.size(), b.size()));
  }

  fs::path dir_;
  std::string profile_;
};

TEST_F(SerialPty, WholeJobArrivesIntactAndASmallerBufferThanTheProfileSaysNeverOverflows) {
  std::string port;
  auto plot = plotter("p", {"--slowdown", "0.1"}, port);
  const Cut r = cut("townhouse.json", "serial:" + port);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(plot->wait(), 0) << "the plotter ends when the host closes the port: " << slurp(dir_ / "p.err");
  const json pr = plotter_report("p");
  const std::string job = slurp(dir_ / "cut" / "job.hpgl");
  EXPECT_EQ(r.report["sent"]["bytes"], job.size()) << "every byte went out";
  EXPECT_EQ(r.report["sent"]["bytes_received"], job.size()) << "and the device confirmed them all";
  EXPECT_EQ(pr["bytes_received"].get<std::size_t>(),
            job.size() + 3 * r.report["sent"]["status_queries"].get<std::size_t>())
      << "the plotter got the job and the host's ESC.O queries, nothing else";
  EXPECT_TRUE(pr["host_xon_xoff_in_os"].get<bool>()) << "popcut left XON/XOFF to the OS (IXON)";
  EXPECT_EQ(pr["overflow_bytes"], 0) << "the host's OS stopped on XOFF: no byte lost";
  EXPECT_LE(pr["max_buffer_used"].get<int>(), 256) << "the 256-byte buffer (the profile says 1024) was never exceeded";
  EXPECT_GT(pr["xoff_sent"].get<int>(), 0) << "a device slower than the line held the host off";
  EXPECT_GT(r.report["sent"]["holds"].get<int>(), 0)
      << "popcut counted the holds though the OS took the XOFF (writes that made no progress)";
  EXPECT_LE(r.report["sent"]["holds"].get<int>(), pr["xoff_sent"].get<int>()) << "at most one hold per XOFF";
  EXPECT_EQ(strokes_of(pr), strokes_of(job)) << "the device cut exactly the job";
  EXPECT_EQ(r.report["sent"]["drained_by"], "esc_o") << "done once the device said its buffer was empty";
  EXPECT_FALSE(pr["knife_down_at_end"].get<bool>());
}

// ESC.B pacing against a 256-byte plotter while the profile says 1024: popcut sends what the
// answers allow and knows the job is done when the device's own buffer is empty (it waited for
// 1024 free, which never came, and failed after hold_timeout_ms).
TEST_F(SerialPty, EscBPacingFollowsTheDevicesAnswersNotTheProfilesSize) {
  std::string p = slurp(profile_);
  replace(p, "flow_control = \"xon_xoff\"", "flow_control = \"esc_b\"");
  replace(p, "drain_query = \"esc_o\"", "drain_query = \"esc_b\"");
  profile_ = (dir_ / "host-escb.toml").string();
  std::ofstream(profile_) << p;
  std::string port;
  auto plot = plotter("pb", {"--profile", profile_, "--slowdown", "0.1"}, port);
  const Cut r = cut("townhouse.json", "serial:" + port);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "pb.err");
  const json pr = plotter_report("pb");
  EXPECT_EQ(pr["overflow_bytes"], 0) << "the answers kept popcut within the plotter's buffer";
  EXPECT_LE(pr["max_buffer_used"].get<int>(), 256) << "never past its 256 bytes";
  EXPECT_EQ(r.report["sent"]["drained_by"], "esc_b") << "done when the device said its buffer was free";
  EXPECT_EQ(strokes_of(pr), strokes_of(slurp(dir_ / "cut" / "job.hpgl"))) << "the device cut exactly the job";
  EXPECT_FALSE(pr["knife_down_at_end"].get<bool>());
}

// The profile says XON/XOFF; the plotter is set up for ESC.B pacing and never says XOFF, so its
// buffer overflows while every write of popcut's succeeds. Its ESC.E answer is the only witness:
// exit 3, and advice to cut again rather than resume.
TEST_F(SerialPty, AProfileWhoseFlowControlTheDeviceDoesNotDoFailsTheJob) {
  std::string p = slurp(profile_);
  replace(p, "flow_control = \"xon_xoff\"", "flow_control = \"esc_b\"");
  const std::string device_profile = (dir_ / "device-escb.toml").string();
  std::ofstream(device_profile) << p;
  std::string port;
  auto plot = plotter("mismatch", {"--profile", device_profile, "--slowdown", "0.5"}, port);
  const Cut r = cut("townhouse.json", "serial:" + port);
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "mismatch.err");
  const json pr = plotter_report("mismatch");
  ASSERT_GT(pr["overflow_bytes"].get<int>(), 0) << "the plotter lost bytes";
  EXPECT_EQ(r.code, 3) << "not a job that got through: " << r.err;
  EXPECT_NE(r.err.find("I/O error 16 (ESC.E)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cut the whole job again"), std::string::npos)
      << "no resume point repairs lost bytes: " << r.err;
  EXPECT_EQ(r.report["sent"]["device_io_error"], 16) << r.report.dump();
}

// A 64-byte plotter at 115200 baud: 4 ms of line (46 bytes) is more than the 16 bytes its XOFF
// leaves, so it must take no more than that at once, or it overruns itself before XOFF goes out.
TEST_F(SerialPty, ATinyBufferUnderXonXoffIsNeverOverrun) {
  std::string port;
  auto plot = plotter("tiny", {"--buffer", "64", "--slowdown", "0.01"}, port);
  const Cut r = cut("pyramid.json", "serial:" + port);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "tiny.err");
  const json pr = plotter_report("tiny");
  EXPECT_EQ(pr["overflow_bytes"], 0) << "XOFF in time";
  EXPECT_LE(pr["max_buffer_used"].get<int>(), 64);
  EXPECT_EQ(strokes_of(pr), strokes_of(slurp(dir_ / "cut" / "job.hpgl"))) << "the device cut exactly the job";
}

// No handshake at all (flow "none"): popcut paces the job by the device's motion, assuming it may
// be 25 % slower than the plan. A plotter as fast as the plan loses nothing; paced with no margin,
// a plotter 20 % slower overflows, and the job fails. Kinematics far faster than the sim's, so
// that the real-time plotter cuts the job in about five seconds.
TEST_F(SerialPty, TimePacingKeepsAPlotterWithNoHandshakeWithinItsBuffer) {
  std::string p = slurp(profile_);
  replace(p, "flow_control = \"xon_xoff\"", "flow_control = \"none\"");
  replace(p, "buffer_bytes = 1024", "buffer_bytes = 256");
  replace(p, "travel_speed_cm_s = 30.0", "travel_speed_cm_s = 300.0");
  replace(p, "accel_mm_s2 = 2000.0", "accel_mm_s2 = 50000.0");
  replace(p, "knife_up_s = 0.03", "knife_up_s = 0.001");
  replace(p, "knife_down_s = 0.03", "knife_down_s = 0.001");
  for (std::size_t at; (at = p.find("\nspeed_cm_s = 1")) != std::string::npos;)
    p.replace(at, 15, "\nspeed_cm_s = 9");  // 10, 15 cm/s: 90, 95
  const std::string fast = (dir_ / "fast.toml").string();
  std::ofstream(fast) << p;
  const std::string tight = (dir_ / "tight.toml").string();
  std::string t = p;
  replace(t, "buffer_bytes = 256", "buffer_bytes = 256\npace_margin_percent = 0");
  std::ofstream(tight) << t;

  std::string port;
  // As fast as the profile says: the margin is left for a loaded machine's delays (the in-process
  // SendJob.TimePacing* tests cover a slower device exactly, on a virtual clock).
  auto plot = plotter("paced", {"--profile", fast, "--slowdown", "1"}, port);
  profile_ = fast;
  const Cut r = cut("townhouse.json", "serial:" + port);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "paced.err");
  const json pr = plotter_report("paced");
  EXPECT_EQ(pr["overflow_bytes"], 0) << "paced within the buffer";
  EXPECT_LE(pr["max_buffer_used"].get<int>(), 192) << "about half of it, as paced";
  EXPECT_EQ(strokes_of(pr), strokes_of(slurp(dir_ / "cut" / "job.hpgl"))) << "the device cut exactly the job";
  EXPECT_EQ(r.report["sent"]["drained_by"], "esc_o") << r.report.dump();

  std::string port2;
  auto plot2 = plotter("unpaced", {"--profile", fast, "--slowdown", "1.2"}, port2);
  profile_ = tight;
  const Cut r2 = cut("townhouse.json", "serial:" + port2, "", "tight");
  ASSERT_EQ(plot2->wait(), 0) << slurp(dir_ / "unpaced.err");
  EXPECT_GT(plotter_report("unpaced")["overflow_bytes"].get<int>(), 0)
      << "a plotter with no handshake loses what overruns it";
  EXPECT_EQ(r2.code, 3) << "not a job that got through: " << r2.err;
  // Its ESC.E answer says so, unless what it made of the garbled bytes keeps it busy past the end
  // wait (a lost separator can merge two coordinates into a move of metres); the message names
  // pace_margin_percent in the first case (SendJob.ADeviceFarSlowerThanThePaceMarginIsCaughtByItsErrorReport).
  EXPECT_TRUE(r2.err.find("I/O error 16 (ESC.E)") != std::string::npos ||
              r2.err.find("still not empty") != std::string::npos)
      << r2.err;
}

// At 9600 baud under XON/XOFF a status query waits behind what the plotter has not read while it
// says XOFF, longer than timeout_ms. Over a UART the port's queue shows that; a pty's does not,
// so popcut must not take the wait for a device that stopped answering.
TEST_F(SerialPty, AQueryBehindAPtyLineHeldByXoffIsNotSilence) {
  std::string p = slurp(profile_);
  replace(p, "baud = 115200", "baud = 9600");
  profile_ = (dir_ / "slow-line.toml").string();
  std::ofstream(profile_) << p;
  std::string port;
  auto plot = plotter("xoff9600", {"--baud", "9600", "--buffer", "1024"}, port);  // the profile's size
  const Cut r = cut("townhouse.json", "serial:" + port);
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "xoff9600.err");
  const json pr = plotter_report("xoff9600");
  ASSERT_GT(pr["xoff_sent"].get<int>(), 0) << "the plotter held the line";
  EXPECT_EQ(r.code, 0) << "a healthy plotter, not one that stopped answering: " << r.err;
  EXPECT_EQ(pr["overflow_bytes"], 0);
  EXPECT_EQ(strokes_of(pr), strokes_of(slurp(dir_ / "cut" / "job.hpgl"))) << "the device cut exactly the job";
}

TEST_F(SerialPty, ADeviceThatNeverHoldsTheLineCountsNoHolds) {
  std::string port;
  auto plot = plotter("roomy", {"--buffer", "65536", "--slowdown", "0.05"}, port);  // the whole job fits: never XOFF
  const Cut r = cut("townhouse.json", "serial:" + port);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(plot->wait(), 0);
  EXPECT_EQ(plotter_report("roomy")["xoff_sent"], 0) << "the plotter never said XOFF";
  EXPECT_EQ(r.report["sent"]["holds"], 0) << "so popcut counted no hold: " << r.report["sent"].dump();
}

TEST_F(SerialPty, ADroppedLineNeverOverClaimsAndResumeFromTheAdvisedStrokeCoversTheJob) {
  std::string port;
  auto plot = plotter("p1", {"--slowdown", "0.05", "--drop-after", "700"}, port);
  const Cut first = cut("townhouse.json", "serial:" + port, "", "first");
  EXPECT_EQ(first.code, 3) << "the job did not get through: " << first.err;
  EXPECT_EQ(first.report["sent"]["error"], "disconnected") << first.report.dump();
  const std::size_t m = first.report["sent"]["last_stroke_sent"].get<std::size_t>();
  const std::size_t n = first.report["sent"]["last_stroke_written"].get<std::size_t>();
  const std::size_t total = first.report["sent"]["total_strokes"].get<std::size_t>();
  ASSERT_LT(m, total);
  EXPECT_LE(m, n) << "received never exceeds written";
  EXPECT_EQ(first.report["sent"]["received_counted_by"], "status_answers") << "the sim profile answers ESC.O";
  EXPECT_NE(first.err.find("last stroke certainly received " + std::to_string(m) + " of " + std::to_string(total)),
            std::string::npos)
      << first.err;
  EXPECT_NE(first.err.find("last stroke written " + std::to_string(n)), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("--resume-from " + std::to_string(m + 1)), std::string::npos)
      << "says how to finish: " << first.err;
  if (n > m) {
    EXPECT_NE(first.err.find("may have been cut already and are then cut a second time"), std::string::npos)
        << "says honestly that strokes " << m + 1 << ".." << n << " may be cut twice: " << first.err;
  }
  ASSERT_EQ(plot->wait(), 0);
  const json pr1 = plotter_report("p1");
  EXPECT_EQ(pr1["bytes_received"], 700) << "the plotter hung up after 700 bytes";
  const std::string job = slurp(dir_ / "first" / "job.hpgl");
  const auto planned = strokes_of(job);
  ASSERT_EQ(planned.size(), total);
  const auto cut1 = strokes_of(pr1);
  ASSERT_GE(cut1.size(), m) << "every stroke claimed received was cut: no over-claim";
  for (std::size_t i = 0; i < m; ++i) EXPECT_EQ(cut1[i], planned[i]) << "stroke " << i + 1 << " before the drop";

  std::string port2;
  auto plot2 = plotter("p2", {"--slowdown", "0.05"}, port2);
  const Cut second = cut("townhouse.json", "serial:" + port2, "--resume-from " + std::to_string(m + 1), "second");
  ASSERT_EQ(second.code, 0) << second.err;
  ASSERT_EQ(plot2->wait(), 0);
  const auto cut2 = strokes_of(plotter_report("p2"));
  EXPECT_EQ(cut2, std::vector<popcut::PlotterPath>(planned.begin() + static_cast<std::ptrdiff_t>(m), planned.end()))
      << "the resumed job cut exactly strokes " << m + 1 << ".." << total;
  // Coverage: strokes 1..m from the first run, m+1..total from the second; none missing.
  std::vector<popcut::PlotterPath> both(cut1.begin(), cut1.begin() + static_cast<std::ptrdiff_t>(m));
  both.insert(both.end(), cut2.begin(), cut2.end());
  EXPECT_EQ(both, planned) << "the two runs together cut every planned stroke";
  EXPECT_EQ(plotter_report("p2")["knife_downs"].get<std::size_t>(), total - m)
      << "no knife-down on the way to the first";
}

TEST_F(SerialPty, CtrlCCancelsSafelyEvenTwiceWithItsOwnExitCode) {
  std::string port;
  auto plot = plotter("p", {"--slowdown", "1"}, port);  // 27 s of motion: the job is surely running
  Child c({POPCUT_CLI, "cut", std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json", "--profile", profile_,
           "--device", "serial:" + port, "--out", (dir_ / "cut").string()},
          dir_ / "cut.stdout", dir_ / "cut.stderr", true);
  // Wait until bytes flow (the job file is written before the port opens), then interrupt twice.
  for (int i = 0; i < 500 && !fs::exists(dir_ / "cut" / "job.hpgl"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  c.signal(SIGINT);
  c.signal(SIGINT);
  const int code = c.wait(std::chrono::seconds(60));
  const std::string err = slurp(dir_ / "cut.stderr");
  EXPECT_EQ(code, 130) << "a cancel has its own exit code: " << err;
  EXPECT_NE(err.find("cancelled"), std::string::npos) << err;
  EXPECT_NE(err.find("lifted the knife"), std::string::npos) << err;
  ASSERT_EQ(plot->wait(), 0);
  const json pr = plotter_report("p");
  const json rep = json::parse(slurp(dir_ / "cut" / "report.json"));
  EXPECT_TRUE(rep["sent"]["cancelled"].get<bool>());
  EXPECT_LT(rep["sent"]["bytes"].get<std::size_t>(), rep["sent"]["bytes_total"].get<std::size_t>()) << "stopped early";
  EXPECT_EQ(pr["bytes_received"].get<std::size_t>(),
            rep["sent"]["bytes"].get<std::size_t>() + 3 * rep["sent"]["status_queries"].get<std::size_t>() + 6)
      << "the job up to a command boundary and the ESC.O queries, then ESC.K and PU; (6 bytes)";
  const std::size_t buffered = rep["sent"]["buffered_bytes"].get<std::size_t>();
  if (buffered > 0) {
    const json strokes = rep["sent"]["buffered_strokes"];
    EXPECT_NE(err.find("may still cut up to " + std::to_string(buffered) + " bytes (strokes " +
                       std::to_string(strokes[0].get<int>()) + ".." + std::to_string(strokes[1].get<int>()) + ")"),
              std::string::npos)
        << "says how much the device may still cut, in bytes and strokes: " << err;
  }
  // The abort (ESC.K) makes the device discard its buffer: what it received and had not cut is
  // gone, so received falls back to executed, and the one resume point is E+1: it leaves no
  // stroke uncut, and the strokes the device dropped are among those it cuts.
  ASSERT_TRUE(rep["sent"]["last_stroke_executed"].is_number()) << "sim.toml's device answers ESC.O";
  const std::size_t e = rep["sent"]["last_stroke_executed"], m = rep["sent"]["last_stroke_sent"];
  EXPECT_TRUE(rep["sent"]["buffer_discarded"].get<bool>()) << rep.dump();
  EXPECT_EQ(m, e) << "received is what the device executed: " << rep["sent"].dump();
  EXPECT_LE(m, popcut::testing::sim_plotter_strokes(pr).size()) << "every stroke counted received was cut: " << err;
  EXPECT_NE(err.find("discard its buffer, so finish with the same command and --resume-from " + std::to_string(e + 1)),
            std::string::npos)
      << "--resume-from E+1 is the advice: " << err;
  EXPECT_GT(pr.value("discarded_bytes", 0), 0)
      << "the plotter dropped what it held (else this proves little): " << pr.dump();
  EXPECT_FALSE(pr["knife_down_at_end"].get<bool>()) << "the knife is up";
  EXPECT_EQ(pr["overflow_bytes"], 0);
}

TEST_F(SerialPty, ASecondCtrlCGivesUpWaitingForADeviceThatHoldsTheLine) {
  // The device says XOFF at 192 bytes and, a thousand times slower than the profile, keeps
  // holding the line: the abort cannot go out before the hold timeout of 60 s.
  std::string p = slurp(profile_);
  replace(p, "hold_timeout_ms = 8000", "hold_timeout_ms = 60000");
  std::ofstream(profile_) << p;
  std::string port;
  auto plot = plotter("p", {"--slowdown", "1000"}, port);
  Child c({POPCUT_CLI, "cut", std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json", "--profile", profile_,
           "--device", "serial:" + port, "--out", (dir_ / "cut").string()},
          dir_ / "cut.stdout", dir_ / "cut.stderr", true);
  for (int i = 0; i < 500 && !fs::exists(dir_ / "cut" / "job.hpgl"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::this_thread::sleep_for(std::chrono::milliseconds(700));  // the line is held by now
  c.signal(SIGINT);
  // popcut says it is waiting for the device to take the abort (it holds the line).
  bool told = false;
  for (int i = 0; i < 3000 && !told; ++i) {
    told = slurp(dir_ / "cut.stderr").find("waiting up to 60 s (hold_timeout_ms) for it to take the abort") !=
           std::string::npos;
    if (!told) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(told) << "popcut says what it waits for: " << slurp(dir_ / "cut.stderr");
  c.signal(SIGINT);
  const int code = c.wait(std::chrono::seconds(50));  // well before the 60 s hold timeout
  const std::string err = slurp(dir_ / "cut.stderr");
  ASSERT_NE(code, -1) << "the second Ctrl-C ended the wait before the hold timeout: " << err;
  EXPECT_EQ(code, 130) << "still a cancel: " << err;
  EXPECT_NE(err.find("could NOT send the abort sequence: gave up waiting for the device"), std::string::npos) << err;
  const json rep = json::parse(slurp(dir_ / "cut" / "report.json"));
  EXPECT_TRUE(rep["sent"]["cancelled"].get<bool>());
  EXPECT_FALSE(rep["sent"]["abort_sent"].get<bool>()) << "the abort never reached the device";
  const std::size_t buffered = rep["sent"]["buffered_bytes"].get<std::size_t>();
  ASSERT_GT(buffered, 0u) << "the device holds bytes it may still cut";
  const json strokes = rep["sent"]["buffered_strokes"];
  EXPECT_NE(err.find("the device may still cut up to " + std::to_string(buffered) + " bytes (strokes " +
                     std::to_string(strokes[0].get<int>()) + ".." + std::to_string(strokes[1].get<int>()) + ")"),
            std::string::npos)
      << "says how much the device may still cut, in bytes and strokes: " << err;
  ASSERT_EQ(plot->wait(), 0);
  const json pr = plotter_report("p");
  // What the port still queued was dropped on giving up: the plotter got at most the job's bytes
  // and the queries, never the abort afterwards.
  EXPECT_LE(pr["bytes_received"].get<std::size_t>(),
            rep["sent"]["bytes"].get<std::size_t>() + 3 * rep["sent"]["status_queries"].get<std::size_t>())
      << "nothing beyond the job's bytes and the queries reached it";
}

TEST_F(SerialPty, ASilentDeviceIsReportedBeforeTheJobAsALineProblem) {
  std::string port;
  auto plot = plotter("mute", {"--stop-after", "0"}, port);
  const Cut mute = cut("box.json", "serial:" + port, "", "mute");
  EXPECT_EQ(mute.code, 3) << mute.err;
  EXPECT_NE(mute.err.find("the device did not answer ESC.O before sending"), std::string::npos) << mute.err;
  EXPECT_NE(mute.err.find("check the cable, the port and the baud rate (the profile says 115200 baud)"),
            std::string::npos)
      << mute.err;
  EXPECT_EQ(mute.report["sent"]["bytes"], 0) << "no byte of the job went out";
  ASSERT_EQ(plot->wait(), 0);
}

// A host that opens the port and closes it without a byte (a terminal program, a probe, a host
// failing before it sends) ends the session: the plotter holds the pty's slave until a host opens
// it, so only noticing the open lets the hang-up through.
TEST_F(SerialPty, AHostThatClosesThePortWithoutWritingEndsTheSession) {
  std::string port;
  auto plot = plotter("silent", {}, port);
  const int fd = ::open(port.c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(fd, 0) << port;
  ::close(fd);  // at once: a quick open and close must not be missed
  ASSERT_EQ(plot->wait(), 0) << "the plotter ended after the host closed the port: " << slurp(dir_ / "silent.err");
  const json pr = plotter_report("silent");
  EXPECT_EQ(pr["ended"], "host closed the port") << pr.dump();
  EXPECT_EQ(pr["bytes_received"], 0) << "nothing was written";
  EXPECT_NE(slurp(dir_ / "silent.err").find("sim-plotter: host closed the port"), std::string::npos)
      << slurp(dir_ / "silent.err");
}

// A host that opens the port and writes only later keeps the session: the open alone ends nothing.
// Meanwhile the plotter sees the port's settings as opened (38400 baud); the host then sets it
// up, writes and closes at once: its bytes arrive at the rate it set, not garbled.
TEST_F(SerialPty, AHostThatPausesAfterOpeningIsStillServed) {
  std::string port;
  auto plot = plotter("pause", {}, port);
  const int fd = ::open(port.c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(fd, 0) << port;
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // many polls of the plotter's loop
  set_up_host(fd);
  const std::string job = "IN;PU0,0;PD400,0,400,400;PU;";
  ASSERT_EQ(::write(fd, job.data(), job.size()), static_cast<ssize_t>(job.size()))
      << "the port is still there after the pause: " << std::strerror(errno);
  ::close(fd);
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "pause.err");
  const json pr = plotter_report("pause");
  EXPECT_EQ(pr["ended"], "host closed the port") << pr.dump();
  EXPECT_EQ(pr["bytes_received"], job.size()) << "every byte written after the pause arrived: " << pr.dump();
  EXPECT_EQ(pr["strokes"].size(), 1u) << "and was cut: " << pr.dump();
}

// Bytes from a host that is not popcut: the report names each malformed and unknown command with
// its byte offset and what was wrong, and the summary line on stderr mentions them.
TEST_F(SerialPty, MalformedAndUnknownCommandsAreListedWithTheirOffsets) {
  std::string port;
  auto plot = plotter("bad", {}, port);
  const int fd = open_host(port);
  ASSERT_GE(fd, 0) << port;
  //                       0  3     9           21          32 35
  const std::string job = "IN;PU0,0;PD400,0,400;PD1..2,5,7;ZZ;PU;";
  ASSERT_EQ(::write(fd, job.data(), job.size()), static_cast<ssize_t>(job.size())) << std::strerror(errno);
  ::close(fd);
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "bad.err");
  const json pr = plotter_report("bad");
  EXPECT_EQ(pr["format"], "popcut.sim-plotter.v2") << "errors became a list: a new version";
  EXPECT_EQ(pr["bytes_received"], job.size()) << pr.dump();
  const json want_errors = json::array({{{"offset", 9}, {"command", "PD"}, {"message", "odd number of coordinates"}},
                                        {{"offset", 21}, {"command", "PD"}, {"message", "malformed parameters"}}});
  EXPECT_EQ(pr["errors"], want_errors) << "each malformed command with its offset: " << pr["errors"].dump();
  const json want_unknown = json::array({{{"offset", 32}, {"command", "ZZ"}, {"message", "unknown command"}}});
  EXPECT_EQ(pr["unknown_commands"], want_unknown) << pr["unknown_commands"].dump();
  const std::string err = slurp(dir_ / "bad.err");
  EXPECT_NE(err.find("; 2 malformed commands (first: \"PD\" at byte 9: odd number of coordinates); 1 unknown command "
                     "(\"ZZ\" at byte "
                     "32: unknown command) (" +
                     (dir_ / "bad.json").string() + " lists them all)"),
            std::string::npos)
      << "the summary line names them: " << err;
}

// --link gives the port a fixed name; popcut opens a port through a symlink (as udev's
// /dev/serial/by-id names are) as the node it points at, which libserialport alone cannot.
TEST_F(SerialPty, APortNamedThroughASymlinkIsCutTo) {
  const fs::path link = dir_ / "plotter";
  std::string port;
  auto plot = plotter("linked", {"--link", link.string(), "--slowdown", "0.05"}, port);
  ASSERT_TRUE(fs::is_symlink(link)) << "the link exists once the port is printed: " << slurp(dir_ / "linked.err");
  const Cut r = cut("box.json", "serial:" + link.string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "linked.err");
  EXPECT_EQ(strokes_of(plotter_report("linked")), strokes_of(slurp(dir_ / "cut" / "job.hpgl")))
      << "the device cut exactly the job";
  EXPECT_FALSE(fs::exists(fs::symlink_status(link))) << "the link is removed when the plotter ends";

  std::ofstream(dir_ / "precious.txt") << "keep me";  // --link never replaces what is not a link
  Child refused({POPCUT_CLI, "sim-plotter", "--link", (dir_ / "precious.txt").string()}, dir_ / "refused.out",
                dir_ / "refused.err");
  EXPECT_EQ(refused.wait(), 2) << slurp(dir_ / "refused.err");
  EXPECT_NE(slurp(dir_ / "refused.err").find("exists and is not a symlink"), std::string::npos)
      << slurp(dir_ / "refused.err");
  EXPECT_EQ(slurp(dir_ / "precious.txt"), "keep me") << "the file is intact";
}

// A device that stops mid-job cuts nothing more of its buffer: popcut names E (known executed)
// <= M (certainly received) <= N (written) and both resume points; after a power cycle (a fresh
// plotter) the advised --resume-from E+1 completes the card with no stroke missing.
TEST_F(SerialPty, AStuckDeviceNamesWhatItExecutedAndResumingFromThereAfterAPowerCycleCoversTheCard) {
  // ESC.O pings: E moves where the device said "buffer empty". The host knows the plotter's
  // 256-byte buffer, so it pings every 64 bytes and M follows closely what the device received.
  std::string p = slurp(profile_);
  replace(p, "buffer_bytes = 1024", "buffer_bytes = 256");
  std::ofstream(profile_) << p;
  std::string port;
  // Slow enough that its buffer holds strokes it received and never cuts when it stops.
  std::vector<std::string> args = {"--stop-after", "1500", "--slowdown", "0.3"};
  auto plot = plotter("stuck", args, port);
  const Cut stuck = cut("townhouse.json", "serial:" + port, "", "stuck");
  EXPECT_EQ(stuck.code, 3) << "a device that stops mid-job is not a job done: " << stuck.err;
  // It stops answering, or (stopped while it held XOFF) holds the line for good: either way the
  // device is blamed, not the line.
  EXPECT_NE(stuck.err.find("paused, out of media or stuck"), std::string::npos) << stuck.err;
  EXPECT_EQ(stuck.err.find("baud"), std::string::npos)
      << "it answered before: not the cable or the baud rate: " << stuck.err;
  const json& sent = stuck.report["sent"];
  ASSERT_TRUE(sent["last_stroke_executed"].is_number()) << "the device answered queries: E is known: " << sent.dump();
  const std::size_t e = sent["last_stroke_executed"].get<std::size_t>();
  const std::size_t m = sent["last_stroke_sent"].get<std::size_t>();
  const std::size_t n = sent["last_stroke_written"].get<std::size_t>();
  EXPECT_LE(e, m);
  EXPECT_LE(m, n);
  EXPECT_NE(stuck.err.find("last stroke known executed " + std::to_string(e) + ", last stroke certainly received " +
                           std::to_string(m)),
            std::string::npos)
      << stuck.err;
  if (e < m) {
    EXPECT_NE(stuck.err.find("if it was reset or power-cycled, or lost its buffer, use --resume-from " +
                             std::to_string(e + 1)),
              std::string::npos)
        << stuck.err;
  }
  EXPECT_LE(sent["bytes_received"].get<std::size_t>(), 1500u) << "never more than the device took before it stopped";
  ASSERT_EQ(plot->wait(), 0);
  const std::string job = slurp(dir_ / "stuck" / "job.hpgl");
  const auto planned = strokes_of(job);
  const auto cut1 = strokes_of(plotter_report("stuck"));
  ASSERT_LE(e, cut1.size()) << "E never claims a stroke the device did not cut";
  for (std::size_t i = 0; i < cut1.size(); ++i)
    EXPECT_EQ(cut1[i], planned[i]) << "stroke " << i + 1 << " before the stop";

  std::string port2;
  std::vector<std::string> args2 = {"--slowdown", "0.05"};
  auto plot2 = plotter("fresh", args2, port2);  // the power-cycled device: an empty buffer
  const Cut again = cut("townhouse.json", "serial:" + port2, "--resume-from " + std::to_string(e + 1), "again");
  ASSERT_EQ(again.code, 0) << again.err;
  ASSERT_EQ(plot2->wait(), 0);
  std::vector<popcut::PlotterPath> both(cut1.begin(), cut1.begin() + static_cast<std::ptrdiff_t>(e));
  const json fresh = plotter_report("fresh");
  const auto cut2 = strokes_of(fresh);
  EXPECT_EQ(fresh["overflow_bytes"], 0) << "the resumed job reached the fresh plotter intact";
  EXPECT_EQ(cut2.size(), planned.size() - e) << "the fresh plotter cut strokes " << e + 1 << ".." << planned.size();
  EXPECT_EQ(
      first_difference_at(
          std::vector<popcut::PlotterPath>(planned.begin() + static_cast<std::ptrdiff_t>(e), planned.end()), cut2),
      -1)
      << "index of the first resumed stroke cut otherwise than planned";
  both.insert(both.end(), cut2.begin(), cut2.end());
  EXPECT_EQ(both, planned) << "strokes 1.." << e << " before the stop and " << e + 1
                           << ".. after the power cycle cover the card";
}

TEST_F(SerialPty, WithoutAStatusQueryAHeldLineIsAStallWithHonestNumbers) {
  // A profile whose device cannot be asked: popcut counts what the port reports gone, less the
  // profile's adapter_fifo_bytes (a pty has no adapter: the key alone sets the margin here).
  std::string p = slurp(profile_);
  replace(p, "drain_query = \"esc_o\"", "drain_query = \"none\"");
  replace(p, "hold_timeout_ms = 8000", "hold_timeout_ms = 3000\nadapter_fifo_bytes = FIFO");
  const std::size_t chunk = 1024 / 8;  // the sender's chunk for the profile's 1024-byte buffer
  for (const std::size_t fifo : {std::size_t{64}, std::size_t{1024}}) {
    std::string with = p;
    replace(with, "FIFO", std::to_string(fifo));
    std::ofstream(profile_) << with;
    const std::string name = "held" + std::to_string(fifo);
    std::string port;
    // It takes 1.5 KiB, says XOFF at 3/4 of its 2 KiB and takes ages to say XON.
    auto plot = plotter(name, {"--slowdown", "1000", "--buffer", "2048"}, port);
    const Cut held = cut("townhouse.json", "serial:" + port, "", name);
    EXPECT_EQ(held.code, 3) << held.err;
    EXPECT_NE(held.err.find("the device held popcut off for 3 s without taking a byte"), std::string::npos) << held.err;
    EXPECT_EQ(held.report["sent"]["error"], "timeout") << held.report.dump();
    EXPECT_EQ(held.report["sent"]["received_counted_by"], "os_queue") << "nothing to ask: the port's count";
    EXPECT_TRUE(held.report["sent"]["last_stroke_executed"].is_null()) << "a device that cannot be asked: E unknown";
    const std::size_t m = held.report["sent"]["last_stroke_sent"].get<std::size_t>();
    const std::size_t n = held.report["sent"]["last_stroke_written"].get<std::size_t>();
    EXPECT_LE(m, n);
    EXPECT_NE(held.err.find("--resume-from " + std::to_string(m + 1)), std::string::npos) << held.err;
    EXPECT_NE(held.err.find("last stroke known executed unknown"), std::string::npos) << held.err;
    // The margin: what may still be between popcut and the device is the key's FIFO plus the
    // last two writes (a pty reports no output queue, and 3 s of hold leave no line time).
    const std::size_t sent = held.report["sent"]["bytes"].get<std::size_t>();
    const std::size_t received = held.report["sent"]["bytes_received"].get<std::size_t>();
    ASSERT_GT(sent, fifo + 2 * chunk) << "the device took more than the margin before it held the line";
    EXPECT_GE(sent - received, fifo) << "adapter_fifo_bytes = " << fifo << " is held back as possibly unseen";
    EXPECT_LE(sent - received, fifo + 2 * chunk) << "and no more than it and the last two writes: the key sets M";
    ASSERT_EQ(plot->wait(), 0);
    EXPECT_EQ(plotter_report(name)["overflow_bytes"], 0);
  }
}

TEST_F(SerialPty, BadPortsAndBaudsAreReported) {
  const Cut missing = cut("box.json", "serial:/dev/popcut-no-such-port");
  EXPECT_EQ(missing.code, 3) << missing.err;
  EXPECT_NE(missing.err.find("No such file"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find("popcut devices"), std::string::npos) << "points to the listing: " << missing.err;
  EXPECT_NE(missing.err.find("popcut-no-such-port: device: not_found: "), std::string::npos)
      << "names the documented class: " << missing.err;

  const Cut by_id = cut("box.json", "serial:0403:6001:POPCUT-NONE", "", "byid");
  EXPECT_EQ(by_id.code, 3) << by_id.err;
  EXPECT_NE(by_id.err.find("no serial port belongs to USB 0403:6001 with serial number POPCUT-NONE"), std::string::npos)
      << by_id.err;

  const Cut notty = cut("box.json", "serial:/dev/null", "", "notty");
  EXPECT_EQ(notty.code, 2) << "not a serial port is a bad --device: " << notty.err;
  EXPECT_NE(notty.err.find("not a serial port"), std::string::npos) << notty.err;

  for (const char* bad : {"serial:", "serial:ttyUSB0", "usb:0b4d", "usb:xyzw:110a", "tcp:1.2.3.4"}) {
    const Cut r = cut("box.json", bad, "", "bad");
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
    EXPECT_NE(r.err.find("--device"), std::string::npos) << bad << ": " << r.err;
  }

  {  // Busy: another program holds the port's lock.
    std::string port;
    auto plot = plotter("busy", {}, port);
    const int fd = ::open(port.c_str(), O_RDWR | O_NOCTTY);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
    const Cut busy = cut("box.json", "serial:" + port, "", "busycut");
    EXPECT_EQ(busy.code, 3) << busy.err;
    EXPECT_NE(busy.err.find("is busy"), std::string::npos) << busy.err;
    ::close(fd);
    plot->signal(SIGTERM);
    EXPECT_EQ(plot->wait(), 0);
  }
  {  // Wrong baud: a device at 9600 hears garbage from a host at 115200 and never answers.
    std::string port;
    auto plot = plotter("baud", {"--baud", "9600"}, port);
    const Cut wrong = cut("box.json", "serial:" + port, "", "wrongbaud");
    EXPECT_EQ(wrong.code, 3) << wrong.err;
    EXPECT_NE(wrong.err.find("the device did not answer ESC.O before sending"), std::string::npos) << wrong.err;
    EXPECT_NE(wrong.err.find("(the profile says 115200 baud)"), std::string::npos) << wrong.err;
    ASSERT_EQ(plot->wait(), 0);
    EXPECT_EQ(plotter_report("baud")["host_baud"], 115200) << "the plotter saw the host's rate";
    EXPECT_EQ(plotter_report("baud")["strokes"].size(), 0u) << "and cut nothing";
  }
  {  // ESC.B pacing at the wrong baud: the same check, with ESC.B.
    std::string p = slurp(profile_);
    replace(p, "flow_control = \"xon_xoff\"", "flow_control = \"esc_b\"");
    replace(p, "drain_query = \"esc_o\"", "drain_query = \"esc_b\"");
    std::ofstream(profile_) << p;
    std::string port;
    auto plot = plotter("baudb", {"--baud", "9600"}, port);
    const Cut wrong = cut("box.json", "serial:" + port, "", "wrongbaudb");
    EXPECT_EQ(wrong.code, 3) << wrong.err;
    EXPECT_NE(wrong.err.find("the device did not answer ESC.B before sending"), std::string::npos) << wrong.err;
    ASSERT_EQ(plot->wait(), 0);
  }
}

TEST_F(SerialPty, AUsbProfileRefusesAnotherDevice) {
  const std::string graphtec = std::string(POPCUT_SOURCE_DIR) + "/configs/devices/graphtec-ce.toml";
  Child c({"/bin/sh", "-c",
           std::string(POPCUT_CLI) + " cut " + std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/box.json --profile " +
               graphtec + " --device usb:1234:5678 --out " + (dir_ / "o").string()},
          dir_ / "o.stdout", dir_ / "o.stderr");
  EXPECT_EQ(c.wait(), 2) << slurp(dir_ / "o.stderr");
  EXPECT_NE(slurp(dir_ / "o.stderr").find("the profile is for USB 0b4d:110a"), std::string::npos)
      << slurp(dir_ / "o.stderr");
}

// The shipped Cameo 4 as a serial GP-GL device at the simulator's line rate, paced by status;
// returns its path (the host's and, with --profile, the plotter's).
std::string gpgl_profile(const fs::path& dir) {
  std::string p = slurp(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/silhouette-cameo4.toml");
  const auto swap = [&](const std::string& from, const std::string& to) {
    const std::size_t at = p.find(from);
    EXPECT_NE(at, std::string::npos) << "silhouette-cameo4.toml has " << from;
    if (at != std::string::npos) p.replace(at, from.size(), to);
  };
  swap("[transport]\n", "[transport]\nbaud = 115200\ntimeout_ms = 3000\nhold_timeout_ms = 8000\n");
  const std::string path = (dir / "cameo.toml").string();
  std::ofstream(path) << p;
  return path;
}

// GP-GL over a pseudo-terminal: ESC ENQ before, between chunks and at the end, the device kept a
// buffer ahead of the model, and the plotter cuts exactly the job.
TEST_F(SerialPty, GpglStatusFlowCutsTheWholeJob) {
  profile_ = gpgl_profile(dir_);
  std::string port;
  auto plot = plotter("g", {"--profile", profile_, "--buffer", "1024", "--slowdown", "0.1"}, port);
  const Cut r = cut("townhouse.json", "serial:" + port);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(plot->wait(), 0) << slurp(dir_ / "g.err");
  const json pr = plotter_report("g");
  EXPECT_EQ(pr["overflow_bytes"], 0);
  EXPECT_EQ(strokes_of(pr), strokes_of(slurp(dir_ / "cut" / "job.gpgl"))) << "the device cut exactly the job";
  EXPECT_EQ(r.report["sent"]["drained_by"], "esc_enq");
  EXPECT_FALSE(pr["knife_down_at_end"].get<bool>());
}

TEST_F(SerialPty, AGpglPlotterWithNoSheetLoadedRefusesTheJob) {
  profile_ = gpgl_profile(dir_);
  std::string port;
  auto plot = plotter("e", {"--profile", profile_, "--tray-empty-after", "0"}, port);
  const Cut r = cut("box.json", "serial:" + port);
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("no sheet loaded"), std::string::npos) << r.err;
  EXPECT_EQ(r.report["sent"]["bytes"], 0);
  ASSERT_EQ(plot->wait(), 0);
  EXPECT_EQ(plotter_report("e")["bytes_received"], 2) << "ESC ENQ and nothing else";
}

// A profile of one language on a device of the other is caught before the first stroke: an
// HP-GL plotter ignores ESC ENQ, and the message says what that likely means; a GP-GL plotter
// ignores ESC.O, which reads as a wrong line (silence does not tell the language).
TEST_F(SerialPty, AProfileOfTheOtherLanguageIsCaughtBeforeTheFirstStroke) {
  const std::string hpgl = profile_;
  profile_ = gpgl_profile(dir_);
  {
    std::string port;
    auto plot = plotter("h", {}, port);  // sim.toml: an HP-GL plotter
    const Cut r = cut("box.json", "serial:" + port, "", "gpgl-on-hpgl");
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("a GP-GL profile seems to be talking to a device that does not speak GP-GL"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.report["sent"]["bytes"], 0);
    ASSERT_EQ(plot->wait(), 0);
    EXPECT_EQ(plotter_report("h")["knife_downs"], 0);
  }
  {
    std::string port;
    auto plot = plotter("gp", {"--profile", profile_}, port);
    const std::string gpgl = profile_;
    profile_ = hpgl;
    const Cut r = cut("box.json", "serial:" + port, "", "hpgl-on-gpgl");
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("the device did not answer ESC.O before sending"), std::string::npos) << r.err;
    EXPECT_EQ(r.report["sent"]["bytes"], 0);
    ASSERT_EQ(plot->wait(), 0);
    EXPECT_EQ(plotter_report("gp")["knife_downs"], 0);
    profile_ = gpgl;
  }
}

}  // namespace
