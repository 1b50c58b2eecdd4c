// Timeouts and backoff shared by the sender's waits: slices, poll intervals, stalls and their wording.
#pragma once

#include <chrono>
#include <string>

namespace popcut::drivers::send {

// Waits are cut into slices this long so a cancel is noticed promptly.
inline constexpr std::chrono::milliseconds kSlice{100};

// The pause before poll number `polls` (from 0) of a busy device: 20, 40, 80, 160, then 200 ms.
std::chrono::milliseconds poll_backoff(int polls);

// Time a device has gone without progress, by its answers: an answer larger than any before
// (more free space) shows it working and starts the count again.
class StallClock {
 public:
  void answered(long answer);
  void waited(std::chrono::milliseconds d) { stalled_ += d; }
  std::chrono::milliseconds stalled() const { return stalled_; }

 private:
  long most_ = -1;
  std::chrono::milliseconds stalled_{0};
};

// "250 ms", "2 s": whole seconds from 10 s or where exact, rounded.
std::string duration_text(std::chrono::milliseconds d);

}  // namespace popcut::drivers::send
