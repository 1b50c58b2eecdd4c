// Webhook delivery: bounded per-endpoint queues, one sender thread each, retries with backoff, HMAC signatures.
#include "notifier.h"

#include <httplib.h>
#include <openssl/hmac.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <mutex>
#include <random>
#include <thread>

#include "log.h"

namespace popcut::daemon {

const char* to_string(EventKind kind) { return kEventKindNames.name(kind).data(); }

std::string event_body(const Event& e) {
  return nlohmann::json{{"event", to_string(e.kind)}, {"at", e.at_s}, {"job", e.job}, {"device", e.device}}.dump();
}

std::string hmac_sha256_hex(const std::string& key, const std::string& data) {
  unsigned char mac[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()), reinterpret_cast<const unsigned char*>(data.data()),
       data.size(), mac, &len);
  static const char* kHex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < len; ++i) {
    out += kHex[mac[i] >> 4];
    out += kHex[mac[i] & 0xf];
  }
  return out;
}

std::string delivery_id() {
  static std::mutex m;
  static std::random_device device;
  std::lock_guard lock(m);
  std::string out;
  for (int i = 0; i < 4; ++i) {
    char part[9];
    std::snprintf(part, sizeof part, "%08x", static_cast<unsigned>(device()));
    out += part;
  }
  return out;
}

double retry_delay_s(int attempt) {
  double d = 0.5;
  for (int i = 1; i < attempt && d < 30; ++i) d *= 2;
  return std::min(d, 30.0);
}

// A receiver that is down, overloaded or timed out may take the next attempt; one that refuses
// the request (400, 401, 404 ...) will refuse it again.
bool worth_retrying(int status) { return status == 0 || status == 408 || status == 429 || status >= 500; }

struct Notifier::Endpoint {
  NotifyConfig config;
  struct Pending {
    std::string event, body;
  };
  std::mutex mutex;
  std::condition_variable wake;
  std::deque<Pending> queue;
  bool stopping = false;
  bool finished = false;              // its thread has left run()
  httplib::Client* active = nullptr;  // the request in flight, for stop() to cut off
  std::chrono::steady_clock::time_point stop_deadline{};
  std::thread thread;
  bool wants(EventKind kind) const {
    for (EventKind k : config.events) {
      if (k == kind) return true;
    }
    return false;
  }
};

Notifier::Notifier(std::vector<NotifyConfig> endpoints, std::size_t queue_events)
    : queue_events_(std::max<std::size_t>(1, queue_events)) {
  for (NotifyConfig& c : endpoints) {
    endpoints_.push_back(std::make_unique<Endpoint>());
    endpoints_.back()->config = std::move(c);
  }
  for (auto& e : endpoints_) e->thread = std::thread([this, ep = e.get()] { run(*ep); });
}

// How long popcutd's stop waits for the webhooks: their timeout_s, at most this.
constexpr double kStopGraceS = 5;

Notifier::~Notifier() {
  for (auto& e : endpoints_) {
    std::lock_guard lock(e->mutex);
    e->stopping = true;
    e->stop_deadline = std::chrono::steady_clock::now() +
                       std::chrono::milliseconds(static_cast<long>(std::min(e->config.timeout_s, kStopGraceS) * 1000));
    e->wake.notify_all();
  }
  // A receiver that hangs would hold popcutd's stop for a whole timeout_s per attempt: past
  // the grace its request is cut off (httplib's stop() shuts the socket down under the reader).
  for (auto& e : endpoints_) {
    std::unique_lock lock(e->mutex);
    if (!e->wake.wait_until(lock, e->stop_deadline, [&] { return e->finished; }) && e->active) e->active->stop();
  }
  for (auto& e : endpoints_) e->thread.join();
}

