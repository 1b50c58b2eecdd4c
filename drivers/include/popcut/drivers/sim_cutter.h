// The simulated cutter: executes its profile's language on a virtual clock, records strokes, models its buffer and
// faults.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "popcut/drivers/device_reader.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/transport.h"

namespace popcut::drivers {

// One knife-down path as the device moved it, in absolute plotter units.
struct SimStroke {
  int pen = 0;
  double force = 0;       // as sent (FS / !FS / FX units)
  double speed_cm_s = 0;  // the speed in force when the knife went down
  std::vector<std::array<std::int64_t, 2>> points_pu;
};

// Faults a test double of a real device must be able to show.
struct SimFaults {
  std::optional<std::size_t> stop_answering_after_bytes;  // then: no execution, no replies
  std::optional<std::size_t> drop_after_bytes;            // then: the connection is gone
  double slowdown = 1;                                    // motion takes this many times longer
  // The device's own stops, which its status answer reports (GP-GL ESC ENQ) and during which it
  // executes nothing but goes on answering and buffering: no sheet loaded, from the start (0) or
  // once this many bytes have arrived (the sheet or roll ran out); its pause key, once this many
  // have.
  std::optional<std::size_t> tray_empty_after_bytes = std::nullopt;
  std::optional<std::size_t> pause_after_bytes = std::nullopt;
};

struct SimIssue {
  std::size_t offset = 0;
  std::string command;
  std::string message;
};

struct SimReport {
  std::size_t bytes_received = 0;
  std::size_t commands = 0;
  std::size_t overflow_bytes = 0;  // bytes that arrived with the buffer full (lost)
  std::size_t max_buffer_used = 0;
  std::size_t discarded_bytes = 0;  // dropped from the buffer by ESC.K (received, never cut)
  int xoff_sent = 0;
  int queries_answered = 0;
  int knife_downs = 0;
  double knife_down_mm = 0;
  double knife_up_mm = 0;
  double motion_time_s = 0;       // time spent executing commands (kinematics, slowdown)
  double clock_s = 0;             // virtual wall clock, including time spent waiting for bytes
  bool outside_area = false;      // a move left the usable area
  std::vector<SimIssue> unknown;  // commands it does not know: reported, not fatal
  std::vector<SimIssue> errors;   // malformed parameters, odd coordinate counts
};

class SimCutter {
 public:
  explicit SimCutter(const DeviceProfile& profile, SimFaults faults = {});

  // Bytes arriving on the line, each taking one character time at the profile's baud rate.
  // With hardware flow control (RTS/CTS, DTR/DSR) a full buffer holds the line until space frees
  // (up to max_wait_s of virtual time); otherwise (XON/XOFF, ESC.B, none) HP-GL bytes that find it
  // full are lost, as on a device the host overran.
  IoResult receive(const std::uint8_t* data, std::size_t size, double max_wait_s);
  // Replies waiting (XON/XOFF, query answers); waits up to max_wait_s of virtual time for one.
  IoResult reply(std::uint8_t* data, std::size_t size, double max_wait_s);
  // Runs every buffered command (the host waiting for the device to finish); false if stuck.
  // `input_whole`: the input ended where the host meant it to (a file, a finished job), so a last
  // command without its terminator runs; false after a hang-up, where a command cut short is
  // dropped (and reported) as a real device would never see its end.
  bool run_to_end(bool input_whole = true);
  // The simulator's clock, for a host that runs it in real time (popcut sim-plotter): advance()
  // executes what the clock reaches; receive() moves it by each byte's line time.
  double now_s() const { return now_s_; }
  std::array<std::int64_t, 2> position() const { return pos_; }  // plotter units
  void advance(double t_s) { advance_to(t_s); }
  // When the next buffered command starts (now or when the one in motion ends); nullopt when
  // none waits or the device is frozen.
  std::optional<double> next_start_s() const;
  // The whole input at once, ahead of the clock, as if the buffer held any amount: for a model of
  // the device's pace (motion_schedule), not for a line.
  void preload(std::string_view bytes);
  // Whether a full buffer holds the line (hardware flow control) rather than losing bytes.
  bool holds_line() const;

