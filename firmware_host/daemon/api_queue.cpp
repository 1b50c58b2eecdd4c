// Reading the queue's requests: Idempotency-Key, the list's filters, an admin's move.
#include "api_queue.h"

#include <openssl/evp.h>

#include <algorithm>
#include <limits>

namespace popcut::daemon {

std::string idempotency_key(const Req& req) {
  const std::size_t n = req.get_header_value_count("Idempotency-Key");
  if (n == 0) return "";
  const std::string key = req.get_header_value("Idempotency-Key");
  const bool visible = std::all_of(key.begin(), key.end(), [](char c) { return c > ' ' && c < 0x7f; });
  if (n > 1 || key.empty() || key.size() > 255 || !visible)
    fail(ApiError::bad_request, "Idempotency-Key must be given once, 1 to 255 visible ASCII characters (e.g. a UUID)",
         "Idempotency-Key");
  return key;
}

std::string request_digest(const NewJob& nj) {
  std::string all;
  const std::string copies = std::to_string(nj.copies);
  for (const std::string* part :
       {&nj.name, &nj.target_device, &nj.target_profile, &nj.material, &copies, &nj.model_json}) {
    all += std::to_string(part->size()) + ":" + *part;
  }
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  EVP_Digest(all.data(), all.size(), md, &len, EVP_sha256(), nullptr);
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < len; ++i) out += {hex[md[i] >> 4], hex[md[i] & 15]};
  return out;
}

JobFilter job_filter(const Req& req) {
  JobFilter f;
  if (const std::optional<std::string> given = query_param(req, "limit")) {
    const std::string& l = *given;
    if (l.empty() || l.size() > 5 || l.find_first_not_of("0123456789") != std::string::npos || std::stoi(l) < 1 ||
        std::stoi(l) > 10000) {
      fail(ApiError::bad_request, "limit must be a whole number from 1 to 10000", "limit");
    }
    f.limit = std::stoi(l);
  }
  if (const std::optional<std::string> given = query_param(req, "state")) {
    std::size_t at = 0;
    while (at <= given->size()) {
      const std::size_t comma = std::min(given->find(',', at), given->size());
      const std::string name = given->substr(at, comma - at);
      const std::optional<JobState> state = parse_job_state(name);
      if (!state)
        fail(ApiError::bad_request,
             "state: '" + name.substr(0, 40) + "' is not a job state (" + kJobStateNames.list(", ") +
                 ", comma-separated)",
             "state");
      f.states.push_back(*state);
      at = comma + 1;
    }
  }
  if (const std::optional<std::string> given = query_param(req, "device")) {
    if (!is_safe_name(*given)) fail(ApiError::bad_name, "not a device name: " + given->substr(0, 64), "device");
    f.device = *given;
  }
  if (const std::optional<std::string> given = query_param(req, "since")) {
    const std::optional<double> since = parse_unix_seconds(*given);
    if (!since) fail(ApiError::bad_request, "since must be unix seconds (a number from 0, e.g. 1764547200)", "since");
    f.since_s = since;
  }
  return f;
}

int copies_field(const json& v) {
  if (!whole_in(v, 1, 1000))
    fail(ApiError::bad_request, "'copies' must be a whole number from 1 to 1000 (cards nested on one sheet)", "copies");
  return v.get<int>();
}

Reorder reorder_request(const Req& req) {
  const json body = parse_body(req);
  if (!body.is_object())
    fail(ApiError::bad_request, "the body must be a JSON object such as {\"priority\": 10} or {\"before\": 42}");
  Reorder r;
  for (const auto& [k, v] : body.items()) {
    if (k == "priority") {
      if (!whole_in(v, -100, 100))
        fail(ApiError::bad_request,
             "'priority' must be a whole number from -100 to 100 (higher is cut first; 0 is "
             "the default)",
             "priority");
      r.priority = v.get<int>();
    } else if (k == "before") {
      if (!whole_in(v, 1, std::numeric_limits<std::int64_t>::max()))
        fail(ApiError::bad_request, "'before' must be the id of a waiting job", "before");
      r.before = v.get<std::int64_t>();
    } else {
      fail(ApiError::bad_request,
           "unknown field '" + k.substr(0, 40) + "' (a job's place takes 'priority' and 'before')", k);
    }
  }
  if (!r.priority && !r.before) fail(ApiError::bad_request, "name 'priority', 'before' or both", "priority");
  return r;
}

}  // namespace popcut::daemon
