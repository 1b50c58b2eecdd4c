// A scripted device line on a virtual clock for the sender's unit tests: held writes, timed replies, scripted answers.
#pragma once

#include <algorithm>
#include <chrono>
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "popcut/drivers/transport.h"

namespace popcut::drivers::testing {

// Reads with nothing to deliver wait their whole timeout out on the clock; every ESC (a status
// query) queues the next scripted answer (or `default_answer`); the first `held_slices` writes
// move no byte (a held line) and cost their timeout.
class ScriptedLine final : public Transport {
 public:
  TransportStatus open() override { return {}; }
  IoResult write(std::span<const std::uint8_t> d, std::chrono::milliseconds timeout) override {
    if (held_slices > 0) {
      --held_slices;
      clock += timeout;
      return {0, {TransportError::timeout, 0, "held"}};
    }
    for (const std::uint8_t b : d) {
      written.push_back(static_cast<char>(b));
      if (b != 0x1b) continue;
      if (!answers.empty()) {
        replies += answers.front();
        answers.pop_front();
      } else {
        replies += default_answer;
      }
    }
    return {d.size(), {}};
  }
  IoResult read(std::span<std::uint8_t> b, std::chrono::milliseconds timeout) override {
    release();
    if (replies.empty()) {
      clock += timeout;
      release();
    }
    if (replies.empty() || b.empty()) return {0, {TransportError::timeout, 0, "silence"}};
    const std::size_t n = std::min(b.size(), replies.size());
    std::copy_n(replies.begin(), n, b.begin());
    replies.erase(0, n);
    return {n, {}};
  }
  TransportStatus drain(std::chrono::milliseconds) override { return {}; }
  void close() override {}
  std::string describe() const override { return "serial:/dev/scripted"; }
  bool backpressure() const override { return holds_line; }
  std::chrono::steady_clock::time_point now() const override { return std::chrono::steady_clock::time_point(clock); }

  // `text` arrives once the clock reaches `at`.
  void say_at(std::chrono::milliseconds at, std::string text) { timed.emplace_back(at, std::move(text)); }

  std::deque<std::string> answers;
  std::string default_answer;
  std::string replies;  // waiting to be read
  std::string written;
  int held_slices = 0;
  bool holds_line = true;
  std::chrono::milliseconds clock{0};

 private:
  void release() {
    for (auto it = timed.begin(); it != timed.end();) {
      if (it->first > clock) {
        ++it;
        continue;
      }
      replies += it->second;
      it = timed.erase(it);
    }
  }
  std::vector<std::pair<std::chrono::milliseconds, std::string>> timed;
};

}  // namespace popcut::drivers::testing
