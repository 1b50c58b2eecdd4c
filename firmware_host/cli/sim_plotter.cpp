// popcut sim-plotter: the simulated cutter behind a pseudo-terminal, in real time, as a stand-in serial cutter.
#include "cli/sim_plotter.h"
#include "report_json.h"
#include "config_dir.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <sys/inotify.h>
#include <termios.h>
#include <unistd.h>
#include <sys/ioctl.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <thread>

#include "cli/checks.h"
#include "cli/common.h"
#include "popcut/drivers/posix_baud.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

std::atomic<bool> g_stop{false};
extern "C" void on_stop(int) { g_stop = true; }
// A person at the device: SIGUSR1 loads a sheet, SIGUSR2 takes it out (its tray is then empty).
std::atomic<int> g_sheet{0};  // 0: no change asked; 1: loaded; 2: empty
extern "C" void on_sheet(int sig) { g_sheet = sig == SIGUSR1 ? 1 : 2; }

// Tells when a host opens the port. The pty's master reports a hang-up (POLLHUP, and EIO once
// the bytes written are read) while no fd of the slave is open, and so from the start when none
// ever was: a plotter not holding the slave cannot tell "nobody opened it yet" from "a host
// opened and closed it between two polls". So the plotter holds the slave until a host has
// opened it, and learns of that open from inotify: the VFS reports IN_OPEN on the slave's inode
// (/dev/pts/N, also opened through --link) once an open has succeeded, whatever the host does
// next. Then the plotter lets go of the slave, and the kernel's own count of open fds ends the
// session when the host's last one closes: however soon (closed already, the hang-up comes as
// the plotter lets go), with any bytes written still read first, and however many fds or child
// processes the host has. Not usable: TIOCPKT (reports flow control and flushes, a termios change
// only in EXTPROC mode; a host may open and close without changing anything), a first byte (a
// host may write none).
class OpenWatch {
 public:
  explicit OpenWatch(const std::string& path) : fd_(::inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
    if (fd_ >= 0 && ::inotify_add_watch(fd_, path.c_str(), IN_OPEN) >= 0) return;
    error_ = std::strerror(errno);
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  ~OpenWatch() {
    if (fd_ >= 0) ::close(fd_);
  }
  OpenWatch(const OpenWatch&) = delete;
  OpenWatch& operator=(const OpenWatch&) = delete;
  // Why opens go unnoticed (empty when watching).
  const std::string& error() const { return error_; }
  // Whether the port was opened since the last call.
  bool opened() {
    alignas(inotify_event) char events[4096];
    bool any = false;
    for (ssize_t n; fd_ >= 0 && (n = ::read(fd_, events, sizeof events)) > 0;) {
      for (ssize_t at = 0; at < n;) {
        const auto* e = reinterpret_cast<const inotify_event*>(events + at);
        any = any || (e->mask & (IN_OPEN | IN_Q_OVERFLOW)) != 0;  // events lost: opens, surely
        at += static_cast<ssize_t>(sizeof(inotify_event) + e->len);
      }
    }
    return any;
  }

 private:
  int fd_;
  std::string error_;
};

json report_json(const drivers::SimCutter& c, const std::string& path, int host_baud, bool host_ixon,
                 const std::string& ended) {
  const drivers::SimReport& r = c.report();
  json strokes = json::array();
  for (const drivers::SimStroke& s : c.strokes()) {
    json pts = json::array();
    for (const auto& p : s.points_pu) pts.push_back({p[0], p[1]});
    strokes.push_back({{"pen", s.pen}, {"force", s.force}, {"speed_cm_s", s.speed_cm_s}, {"points_pu", pts}});
  }
  return {{"format", "popcut.sim-plotter.v2"},
          {"port", path},
          {"ended", ended},
          {"device_baud", c.profile().transport.baud},
          {"host_baud", host_baud},
          {"host_xon_xoff_in_os", host_ixon},
          {"bytes_received", r.bytes_received},
          {"commands", r.commands},
          {"overflow_bytes", r.overflow_bytes},
          {"max_buffer_used", r.max_buffer_used},
          {"discarded_bytes", r.discarded_bytes},
          {"buffer_bytes", c.profile().transport.buffer_bytes},
          {"xoff_sent", r.xoff_sent},
          {"queries_answered", r.queries_answered},
          {"knife_downs", r.knife_downs},
          {"knife_down_at_end", c.knife_down()},
          {"cut_mm", r.knife_down_mm},
          {"motion_time_s", r.motion_time_s},
          {"unknown_commands", sim_issues_json(r.unknown)},
          {"errors", sim_issues_json(r.errors)},
          {"strokes", strokes}};
}

// '; 2 malformed commands (first: "PD" at byte 9: odd number of coordinates)' for the summary line.
std::string issues_summary(const std::vector<drivers::SimIssue>& issues, const std::string& what) {
  if (issues.empty()) return "";
  const drivers::SimIssue& first = issues.front();
  return "; " + std::to_string(issues.size()) + " " + what + (issues.size() == 1 ? "" : "s") + " (" +
         (issues.size() == 1 ? "" : "first: ") + json(first.command).dump() + " at byte " +
         std::to_string(first.offset) + ": " + first.message + ")";
}

// The port the simulated cutter serves: the master side it reads and answers on, and the slave
// side it holds until a host has opened it (OpenWatch).
struct Pty {
  int master = -1;
  int slave = -1;
  std::string path;  // /dev/pts/N
};

Pty open_pty() {
  Pty pty;
  if (::openpty(&pty.master, &pty.slave, nullptr, nullptr, nullptr) != 0) {
    throw CliError(kCannotWrite, ErrorCode::io, "", "output",
                   std::string("cannot create a pseudo-terminal: ") + std::strerror(errno));
  }
  termios tio{};
  ::tcgetattr(pty.slave, &tio);
  ::cfmakeraw(&tio);  // no echo of our replies back to us, no line editing
  ::tcsetattr(pty.slave, TCSANOW, &tio);
  ::fcntl(pty.master, F_SETFL, ::fcntl(pty.master, F_GETFL) | O_NONBLOCK);
  ::fcntl(pty.master, F_SETFD, FD_CLOEXEC);
  ::fcntl(pty.slave, F_SETFD, FD_CLOEXEC);
  pty.path = ::ttyname(pty.slave);
  return pty;
}

// --link: a stale link from an earlier run is replaced; anything else there is the user's.
void make_link(const std::string& link, const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status there = std::filesystem::symlink_status(link, ec);
  if (std::filesystem::exists(there) && !std::filesystem::is_symlink(there)) {
    throw Error(ErrorCode::invalid_input, link, "--link", "exists and is not a symlink: not replacing it");
  }
  std::filesystem::remove(link, ec);
  std::filesystem::create_symlink(path, link, ec);
  if (ec) throw CliError(kCannotWrite, ErrorCode::io, link, "output", "cannot create the link: " + ec.message());
}

drivers::SimCutter make_cutter(const SimPlotterCommand& s) {
  drivers::DeviceProfile profile =
      drivers::load_profile(s.profile_path.empty() ? find_config_file("devices/sim.toml") : s.profile_path);
  if (s.baud > 0) profile.transport.baud = s.baud;
  if (s.buffer_bytes > 0) profile.transport.buffer_bytes = static_cast<std::size_t>(s.buffer_bytes);
  drivers::SimFaults faults;
  faults.slowdown = s.slowdown;
  if (s.drop_after >= 0) faults.drop_after_bytes = static_cast<std::size_t>(s.drop_after);
  if (s.stop_after >= 0) faults.stop_answering_after_bytes = static_cast<std::size_t>(s.stop_after);
  if (s.tray_empty_after >= 0) faults.tray_empty_after_bytes = static_cast<std::size_t>(s.tray_empty_after);
  if (s.pause_after >= 0) faults.pause_after_bytes = static_cast<std::size_t>(s.pause_after);
  return drivers::SimCutter(profile, faults);
}

// One host's session on the port, in real time: the line's bytes into the cutter at the baud
// rate, its replies back, until the host closes the port, the cutter drops the line or Ctrl-C.
class Session {
 public:
  Session(drivers::SimCutter& cutter, Pty& pty, OpenWatch& opens)
      : cutter_(cutter),
        pty_(pty),
        opens_(opens),
        profile_(cutter.profile()),
        held_(cutter.holds_line()),  // hardware flow control: a full buffer stops the line
        xon_xoff_(profile_.transport.flow == drivers::FlowControl::xon_xoff),
        cap_(profile_.transport.buffer_bytes),
        // Bytes per read: about 4 ms of line, so replies (XOFF) go out within a few characters.
        slice_(std::max<std::size_t>(1, static_cast<std::size_t>(profile_.transport.baud / 10 / 250))) {}

