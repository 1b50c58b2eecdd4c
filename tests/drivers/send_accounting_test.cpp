// Unit tests of the sender's accounting (E <= M <= N, buffered bytes, discards) and status channel (answers, silence,
// overdue).
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "send/accounting.h"
#include "send/held_line.h"
#include "send/session.h"
#include "send/status_channel.h"
#include "send_line_fake.h"

namespace {

using namespace popcut;
using namespace popcut::drivers;
using namespace popcut::drivers::send;
using popcut::drivers::testing::ScriptedLine;
using std::chrono::milliseconds;

// IN;PU0,0;PD10,0;PU20,0;PD30,0;PU; : stroke 1 is bytes 3..16 (knife down at 9), stroke 2 16..30 (at 23).
EncodedJob two_strokes() {
  EncodedJob job;
  job.bytes = "IN;PU0,0;PD10,0;PU20,0;PD30,0;PU;";
  job.total_strokes = 2;
  job.stroke_end = {16, 30};
  job.stroke_cut_start = {9, 23};
  job.command_end = {3, 9, 16, 23, 30, 33};
  return job;
}

TEST(SendAccounting, AStrokeIsExecutedOnceTheCommandAfterItHasLeftTheBuffer) {
  const EncodedJob job = two_strokes();
  EXPECT_EQ(stroke_executed_by(job, 16), 0u) << "its last move may still be under way";
  EXPECT_EQ(stroke_executed_by(job, 23), 1u);
  EXPECT_EQ(stroke_executed_by(job, 33), 2u);
}

TEST(SendAccounting, AStrokeIsTouchedOnceItsKnifeWentDown) {
  const EncodedJob job = two_strokes();
  EXPECT_EQ(stroke_touched_by(job, 9), 0u) << "travel only";
  EXPECT_EQ(stroke_touched_by(job, 16), 1u);
  EXPECT_EQ(stroke_touched_by(job, 23), 1u);
  EXPECT_EQ(stroke_touched_by(job, 30), 2u);
}

TEST(SendAccounting, OnlyHpglOfTheAbortEntersTheBuffer) {
  const HostProtocol& hpgl = language_unit(CutterLanguage::hpgl).host();
  EXPECT_EQ(hpgl.buffered_bytes("\x1b.KPU;"), 3u);
  EXPECT_EQ(hpgl.buffered_bytes("PU;"), 3u);
  EXPECT_EQ(hpgl.buffered_bytes("\x1b.K"), 0u);
}

TEST(SendAccounting, AnswersTellWhatLeftTheBufferNeverMore) {
  ScriptedLine line;
  SendOptions o;
  o.buffer_bytes = 100;
  const EncodedJob job = two_strokes();
  SendSession session(line, job, o);
  SendAccounting accounting(session);
  accounting.learn({0, DrainQuery::esc_b, 100});
  const Whereabouts where = accounting.learn({50, DrainQuery::esc_b, 80});
  EXPECT_EQ(where.kind, Whereabouts::Kind::at);
  EXPECT_EQ(where.read_bytes, 30u) << "50 written, 20 still held";
  EXPECT_EQ(accounting.executed(), 30u);
  accounting.learn({60, DrainQuery::esc_b, 150});
  EXPECT_EQ(accounting.device_buffer(), 150u) << "it said it had more free than the profile's size";
  EXPECT_EQ(accounting.executed(), 60u);
  EXPECT_EQ(accounting.learn({0, DrainQuery::esc_b, -1}).kind, Whereabouts::Kind::unknown);
  EXPECT_EQ(accounting.learn({70, DrainQuery::esc_o, 8}).kind, Whereabouts::Kind::at_least);
  EXPECT_EQ(accounting.executed(), 70u);
  EXPECT_EQ(accounting.learn({80, DrainQuery::esc_o, 0}).kind, Whereabouts::Kind::unknown) << "busy: nothing learnt";
  EXPECT_EQ(accounting.executed(), 70u);
}

TEST(SendAccounting, ADiscardedBufferLeavesReceivedAtExecuted) {
  ScriptedLine line;
  SendOptions o;
  o.drain_query = DrainQuery::esc_o;
  const EncodedJob job = two_strokes();
  SendSession session(line, job, o);
  SendAccounting accounting(session);
  SendResult& r = session.result;
  r.bytes_sent = 33;
  accounting.settle(0);
  EXPECT_FALSE(r.last_stroke_executed) << "no answer yet: not known";
  accounting.learn({23, DrainQuery::esc_o, 8});
  accounting.settle(1);
  EXPECT_EQ(r.bytes_received, 33u);
  EXPECT_EQ(r.last_stroke_sent, 2u);
  EXPECT_EQ(r.last_stroke_written, 2u);
  EXPECT_EQ(r.last_stroke_executed, 1u);
  accounting.set_discarding(true);
  accounting.settle(1);
  EXPECT_EQ(r.last_stroke_sent, 1u) << "received but not cut is gone";
  EXPECT_EQ(r.bytes_received, 16u);
  EXPECT_EQ(r.received_before_abort, 2u);
}

TEST(SendAccounting, BufferedBytesAreBoundedOrMeasured) {
  ScriptedLine line;
  SendOptions o;
  o.buffer_bytes = 10;
  o.drain_query = DrainQuery::esc_o;
  o.abort_bytes = "\x1b.KPU;";
  const EncodedJob job = two_strokes();
  SendSession session(line, job, o);
  SendAccounting accounting(session);
  SendResult& r = session.result;
  r.bytes_sent = 33;
  accounting.learn({23, DrainQuery::esc_o, 8});
  accounting.settle(1);
  accounting.bound_buffered(5);
  EXPECT_EQ(r.buffered_bytes, 15u) << "its buffer and what is on its way";
  EXPECT_FALSE(r.buffer_known);
  r.abort_sent = true;
  accounting.measured_buffered(4);
  EXPECT_EQ(r.buffered_bytes, 3u) << "6 held, less the knife-up of the abort";
  accounting.buffered_strokes();
  EXPECT_EQ(r.buffered_first_stroke, 2u) << "no later than after the last executed";
  EXPECT_EQ(r.buffered_last_stroke, 2u);
}

struct Channel {
  Channel(Transport& line, const EncodedJob& job, const SendOptions& o)
      : session(line, job, o), held(session), channel(session, held, [this](const Answer& a) { heard.push_back(a); }) {
    held.listen_with([this] { return channel.take_replies(milliseconds(0)); });
  }
  SendSession session;
  HeldLine held;
  StatusChannel channel;
  std::vector<Answer> heard;
};

TEST(StatusChannel, ARoundTripReturnsTheAnswer) {
  ScriptedLine line;
  line.answers = {"123\r\n"};
  SendOptions o;
  const EncodedJob job = two_strokes();
  Channel c(line, job, o);
  ASSERT_TRUE(c.channel.ask(DrainQuery::esc_o, "before sending"));
  EXPECT_EQ(line.written, "\x1b.O");
  EXPECT_EQ(c.channel.last_answer(), 123);
  EXPECT_EQ(c.channel.answers(), 1);
  EXPECT_EQ(c.session.result.status_queries, 1);
  ASSERT_EQ(c.heard.size(), 1u);
  EXPECT_EQ(c.heard[0].query, DrainQuery::esc_o);
  EXPECT_EQ(c.heard[0].value, 123);
}

TEST(StatusChannel, AnAnswerThatIsNotANumberNamesTheLine) {
  ScriptedLine line;
  line.answers = {
      "a\x01"
      "c\r"};
  SendOptions o;
  o.baud = 9600;
  const EncodedJob job = two_strokes();
  Channel c(line, job, o);
  EXPECT_FALSE(c.channel.ask(DrainQuery::esc_b, "before sending"));
  EXPECT_EQ(c.session.result.status.message,
            "the device answered 'a\\x01c' to ESC.B, not a status number: check the cable, the port and the baud rate "
            "(the profile says "
            "9600 baud)");
}

TEST(StatusChannel, SilenceForTheTimeoutIsADeviceThatDidNotAnswer) {
  ScriptedLine line;
  SendOptions o;
  o.timeout = milliseconds(200);
  const EncodedJob job = two_strokes();
  Channel c(line, job, o);
  EXPECT_FALSE(c.channel.ask(DrainQuery::esc_b, "before sending"));
  EXPECT_EQ(
      c.session.result.status.message,
      "the device did not answer ESC.B before sending within 200 ms: check the cable, the port and the baud rate");
}

TEST(StatusChannel, APingFollowedByMoreThanAStatusIntervalIsWaitedFor) {
  ScriptedLine line;
  SendOptions o;
  o.drain_query = DrainQuery::esc_o;
  o.status_every_bytes = 10;
  o.timeout = milliseconds(200);
  const EncodedJob job = two_strokes();
  Channel c(line, job, o);
  c.session.result.bytes_sent = 16;
  ASSERT_TRUE(c.channel.ping_if_due()) << "16 bytes since the start: asked, not yet overdue";
  EXPECT_EQ(c.session.result.status_queries, 1);
  c.session.result.bytes_sent = 23;
  ASSERT_TRUE(c.channel.ping_if_due()) << "7 bytes since: not due";
  EXPECT_EQ(c.session.result.status_queries, 1);
  c.session.result.bytes_sent = 30;
  EXPECT_FALSE(c.channel.ping_if_due()) << "14 bytes after an unanswered query: overdue";
  EXPECT_EQ(c.session.result.status.message,
            "the device did not answer ESC.O while sending within 200 ms: check the cable, the port and the baud rate");
}

}  // namespace
