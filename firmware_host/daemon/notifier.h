// Webhooks: each [[notify]] endpoint gets the events it names, POSTed from a thread of its own.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "config.h"
#include "notify_event.h"

namespace popcut::daemon {

// Totals over every endpoint since start (/metrics).
struct NotifyCounts {
  std::uint64_t delivered = 0;  // answered 2xx
  std::uint64_t failures = 0;   // given up: every attempt failed, or refused with a 4xx
  std::uint64_t dropped = 0;    // never tried: the endpoint's queue was full (oldest dropped), or popcutd stopped
};

// emit() only queues: a slow, failing or hanging endpoint delays nothing but its own later
// events. Each endpoint holds at most `queue_events` events; a new one then drops the oldest.
class Notifier final : public EventSink {
 public:
  explicit Notifier(std::vector<NotifyConfig> endpoints, std::size_t queue_events = 1000);
  // What is queued gets one attempt each (no retries) for up to each endpoint's timeout_s; the
  // rest is dropped and counted.
  ~Notifier() override;
  Notifier(const Notifier&) = delete;
  Notifier& operator=(const Notifier&) = delete;

  void emit(Event event) override;
  // Whether some endpoint takes events of this kind (no need to build one otherwise).
  bool wants(EventKind kind) const;
  NotifyCounts counts() const;

 private:
  struct Endpoint;
  void run(Endpoint& e);
  bool deliver(Endpoint& e, const std::string& event, const std::string& body);

  std::atomic<std::uint64_t> delivered_{0}, failures_{0}, dropped_{0};
  std::size_t queue_events_;
  std::vector<std::unique_ptr<Endpoint>> endpoints_;
};

// The request body: {"event", "at", "job", "device"} (docs/api.md "Webhooks").
std::string event_body(const Event& event);
// HMAC-SHA256 of `data` with `key`, as 64 lowercase hex digits: X-Popcut-Signature's value after "sha256=".
std::string hmac_sha256_hex(const std::string& key, const std::string& data);
// 32 random hex digits: X-Popcut-Delivery, the same on every attempt of one delivery.
std::string delivery_id();
// Seconds to wait before retry `attempt` (1, 2, ...): 0.5 s doubling, at most 30 s.
double retry_delay_s(int attempt);
// Whether an answer with this status (0: none, the connection failed or timed out) is worth another attempt.
bool worth_retrying(int status);

}  // namespace popcut::daemon
