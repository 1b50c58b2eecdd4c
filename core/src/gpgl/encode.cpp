// GP-GL encoder: the plan's strokes in plotter units (plotter_frame.h) as M/D commands with ETX, tools as J/FX/!.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "popcut/error.h"
#include "popcut/gpgl/gpgl.h"
#include "popcut/text.h"

namespace popcut {
namespace {

class Writer {
 public:
  // A device-control sequence (ESC and its byte): no terminator.
  void control(char byte) {
    out_ += kGpglEsc;
    out_ += byte;
    ends_.push_back(out_.size());
  }
  void cmd(const std::string& s) {
    out_ += s;
    out_ += kGpglEtx;
    ends_.push_back(out_.size());
  }
  std::size_t size() const { return out_.size(); }
  std::string take() { return std::move(out_); }
  std::vector<std::size_t> take_ends() { return std::move(ends_); }

 private:
  std::string out_;
  std::vector<std::size_t> ends_;
};

std::string pairs(const PlotterPath& pts, std::size_t from, std::size_t to) {
  std::string s;
  for (std::size_t i = from; i < to; ++i) {
    if (i > from) s += ',';
    s += std::to_string(pts[i][0]) + "," + std::to_string(pts[i][1]);
  }
  return s;
}

int level(double value, double per_level, int lo, int hi, const char* what, const char* unit, const char* command) {
  const long n = std::lround(value / per_level);
  if (n < lo || n > hi) {
    throw Error(ErrorCode::invalid_input, "", what,
                format_significant(value) + " " + unit + " is " + command + " level " + std::to_string(n) +
                    ", outside this device's " + std::to_string(lo) + ".." + std::to_string(hi) + " (" +
                    format_significant(per_level) + " " + unit + " a level)");
  }
  return static_cast<int>(n);
}

// Initialisation and set-up, the same at the start of a job and of a resumed one.
void write_setup(Writer& w, const GpglDialect& d) {
  w.control(kGpglEot);
  if (d.home == GpglHome::tt) w.cmd("TT");
  if (d.home == GpglHome::h) w.cmd("H");
  if (d.media) w.cmd("FW" + std::to_string(*d.media));
  if (d.orientation) w.cmd(*d.orientation == GpglOrientation::landscape ? "FN1" : "FN0");
  if (d.page_size) {
    w.cmd("FU" + std::to_string(d.area_max_x_pu - d.area_min_x_pu) + "," +
          std::to_string(d.area_max_y_pu - d.area_min_y_pu));
  }
  if (d.track_enhancing) w.cmd(*d.track_enhancing ? "FY0" : "FY1");
  for (const std::string& s : d.setup) w.cmd(s);
}

// The tool commands for `t` where they differ from what the device has; per holder when the
// firmware names the holder in FX and !.
class ToolState {
 public:
  explicit ToolState(const GpglDialect& d) : d_(d) {}
  void select(Writer& w, const ToolSetting& t) {
    const int holder = d_.tool_holders > 1 ? t.pen : 1;
    const std::size_t slot = static_cast<std::size_t>(std::clamp(holder, 1, 2) - 1);
    if (d_.tool_holders > 1 && holder != holder_) {
      w.cmd("J" + std::to_string(holder));
      holder_ = holder;
      if (!d_.tool_in_params) plain_ = {};  // plain FX and ! set the holder selected then
    }
    const std::string suffix = d_.tool_in_params ? "," + std::to_string(holder) : "";
    Levels& lv = d_.tool_in_params ? per_holder_[slot] : plain_;
    const int f = d_.force_level(t.force_g), v = d_.speed_level(t.speed_cm_s);
    if (f != lv.force) w.cmd("FX" + std::to_string(lv.force = f) + suffix);
    if (v != lv.speed) w.cmd("!" + std::to_string(d_.speed_base + (lv.speed = v)) + suffix);
    if (d_.cutter_offset_mm && !offset_sent_[slot]) {
      offset_sent_[slot] = true;
      const long units = std::lround(*d_.cutter_offset_mm / d_.step_mm);  // in steps, uncalibrated
      w.cmd("FC" + std::to_string(units) + (d_.tool_in_params ? ",1" + suffix : ""));
    }
  }

 private:
  struct Levels {
    int force = -1, speed = -1;
  };
  const GpglDialect& d_;
  int holder_ = -1;
  Levels plain_;
  std::array<Levels, 2> per_holder_{};
  std::array<bool, 2> offset_sent_{};
};

void write_finish(Writer& w, const GpglDialect& d) {
  if (d.finish == GpglFinish::origin)
    w.cmd("M" + std::to_string(d.area_min_x_pu) + "," + std::to_string(d.area_min_y_pu));
  if (d.finish == GpglFinish::home) w.cmd("H");
  if (d.tool_holders > 1) w.cmd("J0");  // no holder selected, as the device starts
}

}  // namespace

int GpglDialect::force_level(double force_g) const {
  return level(force_g, force_g_per_level, force_min, force_max, "force", "g", "FX");
}

int GpglDialect::speed_level(double speed_cm_s) const {
  return level(speed_cm_s, speed_cm_s_per_level, speed_min, speed_max, "speed", "cm/s", "!");
}

EncodedJob encode_gpgl_job(const StrokePlan& plan, const GpglDialect& d, const std::array<ToolSetting, 4>& tools,
                           std::size_t from_stroke) {
  const Rect frame = plan.extent();
  const Placement placement = place_sheet(frame, d);
  Writer w;
  write_setup(w, d);
  ToolState tool(d);
  std::optional<ToolSetting> setting;  // the one last sent, re-sent where a stroke's differs
  const std::size_t per_cmd = static_cast<std::size_t>(std::max(1, d.max_pairs_per_command));
  EncodedJob job;
  job.first_stroke = from_stroke;
  std::size_t number = 0;  // of the stroke at hand, as users count them
  for (const Stroke& s : plan.strokes) {
    // The same rounding as plan_in_plotter_units: a stroke that rounds to one point is not sent.
    const PlotterPath pts = stroke_in_plotter_units(s, frame, placement, d);
    if (pts.size() < 2) continue;
    if (++number < from_stroke) continue;
    const ToolSetting& t = tool_for_stroke(tools, s);
    if (!setting || !(*setting == t)) {
      setting = t;
      tool.select(w, t);
    }
    w.cmd("M" + pairs(pts, 0, 1));
    job.stroke_cut_start.push_back(w.size());  // the knife goes down with the next command
    for (std::size_t i = 1; i < pts.size(); i += per_cmd) w.cmd("D" + pairs(pts, i, std::min(pts.size(), i + per_cmd)));
    job.stroke_end.push_back(w.size());
  }
  if (from_stroke < 1 || from_stroke > std::max<std::size_t>(number, 1)) {
    throw Error(ErrorCode::invalid_input, "", "resume",
                "cannot start from stroke " + std::to_string(from_stroke) + ": the job has " + std::to_string(number) +
                    " strokes, numbered from 1");
  }
  write_finish(w, d);
  job.total_strokes = number;
  job.bytes = w.take();
  job.command_end = w.take_ends();
  return job;
}

}  // namespace popcut
