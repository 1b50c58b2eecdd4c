// File transport: poll-bounded writes to a path, fsync as drain.
#include "popcut/drivers/file_transport.h"

#include <cerrno>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

namespace popcut::drivers {

FileTransport::~FileTransport() { close(); }

TransportStatus FileTransport::open() {
  if (fd_ >= 0) return {TransportError::bad_argument, 0, describe() + ": already open"};
  if (path_.empty()) return {TransportError::bad_argument, 0, "file transport needs a path (file:PATH)"};
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NONBLOCK | O_CLOEXEC, 0666);
  if (fd_ < 0) return status_from_errno(errno, "cannot open " + path_);
  return TransportStatus::success();
}

IoResult FileTransport::write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) {
  IoResult r;
  if (fd_ < 0) {
    r.status = {TransportError::bad_argument, 0, describe() + ": write before open"};
    return r;
  }
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (r.bytes < data.size()) {
    const ssize_t n = ::write(fd_, data.data() + r.bytes, data.size() - r.bytes);
    if (n > 0) {
      r.bytes += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno != EAGAIN) {
      r.status = status_from_errno(errno, "write to " + path_);
      return r;
    }
    // A device node may be full for a while (a printer port): wait, but not past the deadline.
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    pollfd p{fd_, POLLOUT, 0};
    if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) == 0) {
      r.status = {TransportError::timeout, ETIMEDOUT, "write to " + path_ + " timed out"};
      return r;
    }
  }
  return r;
}

IoResult FileTransport::read(std::span<std::uint8_t>, std::chrono::milliseconds) {
  return {0, {TransportError::unsupported, 0, describe() + " cannot answer queries"}};
}

TransportStatus FileTransport::drain(std::chrono::milliseconds) {
  if (fd_ < 0) return {TransportError::bad_argument, 0, describe() + ": drain before open"};
  // Character devices (printer ports) do not support fsync; everything is already handed over.
  if (::fsync(fd_) != 0 && errno != EINVAL && errno != EROFS) return status_from_errno(errno, "flush " + path_);
  return TransportStatus::success();
}

void FileTransport::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace popcut::drivers
