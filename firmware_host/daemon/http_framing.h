// How a request's body is framed (RFC 7230 3.3), judged from its request line and headers alone.
#pragma once

#include <httplib.h>

#include <cstdint>
#include <optional>
#include <string>

#include "job.h"

namespace popcut::daemon {

// ASCII case-insensitive equality, as HTTP compares schemes and codings.
bool iequals(const std::string& a, const std::string& b);

// Whether the client says a body follows (any Transfer-Encoding, or a Content-Length but "0"):
// a refused request whose body is left unread closes its connection.
bool declares_body(const httplib::Request& req);

// A request's body framing: one length, or chunked alone; anything else could be read two ways.
struct BodyFraming {
  bool chunked = false;
  std::optional<std::uint64_t> length;  // Content-Length, when sent
  // Why the request is refused before its body is read; nullopt when its framing is sound.
  std::optional<ApiError> refusal;
  std::string message;
};

// Transfer-Encoding, Content-Encoding and Content-Length checked, then what the method asks:
// no body for anything but POST, and a POST framed so its end is known.
BodyFraming read_framing(const httplib::Request& req);

}  // namespace popcut::daemon
