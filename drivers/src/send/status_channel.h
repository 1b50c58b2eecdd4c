// The device's side of the line: status queries in the device's language, their answers, XON/XOFF read by popcut,
// overdue answers.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <string>

#include "send/held_line.h"
#include "send/session.h"

namespace popcut::drivers::send {

// An answered query: the job bytes written before it (all of which have reached the device,
// since answers come back in order), which query it was and the number the device answered.
struct Answer {
  std::size_t bytes_before = 0;
  DrainQuery query = DrainQuery::none;
  long value = 0;
};

class StatusChannel {
 public:
  // `heard` is told every answer, oldest query first.
  StatusChannel(SendSession& session, HeldLine& line, std::function<void(const Answer&)> heard);

  // Sends a status query without waiting for its answer. A line the device holds holds a query
  // like any byte; a cancel before a byte of it has gone leaves it unsent (query_skipped()), so
  // the abort follows. False with the session's status set.
  bool send_query(DrainQuery query);
  // One status round trip: sends the query and waits (up to the timeout, on the transport's
  // clock: real, or the simulator's) until it and every one before it are answered; the answer
  // in last_answer(). False with the session's status set.
  bool ask(DrainQuery query, const std::string& when);
  // Waits up to the timeout until at most `keep` queries are unanswered. False with the
  // session's status set: a device that never answered is on the wrong port or baud; one that
  // answered before and falls silent has stopped.
  bool await_answers(std::size_t keep, DrainQuery query, const std::string& when);
  // Reads what the device said within `wait`: XON/XOFF (the simulator) and answer lines, each of
  // which confirms the oldest query outstanding. False with the session's status set on a
  // transport error or an answer that is not a number.
  bool take_replies(std::chrono::milliseconds wait);
  // A pipelined query followed by more job bytes than can still be on their way (the port's
  // queue and an adapter's FIFO, at least a status interval) has reached the device, which
  // answers device control on arrival: wait for its answer now, so that a device that stops
  // mid-job is noticed then and not only after the last byte.
  bool check_overdue();
  // After a chunk: every status_every_bytes, at a command boundary, a pipelined query that costs
  // no round trip (not under ESC.B flow, whose pacing asks anyway); then what came back.
  bool ping_if_due();

  // The abort is under way: from here a query's answer is waited for, a cancel no longer cuts it short.
  void aborting() { aborting_ = true; }

  long last_answer() const { return last_answer_; }
  bool query_skipped() const {
    return query_skipped_;
  }                                               // the last query was not sent or not answered: a cancel came first
  int answers() const { return answers_; }        // a device that answered once and goes silent has stopped
  bool paused() const { return paused_; }         // XOFF read and no XON since
  int xoffs_read() const { return xoffs_read_; }  // XOFFs popcut read itself (flow control not in the OS)
  bool nothing_pending() const { return pending_.empty(); }
  DrainQuery newest_pending() const { return pending_.back().query; }

 private:
  // A query awaiting its answer: the job bytes written before it, and which query it was.
  struct Pending {
    std::size_t bytes_before;
    DrainQuery query;
    std::chrono::steady_clock::time_point sent_at;  // by the transport's clock
  };

  bool answer_line();
  std::string check_line_hint() const;
  // Before any answer: the language's word on a device of another language, else check_line_hint.
  std::string mismatch_or_line_hint(const std::string& heard) const;
  bool no_answer(DrainQuery query, const std::string& when, std::chrono::milliseconds held);

  SendSession& session_;
  HeldLine& line_;
  std::function<void(const Answer&)> heard_;
  std::size_t status_every_;     // job bytes between pipelined queries
  std::size_t last_ping_ = 0;    // job bytes written before the last of them
  std::deque<Pending> pending_;  // queries awaiting an answer
  std::string text_;             // the answer line read so far
  long last_answer_ = 0;
  std::size_t bytes_heard_ = 0;  // bytes read from the device so far
  int answers_ = 0;
  int xoffs_read_ = 0;
  bool paused_ = false;
  bool query_skipped_ = false;
  bool answer_dropped_ = false;  // a cancel ended await_answers before the answer came
  bool aborting_ = false;
};

}  // namespace popcut::drivers::send
