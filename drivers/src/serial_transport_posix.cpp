// Serial line on POSIX: termios framing and hardware flow, an flock so two programs never share a port,
// and writes paced to the line rate. Ports given by USB ids are found through libserialport.
//
// Why termios and not libserialport's sp_open: libserialport 0.1.1 (Debian 12) refuses every
// pseudo-terminal (no /sys/class/tty entry; TIOCMGET fails), which rules out socat/ser2net ptys
// and the simulated plotter; the line code here is the same for a pty and a /dev/ttyUSB0.
#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <thread>

#include "backends.h"
#include "popcut/drivers/ports.h"
#include "popcut/drivers/posix_baud.h"

namespace popcut::drivers {
namespace {

using Clock = std::chrono::steady_clock;

class SerialTransport final : public Transport {
 public:
  SerialTransport(DeviceAddress address, const DeviceProfile& profile)
      : address_(std::move(address)), settings_(profile.transport), hold_(profile.transport.hold_timeout_ms) {
    // Bits on the line per character: start, data, parity, stop.
    const int bits = 1 + settings_.data_bits + (settings_.parity == Parity::none ? 0 : 1) + settings_.stop_bits;
    char_time_ = std::chrono::duration<double>(static_cast<double>(bits) / settings_.baud);
  }
  ~SerialTransport() override { close(); }
  SerialTransport(const SerialTransport&) = delete;
  SerialTransport& operator=(const SerialTransport&) = delete;

