// Request body framing checks (RFC 7230 3.3): only what httplib reads one way and popcutd too.
#include "http_framing.h"

#include <algorithm>
#include <cctype>

namespace popcut::daemon {
namespace {

BodyFraming refused(ApiError code, std::string message) {
  BodyFraming f;
  f.refusal = code;
  f.message = std::move(message);
  return f;
}

// httplib (built with zlib and brotli) decodes gzip, deflate and br, spelt in lower case, and
// passes any other coding through as if it were none: the compressed bytes would be read as the
// body (a "GZIP" body was refused as bad_json).
std::optional<std::string> coding_problem(const httplib::Request& req) {
  if (!req.has_header("Content-Encoding")) return std::nullopt;
  const std::string coding = req.get_header_value("Content-Encoding");
  if (req.get_header_value_count("Content-Encoding") > 1 ||
      !(iequals(coding, "identity") || coding == "gzip" || coding == "deflate" || coding == "br")) {
    return "Content-Encoding: only gzip, deflate or br (in lower case) or identity is understood, not '" +
           coding.substr(0, 40) + "'";
  }
  return std::nullopt;
}

// Every Content-Length header a number, and all of them the same one.
BodyFraming read_length(const httplib::Request& req) {
  BodyFraming f;
  std::string length;
  for (std::size_t i = 0; i < req.get_header_value_count("Content-Length"); ++i) {
    const std::string v = req.get_header_value("Content-Length", i);
    if (v.empty() || v.size() > 18 || v.find_first_not_of("0123456789") != std::string::npos) {
      return refused(ApiError::bad_request, "Content-Length must be a number of bytes, not '" + v.substr(0, 40) + "'");
    }
    if (i > 0 && v != length)
      return refused(ApiError::bad_request, "two different Content-Length headers (" + length + " and " + v + ")");
    length = v;
  }
  if (!length.empty()) f.length = std::stoull(length);
  return f;
}

}  // namespace

bool iequals(const std::string& a, const std::string& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

bool declares_body(const httplib::Request& req) {
  const std::string declared = req.get_header_value("Content-Length");
  return req.has_header("Transfer-Encoding") || !(declared.empty() || declared == "0");
}

BodyFraming read_framing(const httplib::Request& req) {
  const bool chunked = req.has_header("Transfer-Encoding");
  if (chunked && (req.get_header_value_count("Transfer-Encoding") > 1 ||
                  !iequals(req.get_header_value("Transfer-Encoding"), "chunked"))) {
    return refused(ApiError::bad_request, "Transfer-Encoding: only 'chunked' is understood");
  }
  if (const std::optional<std::string> problem = coding_problem(req)) return refused(ApiError::bad_request, *problem);
  BodyFraming f = read_length(req);
  if (f.refusal) return f;
  f.chunked = chunked;
  if (chunked && f.length) return refused(ApiError::bad_request, "both Content-Length and Transfer-Encoding: send one");
  if (req.method != "POST" && req.method != "PATCH") {
    // httplib does not read such a body: it would be parsed as the next request.
    if (chunked || (f.length && *f.length > 0))
      return refused(ApiError::bad_request, "a " + req.method + " request has no body");
    return f;
  }
  // httplib reads a POST (or PATCH) body without Content-Length until the client closes: a client that
  // neither sends a length nor closes would hold a thread for the whole read timeout.
  if (!f.length && !chunked)
    return refused(ApiError::length_required,
                   "a " + req.method + " needs Content-Length (curl: -d '' for an empty body)");
  return f;
}

}  // namespace popcut::daemon
