// Formats popcut::Error so every message reads "source: location: message".
#include "popcut/error.h"

namespace popcut {
namespace {
std::string compose(const std::string& source, const std::string& location, const std::string& message) {
  std::string s = source.empty() ? std::string("<input>") : source;
  if (!location.empty()) s += ": " + location;
  return s + ": " + message;
}
}  // namespace

const char* to_string(ErrorCode code) {
  // A value outside the enum (a cast gone wrong) is itself a broken invariant.
  const std::string_view name = kErrorCodeNames.name(code);
  return name.empty() ? "internal" : name.data();
}

Error::Error(ErrorCode code, std::string source, std::string location, std::string message)
    : std::runtime_error(compose(source, location, message)),
      code_(code),
      source_(std::move(source)),
      location_(std::move(location)),
      message_(std::move(message)) {}

}  // namespace popcut