  TransportStatus open() override {
    if (fd_ >= 0) return {TransportError::bad_argument, 0, describe() + ": already open"};
    if (TransportStatus st = resolve(); !st.ok()) return st;
    fd_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) {
      const int err = errno;
      TransportStatus st = status_from_errno(err, "cannot open serial port " + path_);
      if (st.error == TransportError::permission) {
        st.message += " (add your user to the group owning it, e.g. `sudo usermod -aG dialout $USER`, then log in again)";
      } else if (st.error == TransportError::not_found) {
        st.message += " (see `popcut devices` for the ports present)";
      }
      return st;
    }
    if (!::isatty(fd_)) return fail({TransportError::bad_argument, 0, path_ + " is not a serial port (not a terminal device)"});
    // An advisory lock: a second popcut (or popcutd worker) on the same port is refused, not interleaved.
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      if (err == EWOULDBLOCK) {
        return fail({TransportError::busy, err, "serial port " + path_ + " is busy: another program holds its lock (is a job running?)"});
      }
      return fail(status_from_errno(err, "cannot lock " + path_));
    }
    termios tio{};
    if (::tcgetattr(fd_, &tio) != 0) return fail(status_from_errno(errno, "cannot read the settings of " + path_));
    ::cfmakeraw(&tio);
    const std::optional<speed_t> speed = speed_of_baud(settings_.baud);
    if (!speed) {
      return fail({TransportError::unsupported, 0, std::to_string(settings_.baud) + " baud is not a standard rate this port can be set to"});
    }
    ::cfsetispeed(&tio, *speed);
    ::cfsetospeed(&tio, *speed);
    tio.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | PARODD | CSTOPB | CRTSCTS);
    static const tcflag_t kSize[] = {CS5, CS6, CS7, CS8};
    tio.c_cflag |= kSize[settings_.data_bits - 5] | CLOCAL | CREAD;
    if (settings_.parity != Parity::none) tio.c_cflag |= PARENB | (settings_.parity == Parity::odd ? PARODD : 0);
    if (settings_.stop_bits == 2) tio.c_cflag |= CSTOPB;
    if (settings_.flow == FlowControl::rts_cts) tio.c_cflag |= CRTSCTS;
    if (settings_.flow == FlowControl::dtr_dsr) {
      return fail({TransportError::unsupported, 0, "DTR/DSR flow control is not available from Linux serial drivers; "
                                                   "wire the cutter for RTS/CTS or use xon_xoff"});
    }
    // XON/XOFF stays off in the kernel: popcut reads them itself so that a device holding the
    // line for too long becomes a timeout it can report, not a write blocked forever.
    tio.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
    tio.c_cc[VMIN] = 0;
    tio.c_cc[VTIME] = 0;
    if (::tcsetattr(fd_, TCSANOW, &tio) != 0) return fail(status_from_errno(errno, "cannot configure " + path_));
    ::tcflush(fd_, TCIOFLUSH);  // stale replies from an earlier session are not answers to us
    line_free_at_ = Clock::now();
    return TransportStatus::success();
  }

  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override {
    IoResult r;
    if (fd_ < 0) return {0, {TransportError::bad_argument, 0, describe() + ": write before open"}};
    // Under RTS/CTS the device holds the line for as long as it cuts a full buffer.
    const auto deadline = Clock::now() + (settings_.flow == FlowControl::rts_cts ? std::max(timeout, hold_) : timeout);
    while (r.bytes < data.size()) {
      const ssize_t n = ::write(fd_, data.data() + r.bytes, data.size() - r.bytes);
      if (n > 0) {
        r.bytes += static_cast<std::size_t>(n);
        line_free_at_ = std::max(line_free_at_, Clock::now()) +
                        std::chrono::duration_cast<Clock::duration>(char_time_ * static_cast<double>(n));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && errno != EAGAIN) {
        r.status = lost(errno, "write to " + path_);
        return r;
      }
      if (!wait_for(POLLOUT, deadline, r.status)) return r;
    }
    // Return once the bytes are on the wire, as a UART would have sent them: what popcut counts
    // as sent has left, and XOFF finds at most one chunk in flight (the kernel queue and a
    // pseudo-terminal would otherwise swallow kilobytes before the device could object).
    r.status = wait_line_free(deadline);
    return r;
  }

  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override {
    IoResult r;
    if (fd_ < 0) return {0, {TransportError::bad_argument, 0, describe() + ": read before open"}};
    const auto deadline = Clock::now() + timeout;
    if (buffer.empty()) {
      // Only let time pass, noticing a hang-up.
      pollfd p{fd_, 0, 0};
      if (::poll(&p, 1, static_cast<int>(timeout.count())) > 0 && (p.revents & (POLLHUP | POLLERR))) {
        r.status = lost(EIO, "serial port " + path_);
      }
      return r;
    }
    for (;;) {
      const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
      if (n > 0) {
        r.bytes = static_cast<std::size_t>(n);
        return r;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && errno != EAGAIN) {
        r.status = lost(errno, "read from " + path_);
        return r;
      }
      if (n == 0 && hung_up()) {
        r.status = lost(EIO, "read from " + path_);
        return r;
      }
      if (!wait_for(POLLIN, deadline, r.status)) return r;
    }
  }

  TransportStatus drain(std::chrono::milliseconds timeout) override {
    if (fd_ < 0) return {TransportError::bad_argument, 0, describe() + ": drain before open"};
    return wait_line_free(Clock::now() + timeout);
  }

  void close() override {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

  std::string describe() const override { return path_.empty() ? address_.text : "serial:" + path_; }
  bool backpressure() const override { return settings_.flow != FlowControl::none; }

 private:
  TransportStatus fail(TransportStatus st) {
    close();
    return st;
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
      if (p.vid) seen += (seen.empty() ? "" : ", ") + p.path + " (" + usb_id_string(*p.vid, *p.pid) +
                         (p.serial_number.empty() ? "" : ":" + p.serial_number) + ")";
      if (p.vid == address_.vid && p.pid == address_.pid &&
          (address_.serial_number.empty() || p.serial_number == address_.serial_number)) {
        path_ = p.path;
        return TransportStatus::success();
      }
    }
    return {TransportError::not_found, 0, "no serial port belongs to USB " + usb_id_string(*address_.vid, *address_.pid) +
                                              (address_.serial_number.empty() ? "" : " with serial number " + address_.serial_number) +
                                              "; USB serial ports present: " + (seen.empty() ? "none" : seen)};
  }

  bool hung_up() const {
    pollfd p{fd_, POLLIN, 0};
    return ::poll(&p, 1, 0) > 0 && (p.revents & POLLHUP);
  }

  TransportStatus lost(int err, const std::string& what) const {
    TransportStatus st = status_from_errno(err, what);
    if (err == EIO || err == ENXIO || err == ENODEV) {
      st.error = TransportError::disconnected;
      st.message += " (the cable was unplugged, the adapter reset or the device hung up)";
    }
    return st;
  }

  // Waits for `events` until the deadline; false with `status` set on timeout or hang-up.
  bool wait_for(short events, Clock::time_point deadline, TransportStatus& status) const {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
    pollfd p{fd_, events, 0};
    const int got = left.count() > 0 ? ::poll(&p, 1, static_cast<int>(left.count())) : 0;
    if (got < 0 && errno == EINTR) return true;
    if (got > 0 && (p.revents & (POLLHUP | POLLERR)) && !(p.revents & events)) {
      status = lost(EIO, "serial port " + path_);
      return false;
    }
    if (got <= 0) {
      status = {TransportError::timeout, ETIMEDOUT,
                std::string(events == POLLIN ? "no reply from " : "cannot write to ") + path_ + " within the timeout"};
      return false;
    }
    return true;
  }

  // Until the kernel's output queue is empty and the line time of what was written has passed.
  TransportStatus wait_line_free(Clock::time_point deadline) {
    for (;;) {
      int queued = 0;
      if (::ioctl(fd_, TIOCOUTQ, &queued) != 0) queued = 0;
      const auto now = Clock::now();
      if (queued <= 0 && now >= line_free_at_) return TransportStatus::success();
      if (hung_up()) return lost(EIO, "serial port " + path_);
      if (now >= deadline) {
        return {TransportError::timeout, ETIMEDOUT, path_ + ": " + std::to_string(queued) +
                                                        " bytes still queued for the line (hardware flow held?)"};
      }
      const auto until = queued > 0 ? now + std::chrono::milliseconds(2) : std::min(line_free_at_, deadline);
      std::this_thread::sleep_until(std::min(until, deadline));
    }
  }

  DeviceAddress address_;
  TransportDefaults settings_;
  std::chrono::milliseconds hold_;
  std::chrono::duration<double> char_time_{};
  std::string path_;
  int fd_ = -1;
  Clock::time_point line_free_at_{};
};

}  // namespace

std::unique_ptr<Transport> make_serial_transport(const DeviceAddress& address, const DeviceProfile& profile, TransportStatus& status) {
  status = TransportStatus::success();
  return std::make_unique<SerialTransport>(address, profile);
}

}  // namespace popcut::drivers