  void serve() {
    while (!g_stop && step()) {
    }
  }
  int host_baud() const { return host_baud_; }
  bool host_ixon() const { return host_ixon_; }
  const std::string& ended() const { return ended_; }

 private:
  double now_s() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

  // A host has opened the port: from now on its closing it (the last fd of the slave) ends the session.
  void host_arrived() {
    seen_host_ = true;
    ::close(pty_.slave);
    pty_.slave = -1;
  }

  // The host's line settings (a pty's master sees the slave's termios): its rate, and whether its
  // OS stops transmitting on XOFF (IXON), as a UART driver does within a character.
  bool read_host_line() {
    termios host{};
    if (::tcgetattr(pty_.master, &host) != 0) return false;
    host_baud_ = drivers::baud_of_speed(::cfgetospeed(&host));
    host_ixon_ = (host.c_iflag & IXON) != 0;
    return true;
  }

  // One pass: replies, then what the line brings. False when the session is over.
  bool step() {
    if (!seen_host_ && opens_.opened()) host_arrived();
    if (const int sheet = g_sheet.exchange(0); sheet != 0) {
      cutter_.set_media_loaded(sheet == 1);
      std::cerr << "sim-plotter: " << (sheet == 1 ? "a sheet is loaded" : "the sheet is taken out: its tray is empty")
                << std::endl;
    }
    const double t = now_s();
    // Replies first: XOFF must not wait behind anything.
    const drivers::IoResult rep = cutter_.reply(buf_, sizeof buf_, 0);
    if (rep.bytes > 0 && ::write(pty_.master, buf_, rep.bytes) < 0 && errno != EAGAIN) return false;
    if (cutter_.now_s() > t) {
      // The line is still busy with bytes already taken: they arrive at the baud rate.
      std::this_thread::sleep_for(std::chrono::duration<double>(std::min(cutter_.now_s() - t, 0.004)));
      return true;
    }
    // Once the host has closed the port its settings are gone: keep the last ones it used (a
    // transmitter stopped by XOFF sends nothing more after the close either). Read from the
    // host's open on, so that its IXON already bounds the first read after a stall.
    pollfd closed{pty_.master, 0, 0};
    const bool host_gone = ::poll(&closed, 1, 0) > 0 && (closed.revents & POLLHUP);
    if (seen_host_ && !host_gone) read_host_line();
    const std::size_t room = room_at(t);
    if (room == 0) return idle(t, host_gone);
    pollfd p{pty_.master, POLLIN, 0};
    ::poll(&p, 1, 4);
    const ssize_t n = ::read(pty_.master, buf_, room);
    if (n < 0 && errno == EIO) {
      if (seen_host_) {
        ended_ = "host closed the port";
        return false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));  // nobody has opened it yet
      return true;
    }
    if (n <= 0) {
      cutter_.advance(std::max(t, cutter_.now_s()));
      return true;
    }
    return take(static_cast<std::size_t>(n), host_gone);
  }

