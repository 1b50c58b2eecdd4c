// Errors that cross popcut_core's boundary: what went wrong and where in the input, for a user to act on.
#pragma once

#include <stdexcept>
#include <string>

#include "popcut/names.h"

namespace popcut {

// Stable catalogue: the CLI maps these to exit codes and the daemon to API error codes.
enum class ErrorCode {
  invalid_input,  // the input is malformed or violates a documented rule
  limit,          // the input exceeds a documented size limit
  io,             // a file could not be read or written
  internal,       // a broken invariant inside popcut: a bug, never the user's fault
};
inline constexpr auto kErrorCodeNames = enum_names<ErrorCode>({{ErrorCode::invalid_input, "invalid_input"},
                                                               {ErrorCode::limit, "limit"},
                                                               {ErrorCode::io, "io"},
                                                               {ErrorCode::internal, "internal"}});

const char* to_string(ErrorCode code);

class Error : public std::runtime_error {
 public:
  // source: file path or "<input>"; location: "line 3, column 7" or a field path like
  // "heights[2][1]" (may be empty); message: what is wrong and what was expected.
  Error(ErrorCode code, std::string source, std::string location, std::string message);

  ErrorCode code() const { return code_; }
  const std::string& source() const { return source_; }
  const std::string& location() const { return location_; }
  const std::string& message() const { return message_; }

 private:
  ErrorCode code_;
  std::string source_;
  std::string location_;
  std::string message_;
};

}  // namespace popcut
