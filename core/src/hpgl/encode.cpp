// HP-GL encoder: the plan's strokes in plotter units (plotter_frame.h), written in one device's dialect.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "popcut/error.h"
#include "popcut/hpgl/hpgl.h"

namespace popcut {
namespace {

class Writer {
 public:
  explicit Writer(const HpglDialect& d) : d_(d) {}
  void raw(const std::string& s) {
    out_ += s;
    mark();
  }
  void cmd(const std::string& s) {
    out_ += s;
    out_ += d_.terminator;
    if (d_.newline) out_ += '\n';
    mark();
  }
  std::size_t size() const { return out_.size(); }
  std::string take() { return std::move(out_); }
  std::vector<std::size_t> take_ends() { return std::move(ends_); }

 private:
  void mark() {
    if (ends_.empty() || ends_.back() != out_.size()) ends_.push_back(out_.size());
  }
  const HpglDialect& d_;
  std::string out_;
  std::vector<std::size_t> ends_;
};

std::string pairs(const std::vector<std::array<std::int64_t, 2>>& pts, std::size_t from, std::size_t to) {
  std::string s;
  for (std::size_t i = from; i < to; ++i) {
    if (i > from) s += ',';
    s += std::to_string(pts[i][0]) + "," + std::to_string(pts[i][1]);
  }
  return s;
}

}  // namespace

std::string encode_hpgl(const StrokePlan& plan, const HpglDialect& d, const std::array<ToolSetting, 4>& tools) {
  return encode_job(plan, d, tools).bytes;
}

EncodedJob encode_job(const StrokePlan& plan, const HpglDialect& d, const std::array<ToolSetting, 4>& tools,
                      std::size_t from_stroke) {
  const Rect frame = plan.extent();
  const Placement placement = place_sheet(frame, d);
  Writer w(d);
  w.raw(d.init);
  const bool relative = d.coords == CoordMode::relative;
  const bool inline_xy = d.move_style == MoveStyle::inline_xy;
  const std::size_t per_cmd = static_cast<std::size_t>(std::max(1, d.max_pairs_per_command));
  if (inline_xy) w.cmd(relative ? "PR" : "PA");
  bool known = false;  // the first move is absolute in every dialect: it fixes the position
  std::array<std::int64_t, 2> at{0, 0};
  int pen = -1;
  long speed = -1, force = -1;
  std::optional<ToolSetting> setting;  // the one last sent, re-sent where a stroke's differs

  // Moves (pen up or down) through `pts`; relative deltas come from the rounded absolutes.
  const auto move = [&](bool down, const std::vector<std::array<std::int64_t, 2>>& abs_pts) {
    std::vector<std::array<std::int64_t, 2>> pts = abs_pts;
    bool as_relative = relative && known;
    if (relative && !known) {
      // Fix the position with one absolute pen-up move, then go relative.
      if (inline_xy) {
        w.cmd("PA");
        w.cmd("PU" + pairs(pts, 0, 1));
        w.cmd("PR");
      } else {
        w.cmd("PU");
        w.cmd("PA" + pairs(pts, 0, 1));
      }
      at = pts.front();
      known = true;
      if (!down) return;
      pts.erase(pts.begin());
      as_relative = true;
    }
    if (as_relative) {
      for (auto& p : pts) {
        const std::array<std::int64_t, 2> abs = p;
        p = {abs[0] - at[0], abs[1] - at[1]};
        at = abs;
      }
    } else {
      at = pts.back();
      known = true;
    }
    const char* pen_cmd = down ? "PD" : "PU";
    const char* coord_cmd = as_relative ? "PR" : "PA";
    if (!inline_xy) w.cmd(pen_cmd);
    for (std::size_t i = 0; i < pts.size(); i += per_cmd) {
      const std::string xy = pairs(pts, i, std::min(pts.size(), i + per_cmd));
      w.cmd((inline_xy ? std::string(pen_cmd) : std::string(coord_cmd)) + xy);
    }
  };

  EncodedJob job;
  job.first_stroke = from_stroke;
  const std::size_t number =
      for_each_stroke_from(plan, frame, placement, d, from_stroke, [&](const Stroke& s, const PlotterPath& pts) {
        const ToolSetting& t = tool_for_stroke(tools, s);
        if (!setting || !(*setting == t)) {
          setting = t;
          if (t.pen != pen) w.cmd("SP" + std::to_string(pen = t.pen));
          const long v = std::max(1L, std::lround(t.speed_cm_s));
          if (d.velocity && v != speed) w.cmd("VS" + std::to_string(speed = v));
          const long f = std::max(1L, std::lround(t.force_g / d.force_g_per_unit));
          if (d.force != ForceStyle::none && f != force)
            w.cmd((d.force == ForceStyle::roland ? "!FS" : "FS") + std::to_string(force = f));
        }
        move(false, {pts.front()});
        job.stroke_cut_start.push_back(w.size());  // the knife goes down with the next command
        move(true, PlotterPath(pts.begin() + 1, pts.end()));
        job.stroke_end.push_back(w.size());
      });
  w.raw(d.finish);
  job.total_strokes = number;
  job.bytes = w.take();
  job.command_end = w.take_ends();
  return job;
}

}  // namespace popcut
