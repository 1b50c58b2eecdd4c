// The cutter language a device profile names, as the drivers see it: its profile section, encoder and simulator reader.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "popcut/drivers/device_reader.h"
#include "popcut/drivers/profile.h"
#include "popcut/lang/encoder.h"

namespace popcut::drivers {

class TomlSection;

// ---- The host's side of a language: what the sender says to a device besides the job. ----

// What a status answer says of the device beyond its number, as its language reads it.
// idle: it has executed everything it received before the query; busy: not yet; tray_empty: no
// sheet is loaded (it cuts nothing); paused: its pause key or a menu holds it; line_garbled and
// input_lost: an I/O error answer (framing or parity; a buffer overflow) says job bytes were lost.
enum class StatusMeaning { nothing, idle, busy, tray_empty, paused, line_garbled, input_lost };

// How a byte of the device's reply reads: part of an answer, the end of one, or filler.
enum class ReplyByte { part, end, skip };

// The sender's half of a language's conversation with a device (the simulator's half is its
// DeviceReader): the bytes of each status query, how an answer is framed and what it means, and
// which bytes of a string enter the device's buffer.
class HostProtocol {
 public:
  virtual ~HostProtocol() = default;
  // The bytes that ask `query`; empty when the language has no such query.
  virtual std::string_view query_bytes(DrainQuery query) const = 0;
  // As users know it from the device's manual: "ESC.B", "ESC ENQ".
  virtual std::string_view query_name(DrainQuery query) const = 0;
  virtual ReplyByte reply_byte(char byte) const = 0;
  // The number an answer carries (its end byte and filler left out); nullopt when it is none.
  virtual std::optional<long> read_answer(std::string_view text) const = 0;
  // What answer `value` to `query` says (nothing: only its number, as ESC.B's free bytes).
  virtual StatusMeaning meaning(DrainQuery query, long value) const = 0;
  // How many bytes of `bytes` enter the device's buffer: device-control sequences never do.
  virtual std::size_t buffered_bytes(std::string_view bytes) const = 0;
  // Said when a device never gave a status answer this language reads (`heard`: what it sent,
  // empty for silence): why it may be a device of another language, or "" when nothing points so.
  virtual std::string mismatch_hint(std::string_view heard) const = 0;
  // The drain query a profile of this language gets when it names none (none: do not ask).
  virtual DrainQuery default_query() const = 0;
  // The job's init resets the device and drops what its buffer holds (GP-GL's ESC EOT): a job
  // must not start while the device still cuts an earlier one.
  virtual bool init_resets_device() const = 0;
};

// One language's part in the drivers; each language unit defines one (hpgl_language.cpp,
// gpgl_language.cpp). The CLI and the daemon never see it: they go through make_encoder /
// encode_for_device; the sender sees only its knife-up and host protocol.
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
  // The job's finish on its own: where it leaves the head is where a job of a [kinematics]
  // starts_at = "origin" device starts, so a cancel sends it after the knife-up too.
  std::string (*park)(const DeviceProfile& profile);
  const HostProtocol& (*host)();  // the sender's side: status queries and their answers
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
