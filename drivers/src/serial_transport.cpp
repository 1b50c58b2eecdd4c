// Serial line through libserialport: framing and flow control (XON/XOFF, RTS/CTS, DTR/DSR) in the OS, an flock per
// port.
//
// Three things libserialport 0.1.1 cannot do are done on its handle directly, and only those:
// - flock: libserialport takes no lock, and two programs interleaving one job would ruin it;
// - clearing IXANY, which it leaves as it found it: with IXANY any byte from the device (a
//   status answer) restarts a transmitter that XOFF stopped, and the buffer overruns;
// - noticing a hang-up (POLLHUP): its blocking read reports a hung-up line as silence.
#include <fcntl.h>
#include <libserialport.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <thread>

#include "backends.h"
#include "popcut/drivers/ports.h"

namespace popcut::drivers {
namespace {

using Clock = std::chrono::steady_clock;
// A device that takes no byte for this long is holding the line (a free line takes a character
// in well under a millisecond at any baud popcut uses, and a write returns at once while the OS
// has room).
constexpr std::chrono::milliseconds kHoldSeen{50};

// The OS error behind libserialport's last SP_ERR_FAIL, as a status.
TransportStatus sp_status(sp_return rc, const std::string& what) {
  if (rc == SP_ERR_FAIL) {
    const int err = sp_last_error_code();
    char* msg = sp_last_error_message();
    TransportStatus st = status_from_errno(err, what);
    if (msg) st.message = what + ": " + msg;
    sp_free_error_message(msg);
    return st;
  }
  if (rc == SP_ERR_SUPP) return {TransportError::unsupported, 0, what + ": not supported by this port or OS"};
  if (rc == SP_ERR_MEM) return {TransportError::io, ENOMEM, what + ": out of memory"};
  return {TransportError::bad_argument, 0, what + ": rejected by libserialport"};
}

class SerialTransport final : public Transport {
 public:
  SerialTransport(DeviceAddress address, const DeviceProfile& profile)
      : address_(std::move(address)), settings_(profile.transport) {
    // Bits on the line per character: start, data, parity, stop.
    const int bits = 1 + settings_.data_bits + (settings_.parity == Parity::none ? 0 : 1) + settings_.stop_bits;
    char_time_ = std::chrono::duration<double>(static_cast<double>(bits) / settings_.baud);
  }
  ~SerialTransport() override { close(); }
  SerialTransport(const SerialTransport&) = delete;
  SerialTransport& operator=(const SerialTransport&) = delete;

