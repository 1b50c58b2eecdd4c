// Classification of OS errors into the transport's error classes.
#include "popcut/drivers/transport.h"

#include <cerrno>
#include <cstring>

namespace popcut::drivers {

const char* to_string(TransportError error) {
  switch (error) {
    case TransportError::none: return "none";
    case TransportError::bad_argument: return "bad_argument";
    case TransportError::not_found: return "not_found";
    case TransportError::permission: return "permission";
    case TransportError::busy: return "busy";
    case TransportError::timeout: return "timeout";
    case TransportError::disconnected: return "disconnected";
    case TransportError::unsupported: return "unsupported";
    case TransportError::io: return "io";
  }
  return "io";
}

TransportStatus status_from_errno(int err, const std::string& what) {
  TransportError kind = TransportError::io;
  switch (err) {
    case ENOENT:
    case ENODEV:
    case ENXIO: kind = TransportError::not_found; break;
    case EACCES:
    case EPERM:
    case EROFS: kind = TransportError::permission; break;
    case ETIMEDOUT:
    case EAGAIN: kind = TransportError::timeout; break;
    case EPIPE:
    case EIO:
    case ECONNRESET: kind = TransportError::disconnected; break;
    case EINVAL:
    case EBADF:
    case EISDIR: kind = TransportError::bad_argument; break;
    case EBUSY: kind = TransportError::busy; break;
    default: break;
  }
  return {kind, err, what + ": " + std::strerror(err)};
}

}  // namespace popcut::drivers