  // Bytes the cutter takes in this read at time t.
  std::size_t room_at(double t) const {
    // A slice, and what the line carried while this process was not running (a loaded machine),
    // so the device keeps up with the line rate.
    const double behind_s = std::max(0.0, t - cutter_.now_s());
    std::size_t room =
        std::min(sizeof buf_, slice_ + static_cast<std::size_t>(behind_s * profile_.transport.baud / 10));
    // A host stopping on XOFF: never more than XOFF's headroom at once, so XOFF goes out in time
    // (a slice can be more than the headroom of a small buffer: 46 bytes at 115200 baud against
    // 16 left of 64).
    if (xon_xoff_ && host_ixon_)
      room = std::min(room, std::max<std::size_t>(1, cap_ * 3 / 4 - std::min(cap_ * 3 / 4, cutter_.buffer_used())));
    if (held_) room = std::min(room, cap_ - std::min(cap_, cutter_.buffer_used()));  // hardware flow: stop reading
    // After XOFF a transmitter stopped by its OS sends nothing: bytes waiting in the pty are
    // still the host's, not on the line. A host doing XON/XOFF itself already put them on the
    // line, and they arrive (and overflow a full buffer) whether it stops or not.
    if (xon_xoff_ && host_ixon_ && cutter_.holding_off()) room = 0;
    return room;
  }

  // No room for a byte: the device works on. False when a gone host has nothing more to send.
  bool idle(double t, bool host_gone) {
    if (seen_host_ && host_gone) {
      // A host closing a serial port leaves what it wrote to go out (Linux waits up to its
      // closing_wait, 30 s) once the device lets it: keep taking it while there is any and the
      // device can make room, as the device would receive it.
      int waiting = 0;
      if (gone_at_s_ < 0) gone_at_s_ = t;
      if (::ioctl(pty_.master, FIONREAD, &waiting) != 0 || waiting <= 0 || cutter_.frozen() || t - gone_at_s_ > 30) {
        ended_ = "host closed the port";
        return false;
      }
    }
    cutter_.advance(t);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return true;
  }

