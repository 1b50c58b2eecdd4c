// The one seam between popcut and a cutter: a byte transport with timeouts and honest byte counts.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace popcut::drivers {

// Error classes a user can act on; os_error keeps errno (or the library's code) for the log.
// busy: another program holds the port (a lock or an exclusive open).
enum class TransportError { none, bad_argument, not_found, permission, busy, timeout, disconnected, unsupported, io };
const char* to_string(TransportError error);

struct TransportStatus {
  TransportError error = TransportError::none;
  int os_error = 0;
  std::string message;
  bool ok() const { return error == TransportError::none; }
  static TransportStatus success() { return {}; }
};

// Byte counts are reported apart from status: a write may move some bytes and then fail.
struct IoResult {
  std::size_t bytes = 0;
  TransportStatus status;
};

class Transport {
 public:
  virtual ~Transport() = default;
  virtual TransportStatus open() = 0;
  virtual IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) = 0;
  virtual IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) = 0;
  // Blocks until everything written has left popcut's side (for a file: reached the disk).
  virtual TransportStatus drain(std::chrono::milliseconds timeout) = 0;
  virtual void close() = 0;
  virtual std::string describe() const = 0;
  // Whether the far end can talk back (XON/XOFF, ESC.B answers); a file or printer node cannot.
  virtual bool answers() const { return true; }
  // Whether the far end holds popcut off by itself when full (line flow control, USB NAKs, a
  // blocking printer node); when not, the sender paces by the job's estimated motion time.
  virtual bool backpressure() const { return true; }
  // Whether the OS applies XON/XOFF itself (a tty with IXON): writes then block while the device
  // holds the line and popcut never reads XON/XOFF; otherwise popcut honours them (the simulator).
  virtual bool os_flow_control() const { return false; }
  // Whether a write's byte count is what the device took (USB bulk actual_length, a file, the
  // simulator); a serial port's is only what the OS took.
  virtual bool writes_acknowledged() const { return true; }
  // Where writes are not acknowledged: bytes write() accepted that the device cannot yet be shown
  // to have received (the OS output queue, and data a UART, an adapter or a pty may still hold).
  virtual std::size_t in_flight() { return 0; }
  // The best guess (not a bound) of how many of those are still on their way by now: the OS queue
  // and what the line's baud rate cannot have carried yet, without in_flight()'s allowance for
  // buffers no one reports. Time pacing uses it: the device cannot work on bytes not yet there.
  virtual std::size_t expected_in_flight() { return in_flight(); }
  // Where the OS applies the device's flow control (a serial port: XOFF, CTS or DSR), popcut
  // never sees the XOFF byte: the transport counts the holds it observes (a write that moves no
  // byte for a while, a queue that stops draining past its line time), once per hold. nullopt:
  // the transport does not watch, and the sender counts write slices that made no progress.
  virtual std::optional<int> holds() const { return std::nullopt; }
  // Whether the device holds the line right now (XOFF or CTS in the OS: written bytes queued and
  // not moving). A status query behind them has not reached the device, so no answer is no sign
  // that it stopped. False where that cannot be seen (a pseudo-terminal's queue reads empty).
  virtual bool holding_line() { return false; }
  // Drops what was written and still waits in popcut's side of the line (a serial port's OS
  // queue), when a cancel gives up on a device that holds the line: nothing stale reaches it
  // later, and closing the port does not wait for it.
  virtual void discard_output() {}
  // The clock the far end works by: real time, or a simulator's virtual time (which waiting on
  // the transport, a read with a timeout, moves on).
  virtual std::chrono::steady_clock::time_point now() const { return std::chrono::steady_clock::now(); }
};

// Builds a status from an errno value, classifying it.
TransportStatus status_from_errno(int err, const std::string& what);

}  // namespace popcut::drivers
