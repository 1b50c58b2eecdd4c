// HP-GL encoding of a stroke plan in one device's dialect: its syntax, tool commands and the encoder behind the seam.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "popcut/lang/encoder.h"
#include "popcut/lang/plotter_frame.h"
#include "popcut/names.h"
#include "popcut/plan/plan.h"

namespace popcut {

enum class MoveStyle { separate, inline_xy };  // "PU;PAx,y;" versus "PUx,y;"
enum class CoordMode { absolute, relative };
enum class ForceStyle { none, fs, roland };  // "FSn;" or Roland's "!FSn;" (CAMM-GL)
// The names device profiles use.
inline constexpr auto kMoveStyleNames =
    enum_names<MoveStyle>({{MoveStyle::separate, "separate"}, {MoveStyle::inline_xy, "inline"}});
inline constexpr auto kCoordModeNames =
    enum_names<CoordMode>({{CoordMode::absolute, "absolute"}, {CoordMode::relative, "relative"}});
inline constexpr auto kForceStyleNames =
    enum_names<ForceStyle>({{ForceStyle::none, "none"}, {ForceStyle::fs, "fs"}, {ForceStyle::roland, "roland"}});

// Everything about the HP-GL bytes a device expects; values only, filled from a device profile.
// The frame part (units, axes, area) comes from [device] and is what every language shares.
struct HpglDialect : PlotterFrame {
  std::string init = "IN;";
  std::string finish = "PU;SP0;";
  MoveStyle move_style = MoveStyle::separate;
  CoordMode coords = CoordMode::absolute;
  std::string terminator = ";";
  bool newline = false;  // a newline after every command (some serial firmwares want lines)
  bool velocity = true;  // VS supported
  ForceStyle force = ForceStyle::fs;
  double force_g_per_unit = 1;  // the force command's unit, in grams (Graphtec levels are coarse)
  int max_pairs_per_command = 64;
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

// HP-GL behind the cutter-language seam: encode_job in one dialect.
class HpglEncoder final : public JobEncoder {
 public:
  explicit HpglEncoder(HpglDialect dialect) : dialect_(std::move(dialect)) {}
  CutterLanguage language() const override { return CutterLanguage::hpgl; }
  EncodedJob encode(const StrokePlan& plan, const std::array<ToolSetting, 4>& tools,
                    std::size_t from_stroke) const override {
    return encode_job(plan, dialect_, tools, from_stroke);
  }

 private:
  HpglDialect dialect_;
};

}  // namespace popcut
