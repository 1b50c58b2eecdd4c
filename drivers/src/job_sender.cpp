// Job streaming: chunked writes paced by XON/XOFF or ESC.B queries, so a device buffer never overflows.
#include "popcut/drivers/job_sender.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace popcut::drivers {
namespace {

constexpr std::uint8_t kXon = 0x11;
constexpr std::uint8_t kXoff = 0x13;

std::span<const std::uint8_t> bytes_of(std::string_view s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

}  // namespace

SendOptions send_options(const DeviceProfile& profile) {
  SendOptions o;
  o.flow = profile.transport.flow;
  o.buffer_bytes = profile.transport.buffer_bytes;
  o.timeout = std::chrono::milliseconds(profile.transport.timeout_ms);
  o.hold_timeout = std::chrono::milliseconds(profile.transport.hold_timeout_ms);
  return o;
}

SendResult send_job(Transport& t, std::string_view job, const SendOptions& o) {
  SendResult r;
  // Small chunks under XON/XOFF: the device says XOFF at 3/4 full, so one chunk in flight must
  // fit in the last quarter.
  const std::size_t chunk = std::max<std::size_t>(1, std::min<std::size_t>(256, o.buffer_bytes / 8));
  bool paused = false;
  std::size_t credit = 0;  // ESC.B: bytes the device last said it could take, less those sent since
  std::uint8_t buf[64];
  while (r.bytes_sent < job.size()) {
    std::size_t n = std::min(chunk, job.size() - r.bytes_sent);
    if (o.flow == FlowControl::xon_xoff) {
      // Take what the device said so far; wait for XON while it holds us off.
      for (;;) {
        const IoResult got = t.read(buf, paused ? o.hold_timeout : std::chrono::milliseconds(0));
        for (std::size_t i = 0; i < got.bytes; ++i) {
          if (buf[i] == kXoff && !paused) {
            paused = true;
            ++r.xoff_pauses;
          } else if (buf[i] == kXon) {
            paused = false;
          }
        }
        if (!got.status.ok() && got.status.error != TransportError::timeout) {
          r.status = got.status;
          return r;
        }
        if (!paused) break;
        if (got.bytes == 0) {
          r.status = {TransportError::timeout, 0, "device held the line (XOFF) for longer than " +
                                                      std::to_string(o.hold_timeout.count()) + " ms"};
          return r;
        }
      }
    } else if (o.flow == FlowControl::esc_b && credit < n) {
      // Ask for free space; poll again (letting the device work, backing off) while there is
      // too little. The answer is credit for the next chunks: the device only drains meanwhile.
      long waited_ms = 0;
      for (int polls = 0;; ++polls) {
        const IoResult w = t.write(bytes_of("\x1b.B"), o.timeout);
        if (!w.status.ok()) {
          r.status = w.status;
          return r;
        }
        ++r.buffer_queries;
        std::string answer;
        while (answer.find('\r') == std::string::npos) {
          const IoResult got = t.read(std::span<std::uint8_t>(buf, 1), o.timeout);
          if (!got.status.ok()) {
            r.status = {got.status.error, got.status.os_error, "no answer to ESC.B: " + got.status.message};
            return r;
          }
          answer.append(reinterpret_cast<const char*>(buf), got.bytes);
        }
        credit = static_cast<std::size_t>(std::max(0L, std::strtol(answer.c_str(), nullptr, 10)));
        if (credit >= n) break;
        if (credit >= chunk / 2) {
          n = credit;
          break;
        }
        if (waited_ms > o.hold_timeout.count()) {
          r.status = {TransportError::timeout, 0, "device buffer stayed full for longer than " +
                                                      std::to_string(o.hold_timeout.count()) + " ms"};
          return r;
        }
        const long wait_ms = std::min(200L, 20L << std::min(polls, 4));
        (void)t.read(std::span<std::uint8_t>(buf, 0), std::chrono::milliseconds(wait_ms));  // let it work
        waited_ms += wait_ms;
      }
    }
    const IoResult w = t.write(bytes_of(job.substr(r.bytes_sent, n)), o.timeout);
    r.bytes_sent += w.bytes;
    credit -= std::min(credit, w.bytes);
    if (o.progress) o.progress(r.bytes_sent, job.size());
    if (!w.status.ok()) {
      r.status = w.status;
      return r;
    }
  }
  r.status = t.drain(o.timeout);
  return r;
}

}  // namespace popcut::drivers