  // The n bytes just read reach the cutter. False when it dropped the line.
  bool take(std::size_t n, bool host_gone) {
    if (!seen_host_) host_arrived();  // a byte shows it too, should opens go unnoticed
    if ((host_gone || !read_host_line()) && !host_wrote_) {
      // Gone before its first byte was read: the settings last read may be those it opened the
      // port with, before it set the port up (set, write and close within one poll). Unknown,
      // then: its bytes are taken as sent.
      host_baud_ = 0;
      host_ixon_ = false;
    }
    host_wrote_ = true;
    if (host_baud_ != 0 && host_baud_ != profile_.transport.baud) {
      // A UART at the wrong rate sees framing errors, not the bytes that were sent.
      for (std::size_t i = 0; i < n; ++i) buf_[i] = static_cast<std::uint8_t>(buf_[i] ^ 0x5a);
    }
    // Bytes that waited in the pseudo-terminal were on the line meanwhile: the clock stays
    // where the line left it, so they arrive (and interleave with motion) at the baud rate.
    const drivers::IoResult got = cutter_.receive(buf_, n, 0);
    if (got.status.error == drivers::TransportError::disconnected) {
      ended_ = "dropped the line (fault)";
      return false;
    }
    return true;
  }

  drivers::SimCutter& cutter_;
  Pty& pty_;
  OpenWatch& opens_;
  const drivers::DeviceProfile& profile_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  const bool held_, xon_xoff_;
  const std::size_t cap_, slice_;
  int host_baud_ = 0;
  bool host_ixon_ = false;
  std::string ended_ = "stopped";
  bool seen_host_ = false, host_wrote_ = false;
  double gone_at_s_ = -1;  // when the host was seen gone with bytes still on their way
  std::uint8_t buf_[4096];
};

