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
#include "cli/commands.h"
#include "popcut/drivers/posix_baud.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/error.h"

namespace popcut::cli {
namespace {

using nlohmann::json;

std::atomic<bool> g_stop{false};
extern "C" void on_stop(int) { g_stop = true; }

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

json report_json(const drivers::SimCutter& c, const std::string& path, int host_baud, bool host_ixon, const std::string& ended) {
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
         (issues.size() == 1 ? "" : "first: ") + json(first.command).dump() + " at byte " + std::to_string(first.offset) + ": " +
         first.message + ")";
}

int run_sim_plotter(const SimPlotterCommand& s) {
  return run_guarded(false, [&] {
    drivers::DeviceProfile profile = drivers::load_profile(
        s.profile_path.empty() ? find_config_file("devices/sim.toml") : s.profile_path);
    if (s.baud > 0) profile.transport.baud = s.baud;
    if (s.buffer_bytes > 0) profile.transport.buffer_bytes = static_cast<std::size_t>(s.buffer_bytes);
    drivers::SimFaults faults;
    faults.slowdown = s.slowdown;
    if (s.drop_after >= 0) faults.drop_after_bytes = static_cast<std::size_t>(s.drop_after);
    if (s.stop_after >= 0) faults.stop_answering_after_bytes = static_cast<std::size_t>(s.stop_after);
    drivers::SimCutter cutter(profile, faults);

    int master = -1, slave = -1;
    if (::openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) {
      throw Error(ErrorCode::io, "", "output", std::string("cannot create a pseudo-terminal: ") + std::strerror(errno));
    }
    termios tio{};
    ::tcgetattr(slave, &tio);
    ::cfmakeraw(&tio);  // no echo of our replies back to us, no line editing
    ::tcsetattr(slave, TCSANOW, &tio);
    ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
    ::fcntl(master, F_SETFD, FD_CLOEXEC);
    ::fcntl(slave, F_SETFD, FD_CLOEXEC);
    const std::string path = ::ttyname(slave);
    OpenWatch opens(path);  // before anyone can know the port
    if (!s.link.empty()) {
      std::error_code ec;
      // A stale link from an earlier run is replaced; anything else there is the user's.
      const std::filesystem::file_status there = std::filesystem::symlink_status(s.link, ec);
      if (std::filesystem::exists(there) && !std::filesystem::is_symlink(there)) {
        throw Error(ErrorCode::invalid_input, s.link, "--link", "exists and is not a symlink: not replacing it");
      }
      std::filesystem::remove(s.link, ec);
      std::filesystem::create_symlink(path, s.link, ec);
      if (ec) throw Error(ErrorCode::io, s.link, "output", "cannot create the link: " + ec.message());
    }
    std::cout << path << std::endl;  // the first line: where to point --device serial:
    std::cerr << "sim-plotter: " << profile.name << " on " << path << " at " << profile.transport.baud << " baud, "
              << profile.transport.buffer_bytes << "-byte buffer, flow " << drivers::to_string(profile.transport.flow)
              << "; stops when the host closes the port (or on Ctrl-C)\n";
    if (!opens.error().empty()) {
      std::cerr << "sim-plotter: warning: cannot watch " << path << " for a host opening it (inotify: " << opens.error()
                << "); a host that closes the port without writing a byte is not noticed: end it with Ctrl-C\n";
    }

    struct sigaction sa {};
    sa.sa_handler = on_stop;
    ::sigaction(SIGINT, &sa, nullptr);
    ::sigaction(SIGTERM, &sa, nullptr);

    const auto start = std::chrono::steady_clock::now();
    const auto now_s = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    const bool held = cutter.holds_line();  // hardware flow control: a full buffer stops the line
    const bool xon_xoff = profile.transport.flow == drivers::FlowControl::xon_xoff;
    bool host_ixon = false;
    const std::size_t cap = profile.transport.buffer_bytes;
    // Bytes per read: about 4 ms of line, so replies (XOFF) go out within a few characters.
    const std::size_t slice = std::max<std::size_t>(1, static_cast<std::size_t>(profile.transport.baud / 10 / 250));
    int host_baud = 0;
    std::string ended = "stopped";
    bool seen_host = false, host_wrote = false;
    double gone_at_s = -1;  // when the host was seen gone with bytes still on their way
    // A host has opened the port: from now on its closing it (the last fd of the slave) ends the session.
    const auto host_arrived = [&] {
      seen_host = true;
      ::close(slave);
      slave = -1;
    };
    std::uint8_t buf[4096];
    while (!g_stop) {
      if (!seen_host && opens.opened()) host_arrived();
      const double t = now_s();
      // Replies first: XOFF must not wait behind anything.
      const drivers::IoResult rep = cutter.reply(buf, sizeof buf, 0);
      if (rep.bytes > 0 && ::write(master, buf, rep.bytes) < 0 && errno != EAGAIN) break;
      if (cutter.now_s() > t) {
        // The line is still busy with bytes already taken: they arrive at the baud rate.
        std::this_thread::sleep_for(std::chrono::duration<double>(std::min(cutter.now_s() - t, 0.004)));
        continue;
      }
      // The host's line settings (a pty's master sees the slave's termios): its rate, and whether
      // its OS stops transmitting on XOFF (IXON), as a UART driver does within a character.
      // Once the host has closed the port its settings are gone: keep the last ones it used (a
      // transmitter stopped by XOFF sends nothing more after the close either). Read from the
      // host's open on, so that its IXON already bounds the first read after a stall.
      pollfd closed{master, 0, 0};
      const bool host_gone = ::poll(&closed, 1, 0) > 0 && (closed.revents & POLLHUP);
      termios host{};
      if (seen_host && !host_gone && ::tcgetattr(master, &host) == 0) {
        host_baud = drivers::baud_of_speed(::cfgetospeed(&host));
        host_ixon = (host.c_iflag & IXON) != 0;
      }
      // Bytes per read: a slice, and what the line carried while this process was not running
      // (a loaded machine), so the device keeps up with the line rate.
      const double behind_s = std::max(0.0, t - cutter.now_s());
      std::size_t room = std::min(sizeof buf, slice + static_cast<std::size_t>(behind_s * profile.transport.baud / 10));
      // A host stopping on XOFF: never more than XOFF's headroom at once, so XOFF goes out in time
      // (a slice can be more than the headroom of a small buffer: 46 bytes at 115200 baud against
      // 16 left of 64).
      if (xon_xoff && host_ixon) room = std::min(room, std::max<std::size_t>(1, cap * 3 / 4 - std::min(cap * 3 / 4, cutter.buffer_used())));
      if (held) room = std::min(room, cap - std::min(cap, cutter.buffer_used()));  // hardware flow: stop reading
      // After XOFF a transmitter stopped by its OS sends nothing: bytes waiting in the pty are
      // still the host's, not on the line. A host doing XON/XOFF itself already put them on the
      // line, and they arrive (and overflow a full buffer) whether it stops or not.
      if (xon_xoff && host_ixon && cutter.holding_off()) room = 0;
      if (room == 0) {
        if (seen_host && host_gone) {
          // A host closing a serial port leaves what it wrote to go out (Linux waits up to its
          // closing_wait, 30 s) once the device lets it: keep taking it while there is any and the
          // device can make room, as the device would receive it.
          int waiting = 0;
          if (gone_at_s < 0) gone_at_s = t;
          if (::ioctl(master, FIONREAD, &waiting) != 0 || waiting <= 0 || cutter.frozen() || t - gone_at_s > 30) {
            ended = "host closed the port";
            break;
          }
        }
        cutter.advance(t);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        continue;
      }
      pollfd p{master, POLLIN, 0};
      ::poll(&p, 1, 4);
      const ssize_t n = ::read(master, buf, room);
      if (n < 0 && errno == EIO) {
        if (seen_host) {
          ended = "host closed the port";
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));  // nobody has opened it yet
        continue;
      }
      if (n <= 0) {
        cutter.advance(std::max(t, cutter.now_s()));
        continue;
      }
      if (!seen_host) host_arrived();  // a byte shows it too, should opens go unnoticed
      if (!host_gone && ::tcgetattr(master, &host) == 0) {
        host_baud = drivers::baud_of_speed(::cfgetospeed(&host));
        host_ixon = (host.c_iflag & IXON) != 0;
      } else if (!host_wrote) {
        // Gone before its first byte was read: the settings last read may be those it opened the
        // port with, before it set the port up (set, write and close within one poll). Unknown,
        // then: its bytes are taken as sent.
        host_baud = 0;
        host_ixon = false;
      }
      host_wrote = true;
      if (host_baud != 0 && host_baud != profile.transport.baud) {
        // A UART at the wrong rate sees framing errors, not the bytes that were sent.
        for (ssize_t i = 0; i < n; ++i) buf[i] = static_cast<std::uint8_t>(buf[i] ^ 0x5a);
      }
      // Bytes that waited in the pseudo-terminal were on the line meanwhile: the clock stays
      // where the line left it, so they arrive (and interleave with motion) at the baud rate.
      const drivers::IoResult got = cutter.receive(buf, static_cast<std::size_t>(n), 0);
      if (got.status.error == drivers::TransportError::disconnected) {
        ended = "dropped the line (fault)";
        break;
      }
    }
    ::close(master);  // the host sees a hang-up
    if (slave >= 0) ::close(slave);
    cutter.run_to_end(false);  // a device goes on cutting what it holds; a command cut short it never ends
    if (!s.link.empty()) {
      std::error_code ec;
      std::filesystem::remove(s.link, ec);
    }
    const json report = report_json(cutter, path, host_baud, host_ixon, ended);
    if (!s.report_path.empty()) write_cli_output(s.report_path, [&](std::ostream& o) { o << rounded_numbers(report).dump(2) << "\n"; });
    if (!s.svg_path.empty()) write_cli_output(s.svg_path, [&](std::ostream& o) { cutter.write_svg(o); });
    const drivers::SimReport& r = cutter.report();
    std::string issues = issues_summary(r.errors, "malformed command") + issues_summary(r.unknown, "unknown command");
    if (r.errors.size() > 1 || r.unknown.size() > 1) {  // the line shows the first of each kind
      issues += s.report_path.empty() ? " (--report FILE lists them all)" : " (" + s.report_path + " lists them all)";
    }
    std::cerr << "sim-plotter: " << ended << "; received " << r.bytes_received << " bytes, cut " << cutter.strokes().size()
              << " strokes, " << r.overflow_bytes << " bytes lost to overflow" << issues << "\n";
    return static_cast<int>(kOk);
  });
}

}  // namespace

