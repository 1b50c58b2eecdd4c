// Blade and mat wear: what a run of a job cut, by tool mode, counted from the strokes the device certainly took.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "device_link.h"
#include "popcut/plan/plan.h"

namespace popcut::daemon {

// Knife-down length by what the knife did (cut through, score, perforation dashes) and the
// knife-down strokes of every mode. Precuts count as the cuts they are.
struct Wear {
  double cut_mm = 0, score_mm = 0, perforate_mm = 0;
  std::int64_t knife_down_strokes = 0;
  Wear& operator+=(const Wear& o);
};

// Strokes first..last (numbered from 1, as sent) of `plan`, each by its kind's mode in `kinds`
// (the job's profile with its material); skipped kinds are never in a plan.
Wear wear_of(const StrokePlan& plan, const std::array<KindPlan, 4>& kinds, std::size_t first, std::size_t last);

// The last stroke a run that started at `first_stroke` is credited with: every stroke of a
// complete cut; else the last the device is known to have executed, else the last it certainly
// received. Never more: a resume that cuts some strokes again counts them in its own run.
std::size_t wear_counted_through(const CutOutcome& out, std::size_t first_stroke);

// One device's counters: since the blade was last changed, and over its whole life (never reset).
struct DeviceWear {
  std::string name;
  Wear blade;            // since `since`
  Wear lifetime;         // since the device was first counted
  double since_s = 0;    // unix seconds of the last reset (or of the first count); 0: never counted
  double worn_at_s = 0;  // when the blade passed blade_life_m (blade_worn was raised); 0: not yet
};

// Whether the blade has passed its life (none configured: never).
bool blade_worn(const DeviceWear& w, std::optional<double> blade_life_m);

}  // namespace popcut::daemon
