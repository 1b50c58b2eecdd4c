// What every part of one job's sending shares: the line, the job, the options, the result so far and the cancel.
#pragma once

#include <cstddef>

#include <string>

#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"

namespace popcut::drivers::send {

// What popcut paces by: the profile's flow control where popcut does it itself (the transport
// answers, and does not apply XON/XOFF in the OS), else none.
FlowControl paced_flow(const Transport& transport, const SendOptions& options);
// The status query popcut asks (none: the device cannot be asked); ESC.B flow asks ESC.B.
DrainQuery asked_query(const Transport& transport, const SendOptions& options, FlowControl flow);

class SendSession {
 public:
  SendSession(Transport& line, const EncodedJob& sent_job, const SendOptions& send_options);

  Transport& transport;
  const EncodedJob& job;
  const SendOptions& options;
  const FlowControl flow;
  const DrainQuery query;
  const HostProtocol& host;  // the language's side of the status conversation
  SendResult result;         // what has gone out and what is known so far; status set by the first failure

  // "ESC.B": a query as the device's manual names it, for messages.
  std::string query_name(DrainQuery q) const { return std::string(host.query_name(q)); }
  // The user's cancel, or the device's stop (device_stopped): both end the job at the command in
  // flight, with the abort and the knife-up.
  bool cancel_requested() const { return stop_ != DeviceStop::none || user_cancelled(); }
  bool user_cancelled() const { return options.cancel && options.cancel->load(); }
  bool pause_requested() const { return options.pause && options.pause->load(); }
  // A status answer said the device cannot go on (tray empty, paused); the first reason stands.
  void device_stopped(DeviceStop why) {
    if (stop_ == DeviceStop::none) stop_ = why;
  }
  DeviceStop device_stop() const { return stop_; }
  // A cancel while the device holds us off: stop waiting unless a command is half sent.
  bool at_boundary_and_cancelled() const;
  // Paced by the motion model: no handshake on a line that cannot hold popcut off, where only the
  // model tells the pace, or status flow, where the device's idle/busy answers correct it.
  bool time_paced() const {
    return (flow == FlowControl::status || (flow == FlowControl::none && !transport.backpressure())) &&
           !options.motion.empty();
  }
  // A cancel waiting on a device that holds the line: says so once (options.waiting_to_cancel),
  // and true with result.status set when the user has given up (options.give_up: a second
  // Ctrl-C). What the port still holds for the device is dropped, so that no stale byte reaches
  // it later.
  bool given_up_while_held();

 private:
  bool told_waiting_ = false;  // options.waiting_to_cancel was called
  DeviceStop stop_ = DeviceStop::none;
};

}  // namespace popcut::drivers::send
