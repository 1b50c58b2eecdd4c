// HP-GL encoding of a stroke plan in one device's dialect: plotter units, placement, tool commands.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "popcut/plan/plan.h"

namespace popcut {

enum class MoveStyle { separate, inline_xy };  // "PU;PAx,y;" versus "PUx,y;"
enum class CoordMode { absolute, relative };
enum class ForceStyle { none, fs, roland };    // "FSn;" or Roland's "!FSn;" (CAMM-GL)

// Everything about the bytes a device expects; values only, filled from a device profile.
struct HpglDialect {
  double units_per_mm_x = 40;  // calibratable: real devices differ by about 0.5 %
  double units_per_mm_y = 40;
  bool swap_axes = false;      // plotter x runs along the pattern's v (e.g. along the media feed)
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

// The job: init, per kind tool selection, every stroke, finish. Throws popcut::Error when a
// point would leave the usable area (never sent).
std::string encode_hpgl(const StrokePlan& plan, const HpglDialect& dialect, const std::array<ToolSetting, 4>& tools);

}  // namespace popcut
