// Simulated cutter: a discrete-event model of a plotter's line, buffer, executor and replies.
#include "popcut/drivers/sim_cutter.h"

#include "popcut/drivers/language.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <ostream>
#include <utility>

namespace popcut::drivers {
namespace {

constexpr char kXon = '\x11';
constexpr char kXoff = '\x13';
// Bytes handed to the reader at a time: fine enough that execution interleaves with arrival.
constexpr std::size_t kSlice = 16;

}  // namespace

SimCutter::SimCutter(const DeviceProfile& profile, SimFaults faults)
    : profile_(profile), faults_(faults), reader_(make_reader(profile)) {}

bool SimCutter::holds_line() const {
  return profile_.transport.flow == FlowControl::rts_cts || profile_.transport.flow == FlowControl::dtr_dsr;
}

std::optional<double> SimCutter::next_start_s() const {
  if (queue_.empty() || frozen() || halted()) return std::nullopt;
  return std::max(busy_until_s_, now_s_);
}

void SimCutter::preload(std::string_view bytes) {
  // Byte by byte: a long PA/PD comes out pair by pair, as a device that gets it over a line
  // reads it, so its bytes leave the buffer as each pair starts (not all when the first does).
  for (std::size_t i = 0; i < bytes.size(); ++i) take(bytes.substr(i, 1));
  report_.bytes_received += bytes.size();
}

std::size_t SimCutter::buffer_used() const { return queued_bytes_ + reader_->pending(); }

bool SimCutter::frozen() const {
  return faults_.stop_answering_after_bytes && report_.bytes_received >= *faults_.stop_answering_after_bytes;
}

void SimCutter::queue_reply(const std::string& s) {
  if (!frozen()) replies_ += s;
}

void SimCutter::check_water_marks() {
  if (profile_.transport.flow != FlowControl::xon_xoff) return;
  const std::size_t cap = profile_.transport.buffer_bytes;
  const std::size_t used = buffer_used();
  if (!xoff_ && used >= cap * 3 / 4) {
    queue_reply(std::string(1, kXoff));
    xoff_ = true;
    ++report_.xoff_sent;
  } else if (xoff_ && used <= cap / 4) {
    queue_reply(std::string(1, kXon));
    xoff_ = false;
  }
}

void SimCutter::advance_to(double t_s) {
  if (!frozen() && !halted()) {
    double cursor = now_s_;
    while (!queue_.empty() && std::max(busy_until_s_, cursor) <= t_s) {
      const double start = std::max(busy_until_s_, cursor);
      DeviceCommand c = std::move(queue_.front());
      queue_.pop_front();
      queued_bytes_ -= c.buffer_bytes;  // the device has read it out of its buffer
      const double dur = [&] {
        const double before = report_.motion_time_s;
        execute(c);
        return report_.motion_time_s - before;
      }();
      busy_until_s_ = start + dur;
      cursor = start;
      check_water_marks();
    }
  }
  now_s_ = std::max(now_s_, t_s);
  report_.clock_s = std::max(report_.clock_s, now_s_);
}

void SimCutter::take(std::string_view bytes) {
  std::vector<DeviceCommand> cmds;
  while (!bytes.empty()) {
    bytes.remove_prefix(reader_->feed_to_control(bytes, cmds));
    dispatch(cmds);
    cmds.clear();
  }
}

void SimCutter::dispatch(std::vector<DeviceCommand>& cmds) {
  for (DeviceCommand& c : cmds) {  // in stream order: a query counts every byte ahead of it
    ++report_.commands;
    if (c.device_control) {
      answer(c);  // device control bypasses the buffer, as on HP plotters
    } else {
      queued_bytes_ += c.buffer_bytes;
      queue_.push_back(std::move(c));
    }
  }
}

IoResult SimCutter::receive(const std::uint8_t* data, std::size_t size, double max_wait_s) {
  IoResult r;
  const double byte_s = 10.0 / profile_.transport.baud;  // start + 8 data + stop bits
  const bool held = holds_line();
  const std::size_t cap = profile_.transport.buffer_bytes;
  const double give_up = now_s_ + max_wait_s;
  while (r.bytes < size) {
    if (faults_.drop_after_bytes && report_.bytes_received >= *faults_.drop_after_bytes) {
      r.status = {TransportError::disconnected, 0,
                  "sim: connection dropped after " + std::to_string(report_.bytes_received) + " bytes"};
      return r;
    }
    std::size_t n = std::min(kSlice, size - r.bytes);
    if (faults_.drop_after_bytes) n = std::min(n, *faults_.drop_after_bytes - report_.bytes_received);
    if (held) {
      // The line is held while the buffer is full: wait for the executor to make room.
      while (buffer_used() >= cap) {
        if (frozen() || halted() || queue_.empty() || std::max(busy_until_s_, now_s_) > give_up) {
          r.status = {TransportError::timeout, 0, "sim: device buffer full; nothing executed within the timeout"};
          advance_to(give_up);
          return r;
        }
        advance_to(std::max(busy_until_s_, now_s_));
      }
      n = std::min(n, cap - buffer_used());
    }
    advance_to(now_s_ + byte_s * static_cast<double>(n));
    const std::string_view slice(reinterpret_cast<const char*>(data) + r.bytes, n);
    if (held || buffer_used() + n <= cap) {
      take(slice);
    } else {
      // No hardware handshake, and the host overran the buffer: HP-GL bytes that find it full
      // are lost, but device-control sequences never enter the buffer and still arrive.
      // Byte by byte, each command queued as it completes, so the fill level is exact.
      for (char c : slice) {
        if (reader_->starts_device_control(c) || reader_->in_device_control() || buffer_used() < cap)
          take(std::string_view(&c, 1));
        else {
          ++report_.overflow_bytes;
          io_error_ = 16;  // HP's ESC.E code: the input buffer has overflowed
        }
      }
    }
    r.bytes += n;
    report_.bytes_received += n;
    report_.max_buffer_used = std::max(report_.max_buffer_used, buffer_used());
    check_water_marks();
  }
  return r;
}

IoResult SimCutter::reply(std::uint8_t* data, std::size_t size, double max_wait_s) {
  IoResult r;
  if (faults_.drop_after_bytes && report_.bytes_received >= *faults_.drop_after_bytes) {
    r.status = {TransportError::disconnected, 0, "sim: connection dropped"};
    return r;
  }
  const double until = now_s_ + max_wait_s;
  if (size == 0) {
    // A host letting time pass, not reading: the wait is all of it, replies or not (a reply
    // nobody reads must not stop the clock).
    advance_to(until);
    r.status = {TransportError::timeout, 0, "sim: nothing read"};
    return r;
  }
  while (replies_.empty() && now_s_ < until) {
    const double next = (!queue_.empty() && !frozen() && !halted()) ? std::max(busy_until_s_, now_s_) : until;
    advance_to(std::min(next, until));
    if (next >= until) break;
  }
  if (replies_.empty()) {
    advance_to(until);
    r.status = {TransportError::timeout, 0, "sim: no reply within the timeout"};
    return r;
  }
  r.bytes = std::min(size, replies_.size());
  std::memcpy(data, replies_.data(), r.bytes);
  replies_.erase(0, r.bytes);
  return r;
}

bool SimCutter::run_to_end(bool input_whole) {
  if (frozen() || halted()) return false;
  std::vector<DeviceCommand> tail;
  reader_->finish(tail);  // only what lacked its terminator at the end of the input
  if (!input_whole) {
    for (const DeviceCommand& c : tail)
      report_.errors.push_back({c.offset, c.name, "cut short when the line ended: not executed"});
    tail.clear();
  }
  dispatch(tail);
  while (!queue_.empty()) advance_to(std::max(busy_until_s_, now_s_));
  advance_to(std::max(busy_until_s_, now_s_));
  end_stroke();
  return true;
}

DeviceFacts SimCutter::facts() const {
  DeviceFacts f;
  const std::size_t cap = profile_.transport.buffer_bytes;
  f.free_buffer_bytes = cap - std::min(cap, buffer_used());
  f.idle = queue_.empty() && busy_until_s_ <= now_s_;
  f.media_loaded = media_loaded_;
  f.paused = paused_;
  f.io_error = io_error_;
  f.errors = !report_.errors.empty();
  f.position = pos_;
  f.knife_down = pen_down_;
  const PlotterFrame& d = profile_.dialect;
  f.area_min = {d.area_min_x_pu, d.area_min_y_pu};
  f.area_max = {d.area_max_x_pu, d.area_max_y_pu};
  return f;
}

void SimCutter::drop_buffer() {
  report_.discarded_bytes += buffer_used();
  for (const DeviceCommand& q : queue_) queued_bytes_ -= q.buffer_bytes;
  queue_.clear();
  reader_->discard_pending();
}

void SimCutter::answer(const DeviceCommand& c) {
  if (frozen()) return;
  switch (c.op) {
    case DeviceOp::query_free_buffer:
    case DeviceOp::query_idle:
    case DeviceOp::query_identity:
    case DeviceOp::query_state: queue_reply(reader_->answer(c, facts())); break;
    case DeviceOp::query_io_error:
      queue_reply(reader_->answer(c, facts()));
      io_error_ = 0;  // read clears it, as on HP
      break;
    case DeviceOp::abort: drop_buffer(); break;  // drop what is buffered, a command in progress too
    case DeviceOp::initialize:
      // GP-GL's ESC EOT: the device starts afresh, the knife up and no tool selected.
      drop_buffer();
      if (pen_down_) end_stroke();
      pen_down_ = false;
      pen_ = 0;
      break;
    case DeviceOp::handshake_setup: break;  // the sim's pacing comes from the profile, so only counted
    default: report_.unknown.push_back({c.offset, c.name, "unknown device-control sequence"}); return;
  }
  ++report_.queries_answered;
}

void SimCutter::end_stroke() {
  if (current_ && current_->points_pu.size() >= 2) strokes_.push_back(std::move(*current_));
  current_.reset();
}

void SimCutter::move_to(std::array<std::int64_t, 2> p) {
  const HpglDialect& d = profile_.dialect;
  const double dx = static_cast<double>(p[0] - pos_[0]) / d.units_per_mm_x;
  const double dy = static_cast<double>(p[1] - pos_[1]) / d.units_per_mm_y;
  const double len = std::hypot(dx, dy);
  const double speed = pen_down_ ? (speed_cm_s_ > 0 ? speed_cm_s_ * 10 : profile_.kinematics.travel_speed_mm_s)
                                 : profile_.kinematics.travel_speed_mm_s;
  report_.motion_time_s += move_time_s(len, speed, profile_.kinematics.accel_mm_s2) * faults_.slowdown;
  if (p[0] < d.area_min_x_pu || p[0] > d.area_max_x_pu || p[1] < d.area_min_y_pu || p[1] > d.area_max_y_pu) {
    report_.outside_area = true;
  }
  if (pen_down_) {
    report_.knife_down_mm += len;
    if (current_ && p != pos_) current_->points_pu.push_back(p);
  } else {
    report_.knife_up_mm += len;
  }
  pos_ = p;
}

void SimCutter::execute(const DeviceCommand& c) {
  const std::string& n = c.name;
  if (c.malformed) report_.errors.push_back({c.offset, n, "malformed parameters"});
  const auto param = [&](std::size_t i, double fallback) { return i < c.params.size() ? c.params[i] : fallback; };
  const auto knife = [&](bool down) {
    if (down == pen_down_) return;
    report_.motion_time_s +=
        (down ? profile_.kinematics.knife_down_s : profile_.kinematics.knife_up_s) * faults_.slowdown;
    pen_down_ = down;
    if (down) {
      current_ = SimStroke{pen_, force_, speed_cm_s_, {pos_}};
      ++report_.knife_downs;
    } else {
      end_stroke();
    }
  };
  const auto moves = [&] {
    if (c.params.size() % 2 != 0) report_.errors.push_back({c.offset, n, "odd number of coordinates"});
    for (std::size_t i = 0; i + 1 < c.params.size(); i += 2) {
      // Far beyond any plotter, but small enough that position arithmetic cannot overflow.
      const auto coord = [](double x) { return std::llround(std::clamp(x, -1e12, 1e12)); };
      const std::array<std::int64_t, 2> v{coord(c.params[i]), coord(c.params[i + 1])};
      move_to(relative_ ? std::array<std::int64_t, 2>{pos_[0] + v[0], pos_[1] + v[1]} : v);
    }
  };
  switch (c.op) {
    case DeviceOp::reset:
      knife(false);
      relative_ = false;
      pen_ = 0;
      break;
    case DeviceOp::defaults: relative_ = false; break;
    case DeviceOp::select_tool:
      knife(false);
      pen_ = static_cast<int>(param(0, 0));
      // A holder's own force and speed (GP-GL's FXn,t and !n,t) apply once it is selected.
      if (const auto f = tool_force_.find(pen_); f != tool_force_.end()) force_ = f->second;
      if (const auto v = tool_speed_.find(pen_); v != tool_speed_.end()) speed_cm_s_ = v->second;
      break;
    case DeviceOp::home:
      knife(false);
      move_to({0, 0});
      break;
    case DeviceOp::speed: set_tool_value(tool_speed_, speed_cm_s_, speed_cm_s_of(param(0, 0)), c); break;
    case DeviceOp::force: set_tool_value(tool_force_, force_, param(0, 0), c); break;
    case DeviceOp::no_effect: break;  // e.g. Roland's tool/sheet type: changes no geometry the sim models
    case DeviceOp::knife_up:
    case DeviceOp::knife_down:
      knife(c.op == DeviceOp::knife_down);
      moves();
      break;
    case DeviceOp::knife_up_relative:
    case DeviceOp::knife_down_relative: {
      knife(c.op == DeviceOp::knife_down_relative);
      const bool was = std::exchange(relative_, true);
      moves();
      relative_ = was;
      break;
    }
    case DeviceOp::absolute:
    case DeviceOp::relative:
      relative_ = c.op == DeviceOp::relative;
      moves();
      break;
    case DeviceOp::report_identity:
    case DeviceOp::report_status:
    case DeviceOp::report_position:
    case DeviceOp::report_version:
    case DeviceOp::report_calibration:
    case DeviceOp::report_lower_left:
    case DeviceOp::report_upper_right: queue_reply(reader_->answer(c, facts())); break;
    default: report_.unknown.push_back({c.offset, n, "unknown command"}); break;
  }
}

double SimCutter::speed_cm_s_of(double value) const {
  return language_unit(profile_.language).speed_cm_s(profile_, value);
}

void SimCutter::set_tool_value(std::map<int, double>& per_tool, double& current, double value, const DeviceCommand& c) {
  // A second parameter names the holder (GP-GL's FXn,t and !n,t); the value applies now only
  // when that holder is the one selected (or none is yet).
  if (c.params.size() >= 2) {
    const int holder = static_cast<int>(c.params[1]);
    per_tool[holder] = value;
    if (holder != pen_ && pen_ != 0) return;
  }
  current = value;
}

void SimCutter::write_svg(std::ostream& out) const {
  const HpglDialect& d = profile_.dialect;
  const double x0 = static_cast<double>(d.area_min_x_pu) / d.units_per_mm_x,
               y0 = static_cast<double>(d.area_min_y_pu) / d.units_per_mm_y;
  const double x1 = static_cast<double>(d.area_max_x_pu) / d.units_per_mm_x,
               y1 = static_cast<double>(d.area_max_y_pu) / d.units_per_mm_y;
  // Only the part that was cut, with a margin: a 600 x 50000 mm roll would be unreadable.
  double lo_x = x1, lo_y = y1, hi_x = x0, hi_y = y0;
  for (const SimStroke& s : strokes_) {
    for (const auto& p : s.points_pu) {
      const double x = static_cast<double>(p[0]) / d.units_per_mm_x, y = static_cast<double>(p[1]) / d.units_per_mm_y;
      lo_x = std::min(lo_x, x), lo_y = std::min(lo_y, y), hi_x = std::max(hi_x, x), hi_y = std::max(hi_y, y);
    }
  }
  if (strokes_.empty()) lo_x = x0, lo_y = y0, hi_x = x0 + 10, hi_y = y0 + 10;
  const double m = 5;
  static const char* const kColours[] = {"#000000", "#d62728", "#1f77b4", "#2ca02c", "#ff7f0e",
                                         "#9467bd", "#8c564b", "#e377c2", "#7f7f7f"};
  out << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"" << lo_x - m << " " << -(hi_y + m) << " "
      << hi_x - lo_x + 2 * m << " " << hi_y - lo_y + 2 * m << "\" width=\"" << hi_x - lo_x + 2 * m << "mm\" height=\""
      << hi_y - lo_y + 2 * m << "mm\">\n";
  out << "<!-- popcut sim: " << strokes_.size() << " strokes, plotter y up; colour = pen -->\n";
  out << "<g fill=\"none\" stroke-width=\"0.3\" stroke-linecap=\"round\" stroke-linejoin=\"round\">\n";
  for (const SimStroke& s : strokes_) {
    out << "<polyline data-pen=\"" << s.pen << "\" data-force=\"" << s.force << "\" data-speed=\"" << s.speed_cm_s
        << "\" stroke=\"" << kColours[static_cast<std::size_t>(std::clamp(s.pen, 0, 8))] << "\" points=\"";
    for (std::size_t i = 0; i < s.points_pu.size(); ++i) {
      out << (i ? " " : "") << static_cast<double>(s.points_pu[i][0]) / d.units_per_mm_x << ","
          << -static_cast<double>(s.points_pu[i][1]) / d.units_per_mm_y;
    }
    out << "\"/>\n";
  }
  out << "</g>\n</svg>\n";
}

std::optional<std::size_t> first_difference(const std::vector<PlotterPath>& planned, const std::vector<SimStroke>& cut,
                                            std::int64_t tol_pu) {
  const std::size_t n = std::min(planned.size(), cut.size());
  for (std::size_t i = 0; i < n; ++i) {
    const PlotterPath& a = planned[i];
    const PlotterPath& b = cut[i].points_pu;
    if (a.size() != b.size()) return i;
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (std::llabs(a[k][0] - b[k][0]) > tol_pu || std::llabs(a[k][1] - b[k][1]) > tol_pu) return i;
    }
  }
  if (planned.size() != cut.size()) return n;
  return std::nullopt;
}

std::chrono::steady_clock::time_point SimTransport::now() const {
  return std::chrono::steady_clock::time_point(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(cutter_ ? cutter_->now_s() : 0.0)));
}

TransportStatus SimTransport::open() {
  if (!cutter_) return {TransportError::bad_argument, 0, "sim: no simulated cutter"};
  if (open_) return {TransportError::bad_argument, 0, "sim: already open"};
  open_ = true;
  return TransportStatus::success();
}

IoResult SimTransport::write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) {
  if (!open_) return {0, {TransportError::bad_argument, 0, "sim: write before open"}};
  return cutter_->receive(data.data(), data.size(), static_cast<double>(timeout.count()) / 1000);
}

IoResult SimTransport::read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) {
  if (!open_) return {0, {TransportError::bad_argument, 0, "sim: read before open"}};
  return cutter_->reply(buffer.data(), buffer.size(), static_cast<double>(timeout.count()) / 1000);
}

TransportStatus SimTransport::drain(std::chrono::milliseconds) {
  if (!open_) return {TransportError::bad_argument, 0, "sim: drain before open"};
  if (cutter_->frozen()) return {TransportError::timeout, 0, "sim: the device stopped answering"};
  return TransportStatus::success();
}

}  // namespace popcut::drivers