  const std::vector<SimStroke>& strokes() const { return strokes_; }
  const SimReport& report() const { return report_; }
  const DeviceProfile& profile() const { return profile_; }
  std::size_t buffer_used() const;
  bool frozen() const;
  bool knife_down() const { return pen_down_; }
  // XON/XOFF: it has said XOFF and not yet XON (a host stopping its transmitter in the OS sends
  // nothing meanwhile).
  bool holding_off() const { return xoff_; }

  // A device without media, or paused at its panel, executes nothing and says so when asked
  // (GP-GL ESC ENQ: "2", "3"); bytes still arrive and queries are still answered.
  void set_media_loaded(bool loaded) { media_loaded_ = loaded; }
  void set_paused(bool paused) { paused_ = paused; }
  bool halted() const { return !media_loaded_ || paused_; }

  // What it cut, one colour per pen, over the usable area.
  void write_svg(std::ostream& out) const;

 private:
  void advance_to(double t_s);
  // Bytes that reached the reader: queues the commands they complete, answers device control.
  void take(std::string_view bytes);
  void dispatch(std::vector<DeviceCommand>& cmds);
  void execute(const DeviceCommand& c);
  void answer(const DeviceCommand& c);
  void move_to(std::array<std::int64_t, 2> p);
  void end_stroke();
  void check_water_marks();
  void queue_reply(const std::string& s);
  DeviceFacts facts() const;
  // SimFaults' tray empty and pause, once their byte counts have arrived.
  void apply_stop_faults();
  void drop_buffer();
  double speed_cm_s_of(double value) const;
  void set_tool_value(std::map<int, double>& per_tool, double& current, double value, const DeviceCommand& c);

  DeviceProfile profile_;
  SimFaults faults_;
  std::unique_ptr<DeviceReader> reader_;  // of the profile's language
  std::deque<DeviceCommand> queue_;
  std::size_t queued_bytes_ = 0;
  double busy_until_s_ = 0;
  double now_s_ = 0;
  std::string replies_;
  bool xoff_ = false;
  int io_error_ = 0;  // what ESC.E answers: 16 after an overflow, until asked
  // Device state.
  bool pen_down_ = false;
  bool relative_ = false;
  std::array<std::int64_t, 2> pos_{0, 0};
  int pen_ = 0;
  double force_ = 0;
  double speed_cm_s_ = 0;
  std::map<int, double> tool_force_, tool_speed_;  // per holder, where the language names one
  bool media_loaded_ = true;
  bool paused_ = false;
  std::optional<SimStroke> current_;
  std::vector<SimStroke> strokes_;
  SimReport report_;
};

// Index of the first recovered stroke that differs from the planned one by more than tol_pu on
// either axis at any point (or by point count), or of the first one missing or extra; nullopt
// when they agree.
std::optional<std::size_t> first_difference(const std::vector<PlotterPath>& planned, const std::vector<SimStroke>& cut,
                                            std::int64_t tol_pu = 1);

// A Transport whose far end is a SimCutter; timeouts count in the simulator's virtual time.
class SimTransport final : public Transport {
 public:
  explicit SimTransport(std::shared_ptr<SimCutter> cutter) : cutter_(std::move(cutter)) {}
  TransportStatus open() override;
  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override;
  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override;
  TransportStatus drain(std::chrono::milliseconds timeout) override;
  void close() override { open_ = false; }
  std::string describe() const override { return "sim"; }
  // Hardware flow control holds the writer; XON/XOFF and ESC.B are popcut's to honour, and a
  // device with none loses what overruns it (the sender paces it by time).
  bool backpressure() const override { return cutter_ && cutter_->holds_line(); }
  // The simulator's virtual clock, which the sender's waits move.
  std::chrono::steady_clock::time_point now() const override;

 private:
  std::shared_ptr<SimCutter> cutter_;
  bool open_ = false;
};

}  // namespace popcut::drivers