  TransportStatus open() override {
    if (port_) return {TransportError::bad_argument, 0, describe() + ": already open"};
    if (TransportStatus st = resolve(); !st.ok()) return st;
    struct stat info {};
    if (::stat(path_.c_str(), &info) != 0) {
      TransportStatus st = status_from_errno(errno, "cannot open serial port " + path_);
      if (st.error == TransportError::not_found) st.message += " (see `popcut devices` for the ports present)";
      return st;
    }
    if (!S_ISCHR(info.st_mode))
      return {TransportError::bad_argument, 0, path_ + " is not a serial port (not a terminal device)"};
    // libserialport 0.1.1 looks a port up in sysfs by its name after /dev/, so the stable names
    // udev makes (/dev/serial/by-id/..., symlinks) are not found: it gets the node they point at.
    std::error_code ec;
    const std::string node = std::filesystem::canonical(path_, ec).string();
    if (sp_get_port_by_name(ec ? path_.c_str() : node.c_str(), &port_) != SP_OK) {
      port_ = nullptr;
      return {TransportError::bad_argument, 0,
              path_ +
                  " is not a serial port (libserialport finds no tty device behind it; a pseudo-terminal needs "
                  "the test shim, see docs/transports.md)"};
    }
    if (const sp_return rc = sp_open(port_, SP_MODE_READ_WRITE); rc != SP_OK) {
      TransportStatus st = sp_status(rc, "cannot open serial port " + path_);
      if (st.error == TransportError::permission) {
        st.message +=
            " (add your user to the group owning it, e.g. `sudo usermod -aG dialout $USER`, then log in again)";
      }
      sp_free_port(port_);
      port_ = nullptr;
      return st;
    }
    open_ = true;
    if (sp_get_port_handle(port_, &fd_) != SP_OK)
      return fail({TransportError::io, 0, "cannot get the handle of " + path_});
    // An advisory lock: a second popcut (or popcutd worker) on the same port is refused, not interleaved.
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      if (err == EWOULDBLOCK) {
        return fail({TransportError::busy, err,
                     "serial port " + path_ + " is busy: another program holds its lock (is a job running?)"});
      }
      return fail(status_from_errno(err, "cannot lock " + path_));
    }
    if (TransportStatus st = configure(); !st.ok()) return fail(st);
    // A pseudo-terminal (Unix98 slaves: majors 136-143) hides its queue from TIOCOUTQ.
    struct stat st {};
    is_pty_ = ::fstat(fd_, &st) == 0 && S_ISCHR(st.st_mode) && major(st.st_rdev) >= 136 && major(st.st_rdev) <= 143;
    sp_flush(port_, SP_BUF_BOTH);  // stale replies from an earlier session are not answers to us
    line_free_at_ = Clock::now();
    return TransportStatus::success();
  }

  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override {
    IoResult r;
    if (!open_) return {0, {TransportError::bad_argument, 0, describe() + ": write before open"}};
    const auto deadline = Clock::now() + timeout;
    if (request_done_) {
      // A new request (not the rest of one a held line cut short): the previous one moves back.
      prev_request_ = cur_request_;
      cur_request_ = 0;
    }
    while (r.bytes < data.size()) {
      if (hung_up()) {
        r.status = lost(EIO, "write to " + path_);
        return r;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
      // Blocks while the OS holds the line (XOFF received, CTS or DSR low): that is flow control.
      // In short waits, so that a hold is seen as such (no byte taken for kHoldSeen).
      const sp_return n =
          sp_blocking_write(port_, data.data() + r.bytes, data.size() - r.bytes,
                            static_cast<unsigned>(std::clamp<long>(left.count(), 1, kHoldSeen.count())));
      if (n < 0) {
        r.status = sp_last_error_code() == EIO || sp_last_error_code() == ENXIO
                       ? lost(sp_last_error_code(), "write to " + path_)
                       : sp_status(n, "write to " + path_);
        return r;
      }
      note_hold(n == 0);
      r.bytes += static_cast<std::size_t>(n);
      cur_request_ += static_cast<std::size_t>(n);
      written_ += static_cast<std::size_t>(n);
      line_free_at_ = std::max(line_free_at_, Clock::now()) +
                      std::chrono::duration_cast<Clock::duration>(char_time_ * static_cast<double>(n));
      if (r.bytes < data.size() && Clock::now() >= deadline) {
        request_done_ = false;
        r.status = {TransportError::timeout, ETIMEDOUT,
                    "cannot write to " + path_ + " within " + std::to_string(timeout.count()) +
                        " ms (the device holds the line: XOFF, or CTS/DSR low)"};
        return r;
      }
    }
    // Return once the OS queue is empty and the line is at most this write's bytes behind, as a
    // UART would be: one chunk stays in flight (the line never idles while popcut prepares the
    // next), and a pseudo-terminal, which would take kilobytes at once, is held to the line rate.
    r.status = wait_line_free(deadline, data.size());
    request_done_ = r.status.ok();
    return r;
  }

  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override {
    IoResult r;
    if (!open_) return {0, {TransportError::bad_argument, 0, describe() + ": read before open"}};
    if (buffer.empty() || timeout.count() == 0) {
      // Only let time pass (or take what is there), noticing a hang-up. With nothing to read
      // into, incoming bytes must not cut the wait short: the caller counts it as time passed.
      pollfd p{fd_, static_cast<short>(buffer.empty() ? 0 : POLLIN), 0};
      const int got = ::poll(&p, 1, static_cast<int>(timeout.count()));
      if (got > 0 && (p.revents & (POLLHUP | POLLERR)) && !(p.revents & POLLIN)) {
        r.status = lost(EIO, "serial port " + path_);
        return r;
      }
      if (buffer.empty()) return r;
      const sp_return n = sp_nonblocking_read(port_, buffer.data(), buffer.size());
      if (n < 0)
        r.status = lost(sp_last_error_code(), "read from " + path_);
      else
        r.bytes = static_cast<std::size_t>(n);
      if (r.bytes == 0 && r.status.ok()) r.status = {TransportError::timeout, ETIMEDOUT, "no reply from " + path_};
      return r;
    }
    if (hung_up()) {
      r.status = lost(EIO, "read from " + path_);
      return r;
    }
    const sp_return n =
        sp_blocking_read_next(port_, buffer.data(), buffer.size(), static_cast<unsigned>(timeout.count()));
    if (n < 0) {
      r.status = lost(sp_last_error_code(), "read from " + path_);
    } else if (n == 0) {
      r.status = hung_up() ? lost(EIO, "read from " + path_)
                           : TransportStatus{TransportError::timeout, ETIMEDOUT,
                                             "no reply from " + path_ + " within the timeout"};
    } else {
      r.bytes = static_cast<std::size_t>(n);
    }
    return r;
  }

  TransportStatus drain(std::chrono::milliseconds timeout) override {
    if (!open_) return {TransportError::bad_argument, 0, describe() + ": drain before open"};
    if (TransportStatus st = wait_line_free(Clock::now() + timeout, 0); !st.ok()) return st;
    // The queue is empty: tcdrain now only waits for the UART's last characters.
    if (const sp_return rc = sp_drain(port_); rc != SP_OK) return lost(sp_last_error_code(), "drain " + path_);
    return TransportStatus::success();
  }

  bool writes_acknowledged() const override { return false; }
  std::size_t in_flight() override {
    if (!open_) return 0;
    const sp_return queued = sp_output_waiting(port_);
    // Besides the OS queue: the last two requests' bytes (a write returns with one of them still
    // on the line, and a UART FIFO, a USB adapter or a pty may hold them), or more if their line
    // time has not passed yet (a pty's buffer is not in the OS queue).
    // And what no one reports: a USB adapter's transmit FIFO or a UART's, the profile's
    // adapter_fifo_bytes. Without device answers the count must stay below what the device got,
    // even if that makes a resume re-cut more: a skipped stroke spoils the card.
    return (queued > 0 ? static_cast<std::size_t>(queued) : 0) +
           std::max(prev_request_ + cur_request_, on_line_by_time()) + settings_.adapter_fifo_bytes;
  }
  std::size_t expected_in_flight() override {
    if (!open_) return 0;
    const sp_return queued = sp_output_waiting(port_);
    // The queue's bytes are among those the line time counts (unless the line was held).
    return std::max(queued > 0 ? static_cast<std::size_t>(queued) : 0, on_line_by_time());
  }

  void close() override {
    if (port_) {
      if (open_) sp_close(port_);
      sp_free_port(port_);
    }
    port_ = nullptr;
    open_ = false;
    fd_ = -1;
  }

  std::string describe() const override { return path_.empty() ? address_.text : "serial:" + path_; }
  std::optional<int> holds() const override { return holds_; }
  void discard_output() override {
    if (open_) sp_flush(port_, SP_BUF_OUTPUT);
  }
  bool backpressure() const override {
    return settings_.flow != FlowControl::none && settings_.flow != FlowControl::esc_b;
  }
  bool os_flow_control() const override { return settings_.flow == FlowControl::xon_xoff; }
  bool holding_line() override {
    if (!open_) return false;
    // A pseudo-terminal under XON/XOFF: what the far end has not read yet waits in the pty, not
    // in a queue popcut can see, so a hold can be neither seen nor ruled out once job bytes have
    // gone (more than a few queries): assume it may be held, as a UART's visible queue would say.
    if (is_pty_ && settings_.flow == FlowControl::xon_xoff) return written_ > kQueriesOnly;
    const sp_return queued = sp_output_waiting(port_);
    return queued > 0 && Clock::now() >= line_free_at_ + kHoldSeen;  // queued past its line time
  }

 private:
  // Bytes written whose line time, at the baud rate, has not yet passed.
  std::size_t on_line_by_time() const {
    const double on_line_s = std::chrono::duration<double>(line_free_at_ - Clock::now()).count();
    return static_cast<std::size_t>(std::max(0.0, std::ceil(on_line_s / char_time_.count())));
  }
  TransportStatus fail(TransportStatus st) {
    close();
    return st;
  }

  TransportStatus configure() {
    const std::string what = "cannot configure " + path_;
    if (const sp_return rc = sp_set_baudrate(port_, settings_.baud); rc != SP_OK) {
      TransportStatus st = sp_status(rc, what);
      st.error = TransportError::unsupported;
      st.message =
          std::to_string(settings_.baud) + " baud is not a rate " + path_ + " can be set to (" + st.message + ")";
      return st;
    }
    if (const sp_return rc = sp_set_bits(port_, settings_.data_bits); rc != SP_OK)
      return sp_status(rc, what + " (data bits)");
    const sp_parity parity = settings_.parity == Parity::none  ? SP_PARITY_NONE
                             : settings_.parity == Parity::odd ? SP_PARITY_ODD
                                                               : SP_PARITY_EVEN;
    if (const sp_return rc = sp_set_parity(port_, parity); rc != SP_OK) return sp_status(rc, what + " (parity)");
    if (const sp_return rc = sp_set_stopbits(port_, settings_.stop_bits); rc != SP_OK)
      return sp_status(rc, what + " (stop bits)");
    sp_flowcontrol flow = SP_FLOWCONTROL_NONE;
    if (settings_.flow == FlowControl::xon_xoff) flow = SP_FLOWCONTROL_XONXOFF;
    if (settings_.flow == FlowControl::rts_cts) flow = SP_FLOWCONTROL_RTSCTS;
    if (settings_.flow == FlowControl::dtr_dsr) flow = SP_FLOWCONTROL_DTRDSR;
    if (const sp_return rc = sp_set_flowcontrol(port_, flow); rc != SP_OK) {
      TransportStatus st = sp_status(rc, what + " (flow control " + to_string(settings_.flow) + ")");
      if (rc == SP_ERR_SUPP) {
        st.message = std::string(to_string(settings_.flow)) + " flow control is not available on " + path_ +
                     " (Linux serial drivers have no DTR/DSR handshake); wire the cutter for RTS/CTS or use xon_xoff";
      }
      return st;
    }
    termios tio{};
    if (::tcgetattr(fd_, &tio) != 0) return status_from_errno(errno, what);
    if (tio.c_iflag & IXANY) {
      tio.c_iflag &= ~static_cast<tcflag_t>(IXANY);
      if (::tcsetattr(fd_, TCSANOW, &tio) != 0) return status_from_errno(errno, what + " (IXANY)");
    }
    return TransportStatus::success();
  }

  // The port's path: given, or the adapter with the USB ids (and serial number) asked for.
  TransportStatus resolve() {
    if (!address_.path.empty()) {
      path_ = address_.path;
      return TransportStatus::success();
    }
    std::vector<SerialPortInfo> ports;
    if (TransportStatus st = list_serial_ports(ports); !st.ok()) return st;
    std::string seen;
    for (const SerialPortInfo& p : ports) {
      if (p.vid)
        seen += (seen.empty() ? "" : ", ") + p.path + " (" + usb_id_string(*p.vid, *p.pid) +
                (p.serial_number.empty() ? "" : ":" + p.serial_number) + ")";
      if (p.vid == address_.vid && p.pid == address_.pid &&
          (address_.serial_number.empty() || p.serial_number == address_.serial_number)) {
        path_ = p.path;
        return TransportStatus::success();
      }
    }
    return {TransportError::not_found, 0,
            "no serial port belongs to USB " + usb_id_string(*address_.vid, *address_.pid) +
                (address_.serial_number.empty() ? "" : " with serial number " + address_.serial_number) +
                "; USB serial ports present: " + (seen.empty() ? "none" : seen)};
  }

  bool hung_up() const {
    pollfd p{fd_, POLLIN, 0};
    return ::poll(&p, 1, 0) > 0 && (p.revents & POLLHUP);
  }

  TransportStatus lost(int err, const std::string& what) const {
    TransportStatus st = status_from_errno(err == 0 ? EIO : err, what);
    if (err == 0 || err == EIO || err == ENXIO || err == ENODEV) {
      st.error = TransportError::disconnected;
      st.message += " (the cable was unplugged, the adapter reset or the device hung up)";
    }
    return st;
  }

  // A hold starts when the device stops taking bytes and ends when it takes one again: counted
  // once however long it lasts.
  void note_hold(bool held) {
    if (held && !holding_) ++holds_;
    holding_ = held;
  }

  // Until the OS output queue is empty and the line time of what was written has passed, but
  // for `behind_bytes` of it.
  TransportStatus wait_line_free(Clock::time_point deadline, std::size_t behind_bytes) {
    const auto target =
        line_free_at_ - std::chrono::duration_cast<Clock::duration>(char_time_ * static_cast<double>(behind_bytes));
    for (;;) {
      const sp_return queued = sp_output_waiting(port_);
      const auto now = Clock::now();
      // Bytes still queued well after the line could have carried them: the OS has stopped the
      // transmitter for the device (the kernel drains a free line whatever popcut's scheduling).
      if (queued > 0 && now >= line_free_at_ + kHoldSeen) note_hold(true);
      if (queued <= 0 && now >= target) return TransportStatus::success();
      if (hung_up()) return lost(EIO, "serial port " + path_);
      if (now >= deadline) {
        return {TransportError::timeout, ETIMEDOUT,
                path_ + ": " + std::to_string(queued) +
                    " bytes still queued for the line (the device holds it: XOFF, or CTS/DSR low)"};
      }
      const auto until = queued > 0 ? now + std::chrono::milliseconds(2) : std::min(target, deadline);
      std::this_thread::sleep_until(std::min(until, deadline));
    }
  }

  DeviceAddress address_;
  TransportDefaults settings_;
  std::chrono::duration<double> char_time_{};
  std::string path_;
  sp_port* port_ = nullptr;
  bool open_ = false;
  int fd_ = -1;
  // Bytes moved by the current write request (possibly over several calls while the line is
  // held) and by the one before: what may still be between popcut and the device.
  std::size_t cur_request_ = 0, prev_request_ = 0;
  bool request_done_ = true;
  Clock::time_point line_free_at_{};
  int holds_ = 0;
  bool holding_ = false;
  bool is_pty_ = false;
  std::size_t written_ = 0;  // since open
  // Status queries before a job (ESC.O, ESC.E) write a few bytes: no job byte to hold yet.
  static constexpr std::size_t kQueriesOnly = 16;
};

}  // namespace

std::unique_ptr<Transport> make_serial_transport(const DeviceAddress& address, const DeviceProfile& profile,
                                                 TransportStatus& status) {
  status = TransportStatus::success();
  return std::make_unique<SerialTransport>(address, profile);
}

}  // namespace popcut::drivers