void Notifier::emit(Event event) {
  std::string body;  // dumped once, only if some endpoint wants it
  for (auto& e : endpoints_) {
    if (!e->wants(event.kind)) continue;
    if (body.empty()) body = event_body(event);
    std::lock_guard lock(e->mutex);
    if (e->stopping) {
      ++dropped_;
      continue;
    }
    if (e->queue.size() >= queue_events_) {
      e->queue.pop_front();
      ++dropped_;
    }
    e->queue.push_back({to_string(event.kind), body});
    e->wake.notify_one();
  }
}

bool Notifier::wants(EventKind kind) const {
  for (const auto& e : endpoints_) {
    if (e->wants(kind)) return true;
  }
  return false;
}

NotifyCounts Notifier::counts() const { return {delivered_.load(), failures_.load(), dropped_.load()}; }

void Notifier::run(Endpoint& e) {
  while (true) {
    Endpoint::Pending p;
    {
      std::unique_lock lock(e.mutex);
      e.wake.wait(lock, [&] { return e.stopping || !e.queue.empty(); });
      if (e.stopping && (e.queue.empty() || std::chrono::steady_clock::now() >= e.stop_deadline)) {
        if (!e.queue.empty())
          log_line("notify ", e.config.url, ": popcutd stops; ", e.queue.size(), " events not sent");
        dropped_ += e.queue.size();
        e.queue.clear();
        e.finished = true;
        e.wake.notify_all();
        return;
      }
      p = std::move(e.queue.front());
      e.queue.pop_front();
    }
    (deliver(e, p.event, p.body) ? delivered_ : failures_)++;
  }
}

// One delivery: the first attempt and up to `retries` more, each with the same delivery id.
bool Notifier::deliver(Endpoint& e, const std::string& event, const std::string& body) {
  const NotifyConfig& c = e.config;
  httplib::Headers headers = {
      {"X-Popcut-Event", event}, {"X-Popcut-Delivery", delivery_id()}, {"User-Agent", "popcutd"}};
  if (!c.secret.empty()) headers.emplace("X-Popcut-Signature", "sha256=" + hmac_sha256_hex(c.secret, body));
  const auto timeout = std::chrono::milliseconds(static_cast<long>(c.timeout_s * 1000));
  for (int attempt = 0;; ++attempt) {
    httplib::Client client(c.origin);
    client.set_connection_timeout(timeout);
    client.set_read_timeout(timeout);
    client.set_write_timeout(timeout);
#ifdef CPPHTTPLIB_OPENSSL_SUPPORT
    client.enable_server_certificate_verification(true);
    if (!c.ca_file.empty()) client.set_ca_cert_path(c.ca_file.c_str());
#endif
    {
      std::lock_guard lock(e.mutex);
      if (e.stopping && std::chrono::steady_clock::now() >= e.stop_deadline) return false;
      e.active = &client;
    }
    const httplib::Result r = client.Post(c.path, headers, body, "application/json");
    std::unique_lock lock(e.mutex);
    e.active = nullptr;
    const int status = r ? r->status : 0;
    if (status >= 200 && status < 300) return true;
    const std::string why = r ? "HTTP " + std::to_string(status) : "no answer (" + httplib::to_string(r.error()) + ")";
    if (!worth_retrying(status) || attempt >= c.retries || e.stopping) {
      log_line("notify ", c.url, ": ", event, " not delivered after ", attempt + 1, " attempts: ", why);
      return false;
    }
    const double delay_s = retry_delay_s(attempt + 1);
    log_line("notify ", c.url, ": ", event, " attempt ", attempt + 1, ": ", why, "; again in ", delay_s, " s");
    // popcutd stopping ends the wait: what is left then gets no more retries.
    e.wake.wait_for(lock, std::chrono::milliseconds(static_cast<long>(delay_s * 1000)), [&] { return e.stopping; });
    if (e.stopping) {
      log_line("notify ", c.url, ": ", event, " not delivered: popcutd stops");
      return false;
    }
  }
}

}  // namespace popcut::daemon
