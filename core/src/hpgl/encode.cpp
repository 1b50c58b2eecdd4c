// HP-GL encoder: rounds every point once to absolute plotter units, then writes the dialect.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "popcut/error.h"
#include "popcut/hpgl/hpgl.h"

namespace popcut {
namespace {

std::string mm_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

// Local sheet coordinates (mm from the min corner) along the plotter's x and y axes.
std::array<double, 2> along_axes(Point2 p, const Rect& sheet, const HpglDialect& d) {
  const double dx = p.x_mm - sheet.min.x_mm, dv = p.v_mm - sheet.min.v_mm;
  if (d.swap_axes) return {dv, dx};
  return {dx, dv};
}

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

PlotterPath rounded(const Stroke& s, const Rect& sheet, const Placement& placement, const HpglDialect& d) {
  PlotterPath pts;
  for (Point2 p : s.points) {
    const auto q = to_plotter(p, sheet, placement, d);
    if (q[0] < d.area_min_x_pu || q[0] > d.area_max_x_pu || q[1] < d.area_min_y_pu || q[1] > d.area_max_y_pu ||
        (!d.allow_negative && (q[0] < 0 || q[1] < 0))) {
      throw Error(ErrorCode::internal, "", "hpgl", "point (" + std::to_string(q[0]) + ", " + std::to_string(q[1]) +
                                                       ") plotter units lies outside the usable area; not sent");
    }
    if (pts.empty() || pts.back() != q) pts.push_back(q);
  }
  return pts;
}

}  // namespace

std::vector<PlotterPath> plan_in_plotter_units(const StrokePlan& plan, const HpglDialect& d) {
  // The frame placed is the sheet and everything the knife's axis visits (drag-knife arcs).
  const Rect frame = plan.extent();
  const Placement placement = place_sheet(frame, d);
  std::vector<PlotterPath> out;
  for (const Stroke& s : plan.strokes) {
    PlotterPath p = rounded(s, frame, placement, d);
    if (p.size() >= 2) out.push_back(std::move(p));
  }
  return out;
}

StrokePlan drop_below_resolution(const StrokePlan& plan, const HpglDialect& d) {
  const Rect frame = plan.extent();
  const Placement placement = place_sheet(frame, d);
  StrokePlan out = plan;
  // The frame placed stays the same (a dropped stroke may have reached past the sheet), so every
  // kept point rounds exactly as it did.
  out.sheet = frame;
  out.strokes.clear();
  for (KindStats& k : out.kinds) k.strokes = k.pen_lifts = k.precuts = 0, k.cut_mm = k.travel_mm = 0;
  Point2 at = plan.home;
  for (const Stroke& s : plan.strokes) {
    KindStats& k = out.kinds[index_of(s.kind)];
    if (rounded(s, frame, placement, d).size() < 2) {
      ++k.strokes_below_resolution;
      continue;
    }
    // Travel to a kind's strokes counts for that kind, as in plan_strokes.
    k.travel_mm += travel_mm({s.points}, at);
    k.cut_mm += path_length_mm(s.points);
    ++(s.precut ? k.precuts : k.strokes);
    ++k.pen_lifts;
    at = s.points.back();
    out.strokes.push_back(s);
  }
  return out;
}

Placement place_sheet(const Rect& sheet, const HpglDialect& d) {
  const std::array<double, 2> size = along_axes(sheet.max, sheet, d);
  Placement p;
  p.width_pu = std::llround(size[0] * d.units_per_mm_x);
  p.height_pu = std::llround(size[1] * d.units_per_mm_y);
  const std::int64_t avail_x = d.area_max_x_pu - d.area_min_x_pu, avail_y = d.area_max_y_pu - d.area_min_y_pu;
  if (p.width_pu > avail_x || p.height_pu > avail_y) {
    throw Error(ErrorCode::invalid_input, "", "usable area",
                "the sheet (" + mm_text(size[0]) + " x " + mm_text(size[1]) + " mm on the plotter's axes) does not fit the "
                "usable area (" + mm_text(static_cast<double>(avail_x) / d.units_per_mm_x) + " x " +
                mm_text(static_cast<double>(avail_y) / d.units_per_mm_y) + " mm)");
  }
  // The sheet sits in the corner the axes grow from: the usable area's min, or max when flipped.
  p.origin_x_pu = d.flip_x ? d.area_max_x_pu : d.area_min_x_pu;
  p.origin_y_pu = d.flip_y ? d.area_max_y_pu : d.area_min_y_pu;
  return p;
}

std::array<std::int64_t, 2> to_plotter(Point2 pt, const Rect& sheet, const Placement& p, const HpglDialect& d) {
  const std::array<double, 2> a = along_axes(pt, sheet, d);
  const std::int64_t x = std::llround(a[0] * d.units_per_mm_x), y = std::llround(a[1] * d.units_per_mm_y);
  return {d.flip_x ? p.origin_x_pu - x : p.origin_x_pu + x, d.flip_y ? p.origin_y_pu - y : p.origin_y_pu + y};
}

std::size_t EncodedJob::last_stroke_within(std::size_t bytes_sent) const {
  const auto it = std::upper_bound(stroke_end.begin(), stroke_end.end(), bytes_sent);
  return first_stroke - 1 + static_cast<std::size_t>(it - stroke_end.begin());
}

std::size_t EncodedJob::command_boundary_at_or_after(std::size_t offset) const {
  if (offset == 0) return 0;  // before the first command
  const auto it = std::lower_bound(command_end.begin(), command_end.end(), offset);
  return it == command_end.end() ? bytes.size() : *it;
}

std::string encode_hpgl(const StrokePlan& plan, const HpglDialect& d, const std::array<ToolSetting, 4>& tools) {
  return encode_job(plan, d, tools).bytes;
}

EncodedJob encode_job(const StrokePlan& plan, const HpglDialect& d, const std::array<ToolSetting, 4>& tools, std::size_t from_stroke) {
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
  std::size_t kind = 99;

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
  std::size_t number = 0;  // of the stroke at hand, as users count them
  for (const Stroke& s : plan.strokes) {
    // The same rounding as plan_in_plotter_units: a stroke that rounds to one point is not sent.
    const PlotterPath pts = rounded(s, frame, placement, d);
    if (pts.size() < 2) continue;
    // Strokes before from_stroke leave no trace: tool, position and mode state start afresh.
    if (++number < from_stroke) continue;
    const std::size_t k = index_of(s.kind);
    if (k != kind) {
      kind = k;
      const ToolSetting& t = tools[k];
      if (t.pen != pen) w.cmd("SP" + std::to_string(pen = t.pen));
      const long v = std::max(1L, std::lround(t.speed_cm_s));
      if (d.velocity && v != speed) w.cmd("VS" + std::to_string(speed = v));
      const long f = std::max(1L, std::lround(t.force_g / d.force_g_per_unit));
      if (d.force != ForceStyle::none && f != force) w.cmd((d.force == ForceStyle::roland ? "!FS" : "FS") + std::to_string(force = f));
    }
    move(false, {pts.front()});
    job.stroke_cut_start.push_back(w.size());  // the knife goes down with the next command
    move(true, PlotterPath(pts.begin() + 1, pts.end()));
    job.stroke_end.push_back(w.size());
  }
  if (from_stroke < 1 || from_stroke > std::max<std::size_t>(number, 1)) {
    throw Error(ErrorCode::invalid_input, "", "resume",
                "cannot start from stroke " + std::to_string(from_stroke) + ": the job has " + std::to_string(number) +
                    " strokes, numbered from 1");
  }
  w.raw(d.finish);
  job.total_strokes = number;
  job.bytes = w.take();
  job.command_end = w.take_ends();
  return job;
}

}  // namespace popcut
