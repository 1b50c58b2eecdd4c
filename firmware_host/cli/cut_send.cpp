// popcut cut's send on a terminal: a progress bar, and Ctrl-C or SIGTERM as a safe cancel.
#include "cli/cut_send.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <string>

namespace popcut::cli {
namespace {

// A one-line bar on a terminal: bytes, strokes, ETA; nothing when stderr is a file or pipe.
class Progress {
 public:
  explicit Progress(bool on) : on_(on && ::isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()) {}
  void operator()(const drivers::SendProgress& p) {
    if (!on_ || p.bytes_total == 0) return;
    const int pct = static_cast<int>(p.bytes_sent * 100 / p.bytes_total);
    const auto now = std::chrono::steady_clock::now();
    if (pct == last_ && now - shown_ < std::chrono::milliseconds(500)) return;
    last_ = pct;
    shown_ = now;
    const int filled = pct * 30 / 100;
    const double elapsed_s = std::chrono::duration<double>(now - start_).count();
    std::string eta = "--";
    if (p.bytes_sent > 0 && elapsed_s > 1) {
      const double left_s =
          elapsed_s * static_cast<double>(p.bytes_total - p.bytes_sent) / static_cast<double>(p.bytes_sent);
      const long s = static_cast<long>(left_s + 0.5);
      eta = std::to_string(s / 60) + ":" + (s % 60 < 10 ? "0" : "") + std::to_string(s % 60);
    }
    std::cerr << "\rcutting [" << std::string(static_cast<std::size_t>(filled), '#')
              << std::string(static_cast<std::size_t>(30 - filled), '.') << "] " << pct << "% " << p.bytes_sent << "/"
              << p.bytes_total << " bytes, stroke " << p.last_stroke_written << "/" << p.total_strokes
              << " written, ETA " << eta << "   " << std::flush;
  }
  void done() {
    if (on_ && last_ >= 0) std::cerr << "\n";
    last_ = -1;
  }

 private:
  bool on_;
  int last_ = -1;
  std::chrono::steady_clock::time_point start_, shown_{};
};

// Ctrl-C asks the sender to stop safely. A second one never kills popcut between a PD and the
// abort that lifts the knife: it is absorbed, unless popcut has said it is waiting for a device
// that holds the line to take that abort (g_waiting); then it gives up the wait (give_up).
std::atomic<bool> g_cancel{false};
std::atomic<bool> g_waiting{false};
std::atomic<bool> g_give_up{false};

extern "C" void on_interrupt(int) {
  if (!g_cancel.exchange(true)) {
    static const char msg[] = "\npopcut: cancelling: finishing the command in flight, then lifting the knife\n";
    (void)!::write(STDERR_FILENO, msg, sizeof msg - 1);
  } else if (g_waiting.load()) {
    if (!g_give_up.exchange(true)) {
      static const char msg[] = "\npopcut: giving up on the abort: nothing more is sent to the device\n";
      (void)!::write(STDERR_FILENO, msg, sizeof msg - 1);
    }
  } else {
    static const char msg[] = "\npopcut: already cancelling; the knife is being lifted, please wait\n";
    (void)!::write(STDERR_FILENO, msg, sizeof msg - 1);
  }
}

// Installs on_interrupt for SIGINT and SIGTERM for its lifetime.
class InterruptGuard {
 public:
  InterruptGuard() {
    g_cancel = false;
    g_waiting = false;
    g_give_up = false;
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    ::sigaction(SIGINT, &sa, &old_int_);
    ::sigaction(SIGTERM, &sa, &old_term_);
  }
  ~InterruptGuard() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

 private:
  struct sigaction old_int_ {
  }, old_term_{};
};

}  // namespace

drivers::SendResult send_with_interrupts(drivers::CutSession& session, const EncodedJob& job,
                                         const drivers::DeviceProfile& profile, bool progress_bar) {
  Progress progress(progress_bar);
  drivers::CutControl control;
  control.progress = [&](const drivers::SendProgress& p) { progress(p); };
  control.cancel = &g_cancel;
  control.give_up = &g_give_up;
  control.waiting_to_cancel = [&] {
    g_waiting = true;
    progress.done();
    std::cerr << "popcut: the device holds the line (XOFF or CTS): waiting up to "
              << profile.transport.hold_timeout_ms / 1000
              << " s (hold_timeout_ms) for it to take the abort sequence and the knife-up; Ctrl-C (or SIGTERM) again "
                 "gives up, and the "
                 "device may then cut everything its buffer holds\n";
  };
  drivers::SendResult sent;
  {
    InterruptGuard guard;
    sent = session.send(job, control);
  }
  progress.done();
  return sent;
}

}  // namespace popcut::cli
