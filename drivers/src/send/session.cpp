// The sending session: effective flow control and query, cancel checks and the give-up of a held cancel.
#include "send/session.h"

#include <utility>

namespace popcut::drivers::send {

FlowControl paced_flow(const Transport& transport, const SendOptions& options) {
  // XON/XOFF is popcut's to read only where the transport does not do it (the simulator); a
  // serial port stops its transmitter in the OS, which then blocks popcut's writes.
  const FlowControl flow = transport.answers() ? options.flow : FlowControl::none;
  return flow == FlowControl::xon_xoff && transport.os_flow_control() ? FlowControl::none : flow;
}

DrainQuery asked_query(const Transport& transport, const SendOptions& options, FlowControl flow) {
  const DrainQuery query = transport.answers() ? options.drain_query : DrainQuery::none;
  return flow == FlowControl::esc_b && query == DrainQuery::none ? DrainQuery::esc_b : query;
}

SendSession::SendSession(Transport& line, const EncodedJob& sent_job, const SendOptions& send_options)
    : transport(line),
      job(sent_job),
      options(send_options),
      flow(paced_flow(line, send_options)),
      query(asked_query(line, send_options, flow)),
      host(language_unit(send_options.language).host()) {
  result.first_stroke = job.first_stroke;
  result.last_stroke_sent = job.first_stroke - 1;
  result.last_stroke_written = job.first_stroke - 1;
  result.total_strokes = job.total_strokes;
  result.received_counted_by =
      query != DrainQuery::none
          ? (line.writes_acknowledged() ? ReceivedCountedBy::transport : ReceivedCountedBy::status_answers)
      : time_paced()               ? ReceivedCountedBy::buffer_size
      : line.writes_acknowledged() ? ReceivedCountedBy::transport
                                   : ReceivedCountedBy::os_queue;
}

bool SendSession::at_boundary_and_cancelled() const {
  return cancel_requested() && job.command_boundary_at_or_after(result.bytes_sent) == result.bytes_sent;
}

bool SendSession::given_up_while_held() {
  if (!std::exchange(told_waiting_, true) && options.waiting_to_cancel) options.waiting_to_cancel();
  if (!options.give_up || !options.give_up->load()) return false;
  transport.discard_output();
  result.status = {
      TransportError::timeout, 0,
      "gave up waiting for the device to take the rest of the cancel: it held the line (XOFF or CTS), so neither "
      "the abort sequence nor the knife-up reached it"};
  return true;
}

}  // namespace popcut::drivers::send