json sim_issues_json(const std::vector<drivers::SimIssue>& issues) {
  json out = json::array();
  for (const drivers::SimIssue& i : issues) out.push_back({{"offset", i.offset}, {"command", i.command}, {"message", i.message}});
  return out;
}

void add_sim_plotter_command(CLI::App& app, SimPlotterCommand& s) {
  s.app = app.add_subcommand("sim-plotter",
                             "Run the simulated cutter on the far side of a pseudo-terminal, in real time: prints the port\n"
                             "(e.g. /dev/pts/3) on the first line, then serves one session; point `popcut cut --device\n"
                             "serial:PORT` at it (under the test shim, docs/transports.md). It waits for a host to open the\n"
                             "port; the session ends when the host closes it (whether it wrote or not) or on Ctrl-C, and it\n"
                             "then writes what it cut (--report, --svg), prints a summary line on stderr and exits.\n"
                             "One session per process: start one per job.\n"
                             "Exit 0: the session ended. Exit 2: a bad option or profile. Exit 3: no pseudo-terminal, link\n"
                             "or output file could be made.");
  s.app->add_option("--profile", s.profile_path,
                    "Device profile (TOML) it behaves like: line rate, buffer, flow control, answers, kinematics\n"
                    "(default: devices/sim.toml from popcut's configs: 115200 baud, 1024 bytes, XON/XOFF, answers ESC.O)")
      ->type_name("FILE");
  s.app->add_option("--baud", s.baud,
                    "Line rate in baud (bits/s; default: the profile's); bytes from a host at another rate arrive\n"
                    "garbled, as on a UART")
      ->check(CLI::Range(300, 4000000));
  s.app->add_option("--buffer", s.buffer_bytes,
                    "Input buffer in bytes (default: the profile's buffer_bytes); with XON/XOFF it says XOFF at 3/4\n"
                    "full and XON at 1/4")
      ->check(CLI::Range(64, 1 << 26));
  s.app->add_option("--slowdown", s.slowdown,
                    "Factor on the time every motion takes (default 1: the profile's kinematics; 2: half as fast;\n"
                    "0.1: ten times faster)")
      ->check(finite_range(0.0001, 1000.0));
  s.app->add_option("--drop-after", s.drop_after, "Hang up after receiving N bytes, as a pulled cable (default: never)")
      ->type_name("N")
      ->check(finite_range(0, 1e12));
  s.app->add_option("--stop-after", s.stop_after,
                    "After receiving N bytes, stop answering and cutting, as a paused or stuck device (default: never)")
      ->type_name("N")
      ->check(finite_range(0, 1e12));
  s.app->add_option("--link", s.link,
                    "Also make PATH a symlink to the port, a fixed name for scripts (--device serial:PATH); an old\n"
                    "link there is replaced, anything else refused; removed on exit")
      ->type_name("PATH");
  s.app->add_option("--report", s.report_path,
                    "When the session ends, write what it received and cut as JSON (popcut.sim-plotter.v2,\n"
                    "docs/formats.md): bytes, overflow, XOFFs, malformed and unknown commands, strokes")
      ->type_name("FILE");
  s.app->add_option("--svg", s.svg_path, "When the session ends, write what it cut as SVG, one colour per pen")->type_name("FILE");
}

std::optional<int> run_sim_plotter_command(const SimPlotterCommand& s) {
  if (s.app && *s.app) return run_sim_plotter(s);
  return std::nullopt;
}

}  // namespace popcut::cli
