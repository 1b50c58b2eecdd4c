// The modelled device's progress along the motion schedule, moved by the transport's clock and the device's answers.
#include "send/motion_tracker.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace popcut::drivers::send {

MotionTracker::MotionTracker(const std::vector<MotionMark>& marks, int pace_margin_percent, Clock::time_point start)
    : marks_(marks), margin_percent_(pace_margin_percent), at_(start) {}

std::vector<MotionMark>::const_iterator MotionTracker::first_mark_past(std::size_t bytes) const {
  return std::upper_bound(marks_.begin(), marks_.end(), bytes,
                          [](std::size_t b, const MotionMark& m) { return b < m.bytes_read; });
}

double MotionTracker::start_of(std::vector<MotionMark>::const_iterator mark) const {
  return mark == marks_.end() ? marks_.back().start_s : mark->start_s;
}

double MotionTracker::time_at(std::size_t read_bytes) const {
  const auto after = first_mark_past(read_bytes);
  return after == marks_.begin() ? 0 : std::prev(after)->start_s;
}

double MotionTracker::time_past(std::size_t bytes) const { return start_of(first_mark_past(bytes)); }

std::size_t MotionTracker::advance(Clock::time_point now, std::size_t has_bytes) {
  const double dt_s = std::chrono::duration<double>(now - at_).count() / slowdown();
  at_ = now;
  const auto waits_for = first_mark_past(has_bytes);
  const double limit_s = start_of(waits_for);
  seconds_ = std::min(seconds_ + std::max(0.0, dt_s), std::max(seconds_, limit_s));
  needs_ = waits_for != marks_.end() && seconds_ >= limit_s ? waits_for->bytes_read : 0;
  const auto started = std::upper_bound(marks_.begin(), marks_.end(), seconds_,
                                        [](double t, const MotionMark& m) { return t < m.start_s; });
  return started == marks_.begin() ? 0 : std::prev(started)->bytes_read;
}

void MotionTracker::heard(const Whereabouts& where) {
  // At least there: a device faster than the margin assumes is not held back by it.
  if (where.kind == Whereabouts::Kind::at) seconds_ = time_at(where.read_bytes);
  if (where.kind == Whereabouts::Kind::at_least) seconds_ = std::max(seconds_, time_at(where.read_bytes));
  // Still busy with them: a device slower than the model says is not run past by it.
  if (where.kind == Whereabouts::Kind::before) seconds_ = std::min(seconds_, time_at(where.read_bytes));
}

std::chrono::milliseconds MotionTracker::quiet_for() const {
  double longest_s = 0;
  for (std::size_t i = 1; i < marks_.size(); ++i)
    longest_s = std::max(longest_s, marks_[i].start_s - marks_[i - 1].start_s);
  return std::max(std::chrono::milliseconds(500),
                  std::chrono::milliseconds(static_cast<long>(std::ceil(longest_s * slowdown() * 1000))));
}

std::size_t advance_by_line(MotionTracker& tracker, Transport& transport, std::size_t bytes_sent) {
  const auto now = transport.now();
  const std::size_t has_bytes =
      tracker.is_all_out() ? bytes_sent : bytes_sent - std::min(bytes_sent, transport.expected_in_flight());
  return tracker.advance(now, has_bytes);
}

}  // namespace popcut::drivers::send
