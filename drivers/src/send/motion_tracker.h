// Where the modelled device is along a job's motion schedule, by a clock: time pacing's view of the device.
#pragma once

#include <chrono>
#include <cstddef>
#include <vector>

#include "popcut/drivers/motion_model.h"
#include "popcut/drivers/transport.h"

namespace popcut::drivers::send {

// What a status answer says of where the device is: at the point where it has read `read_bytes`
// (ESC.B: what it still holds), at least there (ESC.O: buffer empty; ESC ENQ: ready), or not yet
// done with them (ESC ENQ: moving, under status flow).
struct Whereabouts {
  enum class Kind { unknown, at, at_least, before };
  Kind kind = Kind::unknown;
  std::size_t read_bytes = 0;
};

class MotionTracker {
 public:
  using Clock = std::chrono::steady_clock;
  // `marks` non-empty where the tracker is asked anything but quiet_for.
  MotionTracker(const std::vector<MotionMark>& marks, int pace_margin_percent, Clock::time_point start);

  // Moves the modelled device on to `now`, at the model's pace slowed by the margin, and returns
  // the job bytes it has read out of its buffer. It cannot start a command before it has all of
  // it (`has_bytes` have reached it): waiting for bytes (a slow line, a late write) costs it
  // time, so it never runs ahead of the device, which could then be sent more than it has room for.
  std::size_t advance(Clock::time_point now, std::size_t has_bytes);
  // Every byte has left popcut: the device has all that was sent.
  void all_out() { all_out_ = true; }
  bool is_all_out() const { return all_out_; }

  // The device said where it was, later or sooner than the model: from here the model goes on from there.
  void heard(const Whereabouts& where);

  double seconds() const { return seconds_; }  // of motion done
  // Starved: the bytes it must have to go on (0: it is not).
  std::size_t needs() const { return needs_; }
  // When the model has read no more than `read_bytes`, at the latest: the start of the last
  // command within them.
  double time_at(std::size_t read_bytes) const;
  // When the model first reads more than `bytes` (the end of the job's motion past the last mark).
  double time_past(std::size_t bytes) const;
  double end_s() const { return marks_.back().start_s; }
  double slowdown() const { return 1 + margin_percent_ / 100.0; }
  // The longest the device may go without reading a byte: the longest command of the job by the
  // motion model, slowed by the margin (at least a few answers' worth where there is no model).
  std::chrono::milliseconds quiet_for() const;

 private:
  std::vector<MotionMark>::const_iterator first_mark_past(std::size_t bytes) const;
  double start_of(std::vector<MotionMark>::const_iterator mark) const;

  const std::vector<MotionMark>& marks_;
  int margin_percent_;
  double seconds_ = 0;
  std::size_t needs_ = 0;
  Clock::time_point at_;  // the clock reading seconds_ stands for
  bool all_out_ = false;
};

// Moves `tracker` on by the transport's clock, the device having what was sent less what is
// still on its way (all of it once every byte is out).
std::size_t advance_by_line(MotionTracker& tracker, Transport& transport, std::size_t bytes_sent);

}  // namespace popcut::drivers::send