// The summary line on stderr, and --report and --svg, once the session is over.
void write_results(const SimPlotterCommand& s, const drivers::SimCutter& cutter, const std::string& path,
                   const Session& session) {
  const json report = report_json(cutter, path, session.host_baud(), session.host_ixon(), session.ended());
  if (!s.report_path.empty())
    write_cli_output(s.report_path, [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
  if (!s.svg_path.empty()) write_cli_output(s.svg_path, [&](std::ostream& o) { cutter.write_svg(o); });
  const drivers::SimReport& r = cutter.report();
  std::string issues = issues_summary(r.errors, "malformed command") + issues_summary(r.unknown, "unknown command");
  if (r.errors.size() > 1 || r.unknown.size() > 1) {  // the line shows the first of each kind
    issues += s.report_path.empty() ? " (--report FILE lists them all)" : " (" + s.report_path + " lists them all)";
  }
  std::cerr << "sim-plotter: " << session.ended() << "; received " << r.bytes_received << " bytes, cut "
            << cutter.strokes().size() << " strokes, " << r.overflow_bytes << " bytes lost to overflow" << issues
            << "\n";
}

int run_sim_plotter(const SimPlotterCommand& s) {
  drivers::SimCutter cutter = make_cutter(s);
  const drivers::DeviceProfile& profile = cutter.profile();
  Pty pty = open_pty();
  OpenWatch opens(pty.path);  // before anyone can know the port
  if (!s.link.empty()) make_link(s.link, pty.path);
  std::cout << pty.path << std::endl;  // the first line: where to point --device serial:
  std::cerr << "sim-plotter: " << profile.name << " on " << pty.path << " at " << profile.transport.baud << " baud, "
            << profile.transport.buffer_bytes << "-byte buffer, flow " << drivers::to_string(profile.transport.flow)
            << "; stops when the host closes the port (or on Ctrl-C)\n";
  if (!opens.error().empty()) {
    std::cerr << "sim-plotter: warning: cannot watch " << pty.path
              << " for a host opening it (inotify: " << opens.error()
              << "); a host that closes the port without writing a byte is not noticed: end it with Ctrl-C\n";
  }
  struct sigaction sa {};
  sa.sa_handler = on_stop;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
  struct sigaction sheet {};
  sheet.sa_handler = on_sheet;
  ::sigaction(SIGUSR1, &sheet, nullptr);
  ::sigaction(SIGUSR2, &sheet, nullptr);

  Session session(cutter, pty, opens);
  session.serve();
  ::close(pty.master);  // the host sees a hang-up
  if (pty.slave >= 0) ::close(pty.slave);
  cutter.run_to_end(false);  // a device goes on cutting what it holds; a command cut short it never ends
  if (!s.link.empty()) {
    std::error_code ec;
    std::filesystem::remove(s.link, ec);
  }
  write_results(s, cutter, pty.path, session);
  return static_cast<int>(kOk);
}

}  // namespace

json sim_issues_json(const std::vector<drivers::SimIssue>& issues) {
  json out = json::array();
  for (const drivers::SimIssue& i : issues)
    out.push_back({{"offset", i.offset}, {"command", i.command}, {"message", i.message}});
  return out;
}

void add_sim_plotter_command(CLI::App& app, SimPlotterCommand& s) {
  s.app = app.add_subcommand(
      "sim-plotter",
      "Run the simulated cutter on the far side of a pseudo-terminal, in real time: prints the port\n"
      "(e.g. /dev/pts/3) on the first line, then serves one session; point `popcut cut --device\n"
      "serial:PORT` at it (under the test shim, docs/transports.md). It waits for a host to open the\n"
      "port; the session ends when the host closes it (whether it wrote or not) or on Ctrl-C, and it\n"
      "then writes what it cut (--report, --svg), prints a summary line on stderr and exits.\n"
      "One session per process: start one per job.\n"
      "Exit 0: the session ended. Exit 2: a bad option or profile. Exit 3: no pseudo-terminal, link\n"
      "or output file could be made.");
  s.app
      ->add_option(
          "--profile", s.profile_path,
          "Device profile (TOML) it behaves like: line rate, buffer, flow control, answers, kinematics\n"
          "(default: devices/sim.toml from popcut's configs: 115200 baud, 1024 bytes, XON/XOFF, answers ESC.O)")
      ->type_name("FILE");
  s.app
      ->add_option("--baud", s.baud,
                   "Line rate in baud (bits/s; default: the profile's); bytes from a host at another rate arrive\n"
                   "garbled, as on a UART")
      ->check(CLI::Range(300, 4000000));
  s.app
      ->add_option("--buffer", s.buffer_bytes,
                   "Input buffer in bytes (default: the profile's buffer_bytes); with XON/XOFF it says XOFF at 3/4\n"
                   "full and XON at 1/4")
      ->check(CLI::Range(64, 1 << 26));
  s.app
      ->add_option("--slowdown", s.slowdown,
                   "Factor on the time every motion takes (default 1: the profile's kinematics; 2: half as fast;\n"
                   "0.1: ten times faster)")
      ->check(finite_range(0.0001, 1000.0));
  s.app->add_option("--drop-after", s.drop_after, "Hang up after receiving N bytes, as a pulled cable (default: never)")
      ->type_name("N")
      ->check(finite_range(0, 1e12));
  s.app
      ->add_option("--stop-after", s.stop_after,
                   "After receiving N bytes, stop answering and cutting, as a paused or stuck device (default: never)")
      ->type_name("N")
      ->check(finite_range(0, 1e12));
  s.app
      ->add_option("--tray-empty-after", s.tray_empty_after,
                   "No sheet loaded from the start (0) or after receiving N bytes (the sheet ran out): it cuts\n"
                   "nothing more and says so in its status answer (GP-GL ESC ENQ: tray empty) (default: never).\n"
                   "kill -USR1 loads a sheet, kill -USR2 takes it out, as a person at the device would")
      ->type_name("N")
      ->check(finite_range(0, 1e12));
  s.app
      ->add_option("--pause-after", s.pause_after,
                   "After receiving N bytes, its pause key: it cuts nothing more and says so in its status\n"
                   "answer (GP-GL ESC ENQ: paused) (default: never)")
      ->type_name("N")
      ->check(finite_range(0, 1e12));
  s.app
      ->add_option("--link", s.link,
                   "Also make PATH a symlink to the port, a fixed name for scripts (--device serial:PATH); an old\n"
                   "link there is replaced, anything else refused; removed on exit")
      ->type_name("PATH");
  s.app
      ->add_option("--report", s.report_path,
                   "When the session ends, write what it received and cut as JSON (popcut.sim-plotter.v2,\n"
                   "docs/formats.md): bytes, overflow, XOFFs, malformed and unknown commands, strokes")
      ->type_name("FILE");
  s.app->add_option("--svg", s.svg_path, "When the session ends, write what it cut as SVG, one colour per pen")
      ->type_name("FILE");
}

std::optional<int> run_sim_plotter_command(const SimPlotterCommand& s) {
  if (s.app && *s.app) return run_guarded(false, [&] { return run_sim_plotter(s); });
  return std::nullopt;
}

}  // namespace popcut::cli
