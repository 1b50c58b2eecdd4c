// The cutter language a device profile names, as the drivers see it: its profile section, encoder and simulator reader.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "popcut/drivers/device_reader.h"
#include "popcut/drivers/profile.h"
#include "popcut/lang/encoder.h"

namespace popcut::drivers {

class TomlSection;

// One language's part in the drivers; each language unit defines one (hpgl_language.cpp, gpgl_language.cpp). The
// sender, the CLI and the daemon never see it: they go through make_encoder / encode_for_device.
struct LanguageUnit {
  CutterLanguage language;
  std::string_view section;  // its profile section: [hpgl], [gpgl]
  // Reads its section into the profile; [device] (the frame) has been read already.
  void (*read_section)(TomlSection& section, DeviceProfile& profile);
  // Refuses a [transport] abort string that could cut on after a cancel, failing at "abort".
  void (*check_abort)(const TomlSection& transport, const std::string& abort);
  std::unique_ptr<JobEncoder> (*make_encoder)(const DeviceProfile& profile);
  std::unique_ptr<DeviceReader> (*make_reader)();
  // Plotter units per mm when the language's section fixes them (GP-GL's step), read before
  // [device]'s frame; nullptr: [device] units_per_mm says.
  double (*units_per_mm)(TomlSection& section);
  // Checks across sections once the whole profile is read (nullptr: none), throwing like the
  // section readers.
  void (*check_profile)(const DeviceProfile& profile);
  // The knife speed in cm/s a speed command's value sets (HP-GL's VS is cm/s; GP-GL's ! a level).
  double (*speed_cm_s)(const DeviceProfile& profile, double value);
  // The command that lifts the knife, sent after [transport] abort when a job is cancelled.
  std::string (*knife_up)(const DeviceProfile& profile);
};

// Every language popcut speaks, in kCutterLanguageNames order.
std::span<const LanguageUnit* const> language_units();
const LanguageUnit& language_unit(CutterLanguage language);

// The encoder of the profile's language, bound to its dialect.
std::unique_ptr<JobEncoder> make_encoder(const DeviceProfile& profile);
// The job for this device from stroke `from_stroke` on, in its language (see JobEncoder::encode).
EncodedJob encode_for_device(const StrokePlan& plan, const DeviceProfile& profile, std::size_t from_stroke = 1);
// A reader of the profile's language, for the simulated cutter.
std::unique_ptr<DeviceReader> make_reader(const DeviceProfile& profile);

}  // namespace popcut::drivers
