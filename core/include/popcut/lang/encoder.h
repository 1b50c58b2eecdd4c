// The cutter-language seam: a stroke plan in, one language's job bytes and their stroke offsets out.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "popcut/names.h"
#include "popcut/plan/plan.h"

namespace popcut {

// The languages popcut writes jobs in; a device profile names one ([device] language).
enum class CutterLanguage { hpgl, gpgl };
inline constexpr auto kCutterLanguageNames =
    enum_names<CutterLanguage>({{CutterLanguage::hpgl, "hpgl"}, {CutterLanguage::gpgl, "gpgl"}});

// The name popcut gives a job file of `language` in an output directory: job.hpgl, job.gpgl.
inline std::string job_file_name(CutterLanguage language) {
  return "job." + std::string(kCutterLanguageNames.name(language));
}

// The tool one line kind uses: pen (tool slot), force and speed, and optionally its own force
// and speed for each pass (strokes planned with KindPlan::separate_passes carry Stroke::pass).
struct ToolSetting {
  int pen = 1;
  double force_g = 100;
  double speed_cm_s = 10;
  std::vector<double> pass_force_g{};     // [pass]; empty, or a pass past its end: force_g
  std::vector<double> pass_speed_cm_s{};  // [pass]; empty, or a pass past its end: speed_cm_s
  friend bool operator==(const ToolSetting&, const ToolSetting&) = default;
};

// The tool setting a stroke is cut with: its kind's, with its pass's force and speed, and no
// per-pass lists. Encoders ask this for every stroke and re-send pen, force and speed where the
// answer changes, so per-pass settings need no encoder of their own.
ToolSetting tool_for_stroke(const std::array<ToolSetting, 4>& tools, const Stroke& stroke);

// Stroke numbers, the one numbering users see (progress, errors, --resume-from): stroke N is the
// N-th path of plan_in_plotter_units(plan, frame), counted from 1 — the knife-down paths actually
// sent, in cutting order. Strokes that round to a single point are not numbered.
//
// A job's bytes together with where its commands and strokes end, so that "bytes the device has
// received" translates into "strokes fully sent", and a sender can stop between commands. Every
// language fills it the same way, so the sender never needs to know which one wrote the bytes.
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

// One cutter language bound to one device's dialect. An implementation sends exactly the strokes
// of plan_in_plotter_units (same rounding, same numbering), so resume points and figures agree
// whatever the language.
class JobEncoder {
 public:
  virtual ~JobEncoder() = default;
  virtual CutterLanguage language() const = 0;
  // The job from stroke `from_stroke` on: set-up, per kind tool selection, strokes
  // from_stroke..total, finish. Throws popcut::Error when a point would leave the usable area,
  // and invalid_input ("resume") when from_stroke is 0 or past the last stroke.
  virtual EncodedJob encode(const StrokePlan& plan, const std::array<ToolSetting, 4>& tools,
                            std::size_t from_stroke) const = 0;
};

}  // namespace popcut
