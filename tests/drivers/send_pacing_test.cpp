// Unit tests of the sender's pacing parts: backoff and stalls, the motion tracker, writes through a held line, the
// pacers.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <vector>

#include "send/accounting.h"
#include "send/held_line.h"
#include "send/motion_tracker.h"
#include "send/pacer.h"
#include "send/session.h"
#include "send/status_channel.h"
#include "send/waits.h"
#include "send_line_fake.h"

namespace {

using namespace popcut;
using namespace popcut::drivers;
using namespace popcut::drivers::send;
using popcut::drivers::testing::ScriptedLine;
using std::chrono::milliseconds;

// The parts of one send wired as the sender wires them.
struct Parts {
  Parts(Transport& line, const EncodedJob& job, const SendOptions& o)
      : session(line, job, o),
        held(session),
        channel(session, held,
                [this](const Answer& a) {
                  const Whereabouts where = accounting.learn(a);
                  if (session.time_paced()) tracker.heard(where);
                }),
        accounting(session),
        tracker(o.motion, o.pace_margin_percent, line.now()),
        pacer(make_pacer({session, channel, accounting, tracker})) {
    held.listen_with([this] { return channel.take_replies(milliseconds(0)); });
  }
  SendSession session;
  HeldLine held;
  StatusChannel channel;
  SendAccounting accounting;
  MotionTracker tracker;
  std::unique_ptr<Pacer> pacer;
};

const std::vector<MotionMark> kMarks = {{0, 0}, {1.0, 100}, {2.0, 200}, {3.0, 300}};

EncodedJob raw_job(std::size_t size) {
  EncodedJob job;
  job.bytes = std::string(size, ';');
  for (std::size_t i = 1; i <= size; ++i) job.command_end.push_back(i);
  return job;
}

TEST(SendWaits, PollsBackOffToAFifthOfASecond) {
  const std::vector<long> expected = {20, 40, 80, 160, 200, 200, 200};
  for (int polls = 0; polls < 7; ++polls)
    EXPECT_EQ(poll_backoff(polls).count(), expected[static_cast<std::size_t>(polls)]) << polls;
}

TEST(SendWaits, OnlyALargerAnswerRestartsTheStallClock) {
  StallClock stall;
  stall.answered(5);
  stall.waited(milliseconds(300));
  stall.answered(5);  // no more free than before: still stalled
  stall.answered(3);
  EXPECT_EQ(stall.stalled().count(), 300);
  stall.answered(6);
  EXPECT_EQ(stall.stalled().count(), 0);
}

TEST(SendWaits, DurationsInMillisecondsOrWholeSeconds) {
  EXPECT_EQ(duration_text(milliseconds(250)), "250 ms");
  EXPECT_EQ(duration_text(milliseconds(2000)), "2 s");
  EXPECT_EQ(duration_text(milliseconds(12345)), "12 s");
  EXPECT_EQ(duration_text(milliseconds(9999)), "9999 ms");
}

TEST(MotionTracker, MovesByTheClockSlowedByTheMargin) {
  const auto t0 = std::chrono::steady_clock::time_point(milliseconds(1000));
  MotionTracker exact(kMarks, 0, t0);
  EXPECT_EQ(exact.advance(t0, 300), 0u);
  EXPECT_EQ(exact.advance(t0 + milliseconds(1500), 300), 100u) << "the command at 1 s has started";
  EXPECT_DOUBLE_EQ(exact.seconds(), 1.5);
  MotionTracker slow(kMarks, 100, t0);
  slow.advance(t0 + milliseconds(2000), 300);
  EXPECT_DOUBLE_EQ(slow.seconds(), 1.0) << "twice as slow with a 100 % margin";
}

TEST(MotionTracker, AStarvedDeviceWaitsForTheBytesOfItsNextCommand) {
  const auto t0 = std::chrono::steady_clock::time_point(milliseconds(0));
  MotionTracker tracker(kMarks, 0, t0);
  tracker.advance(t0 + milliseconds(5000), 150);
  EXPECT_DOUBLE_EQ(tracker.seconds(), 2.0) << "it cannot start the command at 2 s without byte 200";
  EXPECT_EQ(tracker.needs(), 200u);
  tracker.advance(t0 + milliseconds(5500), 300);
  EXPECT_DOUBLE_EQ(tracker.seconds(), 2.5) << "the wait cost it time";
  EXPECT_EQ(tracker.needs(), 0u);
}

TEST(MotionTracker, AnswersPlaceTheModel) {
  const auto t0 = std::chrono::steady_clock::time_point(milliseconds(0));
  MotionTracker tracker(kMarks, 0, t0);
  tracker.advance(t0 + milliseconds(2500), 300);
  tracker.heard({Whereabouts::Kind::at, 150});
  EXPECT_DOUBLE_EQ(tracker.seconds(), 1.0) << "ESC.B: where it is, even behind the model";
  tracker.heard({Whereabouts::Kind::at_least, 50});
  EXPECT_DOUBLE_EQ(tracker.seconds(), 1.0) << "ESC.O: never back";
  tracker.heard({Whereabouts::Kind::at_least, 250});
  EXPECT_DOUBLE_EQ(tracker.seconds(), 2.0);
  EXPECT_DOUBLE_EQ(tracker.time_past(150), 2.0);
  EXPECT_DOUBLE_EQ(tracker.time_past(300), 3.0) << "past the last mark: the end of the motion";
  EXPECT_EQ(tracker.quiet_for().count(), 1000) << "the longest command";
  EXPECT_EQ(MotionTracker({}, 0, t0).quiet_for().count(), 500) << "no model: a few answers' worth";
}

TEST(HeldLine, AHoldIsCountedOnceAndWaitedOut) {
  ScriptedLine line;
  line.held_slices = 3;
  SendOptions o;
  o.timeout = milliseconds(1000);
  const EncodedJob job = raw_job(3);
  Parts parts(line, job, o);
  std::size_t taken = 0;
  EXPECT_EQ(parts.held.write(
                "PU;", [&](std::size_t k) { taken += k; }, [](std::size_t) { return false; }),
            Held::written);
  EXPECT_EQ(taken, 3u);
  EXPECT_EQ(parts.held.slice_holds(), 1);
  EXPECT_EQ(line.clock.count(), 750) << "three slices of 250 ms";
}

TEST(HeldLine, AHoldPastTheHoldTimeoutFails) {
  ScriptedLine line;
  line.held_slices = 100;
  SendOptions o;
  o.hold_timeout = milliseconds(1000);
  const EncodedJob job = raw_job(3);
  Parts parts(line, job, o);
  EXPECT_EQ(parts.held.write(
                "PU;", [](std::size_t) {}, [](std::size_t) { return false; }),
            Held::failed);
  EXPECT_EQ(parts.session.result.status.message,
            "the device held popcut off for 1 s without taking a byte (hold_timeout_ms): is it paused, out of media or "
            "stuck? (held)");
}

TEST(HeldLine, ALineThatCannotBeHeldFailsAtTheFirstTimeout) {
  ScriptedLine line;
  line.holds_line = false;
  line.held_slices = 1;
  SendOptions o;
  const EncodedJob job = raw_job(3);
  Parts parts(line, job, o);
  EXPECT_EQ(parts.held.write(
                "PU;", [](std::size_t) {}, [](std::size_t) { return false; }),
            Held::failed);
  EXPECT_EQ(parts.session.result.status.message, "held");
}

TEST(HeldLine, TheAbortWaitsUpToTheHoldTimeoutAndTellsTheUserOnce) {
  ScriptedLine line;
  line.held_slices = 100;
  SendOptions o;
  o.timeout = milliseconds(500);
  o.hold_timeout = milliseconds(1000);
  int told = 0;
  o.waiting_to_cancel = [&] { ++told; };
  const EncodedJob job = raw_job(3);
  Parts parts(line, job, o);
  EXPECT_FALSE(parts.held.write_abort("PU;"));
  EXPECT_EQ(told, 1);
  EXPECT_EQ(line.clock.count(), 1000);
  EXPECT_EQ(parts.session.result.status.message,
            "the device held the line for 1 s (hold_timeout_ms) and did not take the abort sequence: held");
  EXPECT_EQ(parts.held.slice_holds(), 0) << "the abort's waits are no holds of the job";
}

TEST(HeldLine, TheAbortIsGivenUpOnASecondInterrupt) {
  ScriptedLine line;
  line.held_slices = 100;
  SendOptions o;
  const std::atomic<bool> give_up{true};
  o.give_up = &give_up;
  const EncodedJob job = raw_job(3);
  Parts parts(line, job, o);
  EXPECT_FALSE(parts.held.write_abort("PU;"));
  EXPECT_EQ(line.clock.count(), 250) << "one slice";
  EXPECT_NE(parts.session.result.status.message.find("gave up waiting"), std::string::npos);
}

TEST(Pacer, TimePacingWaitsUntilTheModelHasReadEnough) {
  for (const int margin : {0, 100}) {
    ScriptedLine line;
    line.holds_line = false;
    SendOptions o;
    o.buffer_bytes = 100;  // 50 ahead of the model
    o.motion = kMarks;
    o.pace_margin_percent = margin;
    const EncodedJob job = raw_job(300);
    Parts parts(line, job, o);
    ASSERT_TRUE(parts.session.time_paced());
    parts.session.result.bytes_sent = 100;
    std::size_t n = 50;
    ASSERT_TRUE(parts.pacer->pace(n, 50));
    EXPECT_EQ(n, 50u);
    const long expected_ms = margin == 0 ? 1000 : 2000;  // until the model has read byte 100
    EXPECT_GE(line.clock.count(), expected_ms) << margin;
    EXPECT_LT(line.clock.count(), expected_ms + 150) << margin;
  }
}

TEST(Pacer, EscBSendsWhatTheDeviceSaysIsFreeAndSpendsTheCredit) {
  ScriptedLine line;
  line.answers = {"40\r"};
  SendOptions o;
  o.flow = FlowControl::esc_b;
  const EncodedJob job = raw_job(300);
  Parts parts(line, job, o);
  std::size_t n = 100;
  ASSERT_TRUE(parts.pacer->pace(n, 128));
  EXPECT_EQ(n, 40u) << "the free space, worth a write";
  EXPECT_EQ(parts.session.result.buffer_queries, 1);
  parts.pacer->written(30);
  n = 10;
  ASSERT_TRUE(parts.pacer->pace(n, 128));
  EXPECT_EQ(parts.session.result.status_queries, 1) << "the credit left covers it: no query";
}

TEST(Pacer, EscBFailsWhenTheBufferStaysFullForTheHoldTimeout) {
  ScriptedLine line;
  line.default_answer = "0\r";
  SendOptions o;
  o.flow = FlowControl::esc_b;
  o.hold_timeout = milliseconds(500);
  const EncodedJob job = raw_job(300);
  Parts parts(line, job, o);
  std::size_t n = 100;
  EXPECT_FALSE(parts.pacer->pace(n, 128));
  EXPECT_NE(parts.session.result.status.message.find("the device's buffer stayed full for 500 ms"), std::string::npos)
      << parts.session.result.status.message;
}

TEST(Pacer, XonXoffWaitsForXon) {
  ScriptedLine line;
  line.replies = "\x13";
  line.say_at(milliseconds(700), "\x11");
  SendOptions o;
  o.flow = FlowControl::xon_xoff;
  const EncodedJob job = raw_job(300);
  Parts parts(line, job, o);
  std::size_t n = 10;
  ASSERT_TRUE(parts.pacer->pace(n, 10));
  EXPECT_GE(line.clock.count(), 700);
  EXPECT_EQ(parts.channel.xoffs_read(), 1);
  EXPECT_FALSE(parts.channel.paused());
}

TEST(Pacer, XonXoffFailsWhenHeldOffForTheHoldTimeout) {
  ScriptedLine line;
  line.replies = "\x13";
  SendOptions o;
  o.flow = FlowControl::xon_xoff;
  o.hold_timeout = milliseconds(300);
  const EncodedJob job = raw_job(300);
  Parts parts(line, job, o);
  std::size_t n = 10;
  EXPECT_FALSE(parts.pacer->pace(n, 10));
  EXPECT_EQ(parts.session.result.status.message,
            "the device held popcut off (XOFF) for 300 ms (hold_timeout_ms): is it paused, out of media or stuck?");
}

}  // namespace
