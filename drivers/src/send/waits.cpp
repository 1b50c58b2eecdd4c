// Poll backoff, stall clock and duration wording for the sender's waits.
#include "send/waits.h"

#include <algorithm>

namespace popcut::drivers::send {

std::chrono::milliseconds poll_backoff(int polls) {
  return std::chrono::milliseconds(std::min(200L, 20L << std::min(polls, 4)));
}

void StallClock::answered(long answer) {
  if (answer <= most_) return;
  most_ = answer;
  stalled_ = std::chrono::milliseconds(0);
}

std::string duration_text(std::chrono::milliseconds d) {
  if (d.count() % 1000 == 0 || d.count() >= 10000) return std::to_string((d.count() + 500) / 1000) + " s";
  return std::to_string(d.count()) + " ms";
}

}  // namespace popcut::drivers::send
