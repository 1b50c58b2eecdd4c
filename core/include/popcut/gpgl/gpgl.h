// GP-GL (Graphtec, Silhouette) encoding of a stroke plan in one device's dialect, and the encoder behind the seam.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "popcut/lang/encoder.h"
#include "popcut/lang/plotter_frame.h"
#include "popcut/names.h"
#include "popcut/plan/plan.h"

namespace popcut {

// GP-GL ends every command with ETX; ESC sequences are device control and take none.
inline constexpr char kGpglEtx = '\x03';
inline constexpr char kGpglEsc = '\x1b';
inline constexpr char kGpglEot = '\x04';  // ESC EOT: initialise the device
inline constexpr char kGpglEnq = '\x05';  // ESC ENQ: the device's state, answered at once

// The command that brings the head home after the initialisation: Silhouette's TT, Graphtec's
// H, or none (newer Silhouette firmware homes on ESC EOT).
enum class GpglHome { none, tt, h };
inline constexpr auto kGpglHomeNames =
    enum_names<GpglHome>({{GpglHome::none, "none"}, {GpglHome::tt, "tt"}, {GpglHome::h, "h"}});

// Where the head goes when the job is done: the sheet's origin corner with the knife up
// ("M" to the usable area's min corner), Graphtec's home (H), or nowhere.
enum class GpglFinish { origin, home, none };
inline constexpr auto kGpglFinishNames =
    enum_names<GpglFinish>({{GpglFinish::origin, "origin"}, {GpglFinish::home, "home"}, {GpglFinish::none, "none"}});

enum class GpglOrientation { portrait, landscape };  // FN0, FN1
inline constexpr auto kGpglOrientationNames =
    enum_names<GpglOrientation>({{GpglOrientation::portrait, "portrait"}, {GpglOrientation::landscape, "landscape"}});

// Everything about the GP-GL bytes a device expects; values only, filled from a device profile's
// [gpgl]. The frame part (units, axes, area) is [device]'s, shared with every language.
struct GpglDialect : PlotterFrame {
  double step_mm = 0.05;  // the device's GP-GL step (a panel setting on Graphtec cutters)
  GpglHome home = GpglHome::none;
  GpglFinish finish = GpglFinish::origin;
  int tool_holders = 1;         // 2: J selects the holder (dual-carriage Silhouettes)
  bool tool_in_params = false;  // FXn,t and !n,t name the holder (Cameo 3 and later)
  int force_min = 1, force_max = 33;
  double force_g_per_level = 7;  // grams one FX level presses
  int speed_min = 1, speed_max = 10;
  double speed_cm_s_per_level = 1;         // cm/s one ! level moves
  int speed_base = 0;                      // ! sends base + level: 100 for Graphtec's "!101..!160 are cm/s"
  std::optional<double> cutter_offset_mm;  // FC in plotter units; unset: not sent
  std::optional<int> media;                // FW
  std::optional<bool> track_enhancing;     // FY (FY0 turns it on)
  std::optional<GpglOrientation> orientation;
  bool page_size = false;          // FU with the usable area's extent
  std::vector<std::string> setup;  // further set-up commands, each sent with ETX
  int max_pairs_per_command = 32;

  // Levels for a tool setting; throw popcut::Error (invalid_input) naming the setting when it
  // falls outside the device's range.
  int force_level(double force_g) const;
  int speed_level(double speed_cm_s) const;
};

// The job from stroke `from_stroke` on: ESC EOT, home, set-up, per stroke the tool where its
// setting changes (J, FX, !), a knife-up M to its start and D through its points, then finish.
// From a later stroke the job re-sends the initialisation and the tool setup of that stroke and
// travels to it with the knife up, so `--resume-from N` cuts exactly strokes N.. . Throws
// popcut::Error when a point would leave the usable area (never sent), and invalid_input
// ("resume") when from_stroke is 0 or past the last stroke.
EncodedJob encode_gpgl_job(const StrokePlan& plan, const GpglDialect& dialect, const std::array<ToolSetting, 4>& tools,
                           std::size_t from_stroke = 1);

// GP-GL behind the cutter-language seam: encode_gpgl_job in one dialect.
class GpglEncoder final : public JobEncoder {
 public:
  explicit GpglEncoder(GpglDialect dialect) : dialect_(std::move(dialect)) {}
  CutterLanguage language() const override { return CutterLanguage::gpgl; }
  EncodedJob encode(const StrokePlan& plan, const std::array<ToolSetting, 4>& tools,
                    std::size_t from_stroke) const override {
    return encode_gpgl_job(plan, dialect_, tools, from_stroke);
  }

 private:
  GpglDialect dialect_;
};

}  // namespace popcut
