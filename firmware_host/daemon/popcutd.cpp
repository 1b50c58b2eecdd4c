// popcutd startup: read and check the config, recover the queue, serve HTTP, stop cleanly on SIGTERM.
#include "popcutd.h"

#include <sys/socket.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <pthread.h>
#include <thread>

#include "config.h"
#include "daemon.h"
#include "http_api.h"
#include "http_server.h"
#include "log.h"
#include "popcut/error.h"

namespace popcut::daemon {

namespace {

struct CommandLine {
  std::string config_path, data_dir;
  int port = -1;  // -1: [server] port
};

void usage(std::ostream& o) {
  o << "Usage: popcutd --config FILE [--data-dir DIR] [--port N]\n"
       "popcutd — the popcut job queue, HTTP API and kiosk page for one or more cutters (docs/api.md).\n"
       "  --config FILE   the configuration (e.g. configs/popcutd.toml); required\n"
       "  --data-dir DIR  overrides [server] data_dir\n"
       "  --port N        overrides [server] port; 0 picks a free port, printed on standard output\n"
       "Exit codes: 0 stopped by SIGTERM or SIGINT, 2 bad command line or configuration, 3 cannot listen or\n"
       "open the data directory, 4 internal error.\n";
}

// Three options: parsed by hand (CLI11's inlined splitting trips GCC 12's -Wnull-dereference here).
// Returns the exit code when the command line is all there is to do (--help, a mistake).
std::optional<int> parse_command_line(int argc, char** argv, CommandLine& cl) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage(std::cout);
      return 0;
    }
    const bool has_value = i + 1 < argc;
    if ((a == "--config" || a == "--data-dir" || a == "--port") && !has_value) {
      std::cerr << "popcutd: error: " << a << " needs a value\nRun 'popcutd --help' for usage.\n";
      return 2;
    }
    if (a == "--config") {
      cl.config_path = argv[++i];
    } else if (a == "--data-dir") {
      cl.data_dir = argv[++i];
    } else if (a == "--port") {
      const std::string v = argv[++i];
      if (v.empty() || v.size() > 5 || v.find_first_not_of("0123456789") != std::string::npos || std::stoi(v) > 65535) {
        std::cerr << "popcutd: error: --port " << v << ": expected 0 to 65535\n";
        return 2;
      }
      cl.port = std::stoi(v);
    } else {
      std::cerr << "popcutd: error: unknown argument '" << a << "'\nRun 'popcutd --help' for usage.\n";
      return 2;
    }
  }
  if (cl.config_path.empty()) {
    std::cerr << "popcutd: error: --config FILE is required\nRun 'popcutd --help' for usage.\n";
    return 2;
  }
  return std::nullopt;
}

// SIGTERM and SIGINT are taken by one thread with sigwait: every other thread blocks them.
sigset_t block_stop_signals() {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  std::signal(SIGPIPE, SIG_IGN);  // a client that hangs up is an error on its socket, not our death
  return stop_signals;
}

void configure_server(HttpServer& server, const DaemonConfig& config) {
  server.new_task_queue = [n = config.http_threads] { return new httplib::ThreadPool(static_cast<std::size_t>(n)); };
  // Small JSON answers: without TCP_NODELAY, Nagle and delayed ACKs add ~40 ms to each.
  server.set_tcp_nodelay(true);
  // SO_REUSEADDR only: httplib's default also sets SO_REUSEPORT, which lets a second popcutd bind
  // the same port and take half of the requests.
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
}

void report_listen_failure(const DaemonConfig& config, int why) {
  std::cerr << "popcutd: error: cannot listen on " << config.listen << ":" << config.port
            << (why ? std::string(": ") + std::strerror(why)
                    : std::string(": the host name does not resolve to an address of this machine"))
            << (why == EADDRINUSE ? " (another popcutd or program has the port; [server] port sets another)" : "")
            << (why == EADDRNOTAVAIL ? " (no interface of this machine has that address; [server] listen)" : "")
            << "\n";
}

void report_listening(const DaemonConfig& config, int bound) {
  // One line for scripts and tests that asked for port 0.
  // An IPv6 address goes in brackets in a URL (RFC 3986): http://[::1]:8742.
  const bool v6 = config.listen.find(':') != std::string::npos;
  std::cout << "popcutd: listening on http://" << (v6 ? "[" + config.listen + "]" : config.listen) << ":" << bound
            << std::endl;
  log_line("data in ", config.data_dir, "; ", config.devices.size(), " devices");
  // The kernel takes a larger backlog silently as its cap: say so, since bursts beyond it wait 1 s.
  if (std::ifstream cap_file("/proc/sys/net/core/somaxconn"); cap_file) {
    int cap = 0;
    if (cap_file >> cap && cap < config.listen_backlog) {
      log_line("[server] listen_backlog ", config.listen_backlog, " is capped at ", cap,
               " by net.core.somaxconn (sysctl)");
    }
  }
}

// Serves until SIGTERM or SIGINT; the exit code.
int serve(const DaemonConfig& config, Daemon& daemon, sigset_t stop_signals) {
  HttpServer server(ConnectionLimits{config.header_timeout_s, config.keep_alive_timeout_s, 5, config.listen_backlog});
  configure_server(server, config);
  HttpApi api(server, daemon);
  errno = 0;  // httplib returns only false; the failed bind()'s errno says why (in use, not here)
  const int bound = server.bind_and_listen(config.listen, config.port);
  if (bound <= 0) {
    report_listen_failure(config, errno);
    daemon.shutdown();
    return 3;
  }
  report_listening(config, bound);
  std::thread signals([&] {
    int sig = 0;
    sigwait(&stop_signals, &sig);
    log_line("signal ", sig, ": stopping the cuts safely and exiting");
    server.stop();
  });
  const bool ok = server.listen_after_bind();
  // listen_after_bind only returns once stopped; on failure wake the signal thread ourselves.
  if (!ok) pthread_kill(signals.native_handle(), SIGTERM);
  signals.join();
  daemon.shutdown();
  log_line("stopped");
  return ok ? 0 : 3;
}

}  // namespace

int run_popcutd(int argc, char** argv) {
  CommandLine cl;
  if (const std::optional<int> done = parse_command_line(argc, argv, cl)) return *done;
  DaemonConfig config;
  try {
    config = load_daemon_config(cl.config_path);
  } catch (const Error& e) {
    std::cerr << "popcutd: error: " << e.what() << "\n";
    return 2;
  }
  if (!cl.data_dir.empty()) config.data_dir = cl.data_dir;
  if (cl.port >= 0) config.port = cl.port;

  const sigset_t stop_signals = block_stop_signals();
  std::unique_ptr<Daemon> daemon;
  try {
    daemon = std::make_unique<Daemon>(config);
  } catch (const Error& e) {
    std::cerr << "popcutd: error: " << e.what() << "\n";
    return 3;
  }
  if (const auto r = daemon->recovered(); r.interrupted + r.requeued > 0) {
    log_line("recovered after an unclean stop: ", r.interrupted, " cutting -> interrupted (resume when asked), ",
             r.requeued, " planning -> queued (planned again)");
  }
  return serve(config, *daemon, stop_signals);
}

}  // namespace popcut::daemon
