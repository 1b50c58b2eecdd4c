// HP-GL encoding of a stroke plan in one device's dialect: plotter units, placement, tool commands.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "popcut/names.h"
#include "popcut/plan/plan.h"

namespace popcut {

enum class MoveStyle { separate, inline_xy };  // "PU;PAx,y;" versus "PUx,y;"
enum class CoordMode { absolute, relative };
enum class ForceStyle { none, fs, roland };    // "FSn;" or Roland's "!FSn;" (CAMM-GL)
// The names device profiles use.
inline constexpr auto kMoveStyleNames =
    enum_names<MoveStyle>({{MoveStyle::separate, "separate"}, {MoveStyle::inline_xy, "inline"}});
inline constexpr auto kCoordModeNames =
    enum_names<CoordMode>({{CoordMode::absolute, "absolute"}, {CoordMode::relative, "relative"}});
inline constexpr auto kForceStyleNames =
    enum_names<ForceStyle>({{ForceStyle::none, "none"}, {ForceStyle::fs, "fs"}, {ForceStyle::roland, "roland"}});

// Everything about the bytes a device expects; values only, filled from a device profile.
struct HpglDialect {
  double units_per_mm_x = 40;  // calibratable: real devices differ by about 0.5 %
  double units_per_mm_y = 40;
  bool swap_axes = false;      // plotter x runs along the pattern's v; alone a mirror, with one flip a quarter turn
  bool flip_x = false;         // plotter x grows the other way (after any swap)
  bool flip_y = false;
  std::int64_t area_min_x_pu = 0, area_min_y_pu = 0;  // usable area, in plotter units
  std::int64_t area_max_x_pu = 0, area_max_y_pu = 0;
  bool allow_negative = false;
  std::string init = "IN;";
  std::string finish = "PU;SP0;";
  MoveStyle move_style = MoveStyle::separate;
  CoordMode coords = CoordMode::absolute;
  std::string terminator = ";";
  bool newline = false;        // a newline after every command (some serial firmwares want lines)
  bool velocity = true;        // VS supported
  ForceStyle force = ForceStyle::fs;
  double force_g_per_unit = 1; // the force command's unit, in grams (Graphtec levels are coarse)
  int max_pairs_per_command = 64;
};

// The tool one line kind uses: pen (SP), force and speed.
struct ToolSetting {
  int pen = 1;
  double force_g = 100;
  double speed_cm_s = 10;
};

// Where the sheet's min corner lands, in absolute plotter units, and how pattern mm map there.
struct Placement {
  std::int64_t origin_x_pu = 0, origin_y_pu = 0;
  std::int64_t width_pu = 0, height_pu = 0;  // the sheet's extent on the plotter axes
};

// Puts `sheet` (the encoder passes StrokePlan::extent(): the sheet and any drag-knife arcs past
// its edge) at the usable area's origin corner; throws popcut::Error (invalid_input) when it does
// not fit, naming both sizes in mm.
Placement place_sheet(const Rect& sheet, const HpglDialect& dialect);

// Absolute plotter coordinates of a pattern point, rounded once (every move derives from these).
std::array<std::int64_t, 2> to_plotter(Point2 p, const Rect& sheet, const Placement& placement, const HpglDialect& dialect);

using PlotterPath = std::vector<std::array<std::int64_t, 2>>;

// Every stroke in absolute plotter units, consecutive repeats merged and strokes that round to a
// single point dropped: exactly the knife-down paths the encoder sends (and a device should cut).
// Throws popcut::Error when a point would leave the usable area (never sent).
std::vector<PlotterPath> plan_in_plotter_units(const StrokePlan& plan, const HpglDialect& dialect);

// The plan as the device will get it: strokes that round to a single plotter point (the encoder
// never sends them) are removed and counted in strokes_below_resolution; strokes, pen_lifts,
// cut_mm and travel_mm are recomputed from what is left. Throws like plan_in_plotter_units.
StrokePlan drop_below_resolution(const StrokePlan& plan, const HpglDialect& dialect);

// Stroke numbers, the one numbering users see (progress, errors, --resume-from): stroke N is the
// N-th path of plan_in_plotter_units(plan, dialect), counted from 1 — the knife-down paths
// actually sent, in cutting order. Strokes that round to a single point are not numbered.
//
// A job's bytes together with where its commands and strokes end, so that "bytes the device has
// received" translates into "strokes fully sent", and a sender can stop between commands.
struct EncodedJob {
  std::string bytes;
  std::size_t first_stroke = 1;   // number of the first stroke these bytes carry
  std::size_t total_strokes = 0;  // strokes in the whole plan (numbers 1..total_strokes)
  // stroke_end[i]: offset just past the last command of stroke first_stroke + i.
  std::vector<std::size_t> stroke_end;
  // stroke_cut_start[i]: offset of the knife-down command of stroke first_stroke + i; the bytes
  // before it (tool set-up, knife-up travel) cut nothing. Empty for raw bytes with no strokes.
  std::vector<std::size_t> stroke_cut_start;
  // Offsets just past every command (init and finish count as one each), ascending; the last is
  // bytes.size(). A sender that stops at one of these leaves no command half-sent.
  std::vector<std::size_t> command_end;

  // Number of the last stroke whose commands lie entirely within the first `bytes_sent` bytes;
  // first_stroke - 1 when none does (0 for a job from the start).
  std::size_t last_stroke_within(std::size_t bytes_sent) const;
  // The first command boundary at or after `offset` (0 is one; bytes.size() past the end).
  std::size_t command_boundary_at_or_after(std::size_t offset) const;
};

// The job from stroke `from_stroke` on: init, per kind tool selection, strokes from_stroke..total,
// finish. From a later stroke the job re-sends init and the tool setup of that stroke's kind and
// travels to it with the knife up (every stroke starts with a pen-up move), so `--resume-from N`
// cuts exactly strokes N.. . Throws popcut::Error when a point would leave the usable area (never
// sent), and invalid_input ("resume") when from_stroke is 0 or past the last stroke.
EncodedJob encode_job(const StrokePlan& plan, const HpglDialect& dialect, const std::array<ToolSetting, 4>& tools,
                      std::size_t from_stroke = 1);

// The whole job's bytes: encode_job(plan, dialect, tools).bytes.
std::string encode_hpgl(const StrokePlan& plan, const HpglDialect& dialect, const std::array<ToolSetting, 4>& tools);

}  // namespace popcut
