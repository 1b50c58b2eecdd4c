// Streams a job to a Transport, pacing it by the profile's flow control, with progress, cancel and drain.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "popcut/drivers/motion_model.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/transport.h"
#include "popcut/hpgl/hpgl.h"
#include "popcut/names.h"

namespace popcut::drivers {

// Where a job stands; strokes are numbered as users see them (see EncodedJob in hpgl.h).
// "Received" counts only what the device can be shown to hold (see SendResult); "written" what
// the transport accepted.
struct SendProgress {
  std::size_t bytes_sent = 0;
  std::size_t bytes_total = 0;
  // Last stroke the device certainly received (0: none yet). Paced by time with no answers: what
  // left the port, as long as all goes well (the result after a failure counts far less).
  std::size_t last_stroke_sent = 0;
  std::size_t last_stroke_written = 0;  // last stroke whose commands all went into the transport
  std::size_t first_stroke = 1;         // where this transmission started (--resume-from)
  std::size_t total_strokes = 0;
};

struct SendOptions {
  // The device's language: its status queries and answers, and which bytes enter its buffer.
  CutterLanguage language = CutterLanguage::hpgl;
  FlowControl flow = FlowControl::none;
  std::size_t buffer_bytes = 1024;          // the device's buffer: chunks stay well inside it
  std::chrono::milliseconds timeout{5000};  // for one write or one reply
  // How long the device may hold us off (XOFF, or a full buffer under ESC.B) while it cuts: a
  // full buffer can take minutes of motion to drain.
  std::chrono::milliseconds hold_timeout{120000};
  // How to learn that the device has executed everything once the last byte is out. Not none:
  // the device answers that query, so popcut asks it once before sending (silence or garbage: a
  // wrong port, cable or baud, reported before any byte of the job goes out) and every
  // status_every_bytes while sending, and counts as received only what an answer confirms.
  DrainQuery drain_query = DrainQuery::none;
  std::size_t status_every_bytes = 0;  // 0: a quarter of buffer_bytes
  // After the drain, ask ESC.E: a device reporting an I/O error (15: framing, parity, overrun;
  // 16: input buffer overflow) lost bytes, so a job that seemed to get through did not.
  bool error_query = false;
  int baud = 0;  // named in the "did not answer" message of a serial line
  // The device's pace by the motion model (motion_schedule in motion_model.h); empty where there is no device
  // to wait for (a plain file). Used where nothing
  // else tells how far the device has got: with no query, the sender waits until a full buffer's
  // share of the job's motion has passed before calling the job done; with no handshake (flow
  // none on a line that cannot hold popcut off) it also paces the job by it (time pacing).
  std::vector<MotionMark> motion;
  // Time pacing assumes the device may take this much longer than the model says.
  int pace_margin_percent = 25;
  // Where that margin is set, for the overflow message: the key, the file, and why that key.
  std::string pace_margin_from = "[transport] pace_margin_percent";
  // Sent on cancel, after the last complete command: the profile's abort sequence, then knife up
  // (HP-GL's by default; send_options takes the profile language's).
  std::string abort_bytes = "PU;";
  // The abort makes the device drop its buffer (ESC.K): after it, what was received but not
  // executed is no longer received (see SendResult::buffer_discarded).
  bool abort_discards_buffer = false;
  // Set (from any thread, e.g. a signal handler) to stop the job safely. Checked between chunks
  // and while waiting; the sender finishes the command in flight first.
  const std::atomic<bool>* cancel = nullptr;
  // A cancel ends with the abort sequence and a knife-up, which a device holding the line (XOFF,
  // CTS) takes only when it lets popcut send again: up to hold_timeout. waiting_to_cancel is
  // called once when a cancel starts waiting so; give_up set (a second Ctrl-C after that notice)
  // then stops the wait: nothing more is sent (what the port still queues is dropped),
  // abort_sent is false, and the device may cut all its buffer holds. Checked only while held.
  const std::atomic<bool>* give_up = nullptr;
  std::function<void()> waiting_to_cancel;
  std::function<void(const SendProgress&)> progress;  // after every chunk
  // Set (from any thread) to pause the job: unlike a cancel, nothing of what the device holds is
  // dropped. The sender finishes the stroke in flight, sends pause_bytes (knife up), waits until
  // the device has executed everything as at the end of a job, and returns with paused set and
  // the counts of a drained job, so that last_stroke_written is the last stroke cut and a resume
  // from the next one cuts each stroke exactly once. A cancel during that wait wins.
  const std::atomic<bool>* pause = nullptr;
  std::string pause_bytes = "PU;";  // knife up (send_options: the language's, and its park for starts_at origin)
};

// How SendResult::bytes_received was counted: transport (a write's count is what the device
// took: USB, a file, the simulator), status_answers (serial, device answers queries), os_queue
// (serial, device cannot be asked: written less the OS queue and what may still be in flight) or
// buffer_size (paced by time, device cannot be asked: a device that stopped lost what overran
// its buffer, so only the first buffer_bytes are certain).
enum class ReceivedCountedBy { transport, status_answers, os_queue, buffer_size };
inline constexpr auto kReceivedCountedByNames =
    enum_names<ReceivedCountedBy>({{ReceivedCountedBy::transport, "transport"},
                                   {ReceivedCountedBy::status_answers, "status_answers"},
                                   {ReceivedCountedBy::os_queue, "os_queue"},
                                   {ReceivedCountedBy::buffer_size, "buffer_size"}});
const char* to_string(ReceivedCountedBy how);

// How a job's end was confirmed: the device's ESC.B (whole buffer free), ESC.O (buffer empty) or
// ESC ENQ ("ready") answer, the motion model's estimate, or none (a file: nothing to wait for).
// not_drained (a cancel or failure) is written as an empty name.
enum class DrainedBy { not_drained, esc_b, esc_o, estimate, none, esc_enq };
inline constexpr auto kDrainedByNames = enum_names<DrainedBy>({{DrainedBy::not_drained, ""},
                                                               {DrainedBy::esc_b, "esc_b"},
                                                               {DrainedBy::esc_o, "esc_o"},
                                                               {DrainedBy::estimate, "estimate"},
                                                               {DrainedBy::none, "none"},
                                                               {DrainedBy::esc_enq, "esc_enq"}});
const char* to_string(DrainedBy how);

// Why the device itself ended a job, by its status answer: no sheet loaded (tray empty, also a
// roll that ran out) or its pause key. none (written as an empty name): it did not.
enum class DeviceStop { none, tray_empty, paused };
inline constexpr auto kDeviceStopNames = enum_names<DeviceStop>(
    {{DeviceStop::none, ""}, {DeviceStop::tray_empty, "tray_empty"}, {DeviceStop::paused, "paused"}});
const char* to_string(DeviceStop why);

// Never over-claims: bytes written into a serial port may still sit in the OS queue, a UART FIFO
// or a pseudo-terminal when the line drops. bytes_received counts what the device took (USB
// bulk actual_length), what it confirmed (its answer to a status query sent after those bytes)
// or, for a device that cannot be asked, what the port reports gone (written, less the OS output
// queue and what may still be in flight).
// Resuming from last_stroke_sent + 1 therefore never skips a stroke while the device keeps its
// buffer and goes on cutting; strokes last_stroke_sent + 1 .. last_stroke_written may have been
// cut already and are cut again. Received is not cut: a device that hangs, is paused for good or
// loses power never cuts what sits in its buffer. last_stroke_executed (E <= M <= N) is what it
// is known to have cut, and the resume point after a reset or power cycle.
struct SendResult {
  std::size_t bytes_sent = 0;      // job bytes the transport accepted (abort and queries not counted)
  std::size_t bytes_received = 0;  // job bytes the device can be shown to have received (<= bytes_sent)
  std::size_t first_stroke = 1;
  std::size_t last_stroke_sent = 0;     // last stroke the device certainly received (first_stroke - 1: none)
  std::size_t last_stroke_written = 0;  // last stroke whose commands all went into the transport
  // Last stroke the device is known to have executed (first_stroke - 1: none), from its answers:
  // ESC.B (bytes written before the query, less what its buffer still holds), ESC.O "buffer
  // empty", a drain it confirmed. A stroke counts once the command after it has left the buffer.
  // nullopt: the device cannot be asked (no drain_query, a file), so it is not known.
  std::optional<std::size_t> last_stroke_executed;
  std::size_t total_strokes = 0;
  ReceivedCountedBy received_counted_by = ReceivedCountedBy::transport;
  // Paced by time, after a cancel or failure: how long the device may go on cutting what it
  // holds, by the model (0: not paced by time). A job sent to it meanwhile would overrun it.
  double busy_for_s = 0;
  bool cancelled = false;
  // Paused (SendOptions::pause) at a stroke boundary: status ok means the device drained and
  // lifted the knife, and strokes first_stroke..last_stroke_written are cut, no more.
  bool paused = false;
  bool abort_sent = false;  // the abort sequence and knife up reached the transport
  // The abort went out and the profile says the device drops its buffer on it (an ESC.B answer
  // after it showing job bytes still held says otherwise and clears this): last_stroke_sent is
  // then last_stroke_executed (first_stroke - 1 when unknown), since strokes it held uncut are
  // gone, and nothing more is cut (buffered_bytes 0). Strokes last_stroke_sent+1..
  // last_stroke_written may have been cut before it stopped. received_before_abort is what it had
  // received: the resume point, should the device have ignored the abort.
  bool buffer_discarded = false;
  std::size_t received_before_abort = 0;
  // After a cancel or a failure: bytes the device may still hold and go on cutting. Exact when
  // the device answered ESC.B (buffer_known), else an upper bound (its buffer plus what is still
  // on its way, at most what was sent); they carry strokes buffered_first_stroke..last written
  // (or the stroke cut short by the cancel).
  std::size_t buffered_bytes = 0;
  bool buffer_known = false;
  std::size_t buffered_first_stroke = 0;
  std::size_t buffered_last_stroke = 0;
  DrainedBy drained_by = DrainedBy::not_drained;  // on success: how the end was confirmed
  // Times the device held popcut off: an XOFF popcut read itself (the simulator, USB), or a write
  // slice that made no progress on a line the device holds (XOFF or CTS applied by the OS, USB
  // NAKs), counted once per hold however long it lasts. ESC.B waits count in buffer_queries.
  int holds = 0;
  int buffer_queries = 0;  // ESC.B round trips to pace the job (ESC.B flow control)
  int status_queries = 0;  // every ESC.B/ESC.O/ESC.E sent: before the job, pacing, confirmations, drain, errors
  // ESC.E's answer after the job, when nonzero (the status then says what it means): the device
  // lost or garbled bytes, so what it cut is not the job and no resume point can repair it.
  int device_io_error = 0;
  // The device said it cannot go on (status answer): before any byte, nothing was sent; during
  // the job, popcut finished the command in flight, sent the abort and the knife-up, and the
  // counts say where to resume once the sheet is loaded or the device resumed.
  DeviceStop device_stop = DeviceStop::none;
  TransportStatus status;  // ok only when every byte went out and the device drained (not on cancel)
  bool complete() const { return status.ok() && !cancelled && !paused; }
  // Paused with every stroke through last_stroke_written executed and the knife lifted.
  bool paused_cleanly() const { return status.ok() && paused && !cancelled; }
};

// Flow, buffer, timeouts, drain query and abort sequence from the profile.
SendOptions send_options(const DeviceProfile& profile);

// The pace margin's key and file, and why that key: "[transport] pace_margin_percent in P: ...".
std::string pace_margin_from(const DeviceProfile& profile);

// Writes `job`, chunked on command boundaries; stops at the first transport error (reported with
// the bytes and strokes that got through) or at a cancel. A transport that cannot answer
// (Transport::answers() false) is never asked for XON/XOFF or ESC.B.
SendResult send_job(Transport& transport, const EncodedJob& job, const SendOptions& options);
// Raw bytes with no stroke information (tests, hand-written jobs).
SendResult send_job(Transport& transport, std::string_view job, const SendOptions& options);

}  // namespace popcut::drivers
