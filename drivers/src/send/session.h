// What every part of one job's sending shares: the line, the job, the options, the result so far and the cancel.
#pragma once

#include <cstddef>

#include "popcut/drivers/job_sender.h"

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
  SendResult result;  // what has gone out and what is known so far; status set by the first failure

  bool cancel_requested() const { return options.cancel && options.cancel->load(); }
  // A cancel while the device holds us off: stop waiting unless a command is half sent.
  bool at_boundary_and_cancelled() const;
  // No handshake and a line that cannot hold popcut off: only the motion model tells the pace.
  bool time_paced() const { return flow == FlowControl::none && !transport.backpressure() && !options.motion.empty(); }
  // A cancel waiting on a device that holds the line: says so once (options.waiting_to_cancel),
  // and true with result.status set when the user has given up (options.give_up: a second
  // Ctrl-C). What the port still holds for the device is dropped, so that no stale byte reaches
  // it later.
  bool given_up_while_held();

 private:
  bool told_waiting_ = false;  // options.waiting_to_cancel was called
};

}  // namespace popcut::drivers::send
