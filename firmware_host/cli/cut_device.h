// What every command that cuts shares (cut, test-cut, calibrate): the device and profile chosen, its checks, the
// simulator's faults, the messages and exit codes of a send.
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "popcut/drivers/cut_session.h"
#include "popcut/drivers/device_plan.h"
#include "popcut/drivers/profile.h"

namespace popcut::cli {

// --sim-stop-after, --sim-drop-after, --sim-tray-empty-after, --sim-pause-after, --sim-slowdown:
// faults for `--device sim` only.
struct SimFaultArgs {
  long stop_answering_after = -1, drop_after = -1;
  long tray_empty_after = -1, pause_after = -1;  // the simulator's own stops (-1: never)
  double slowdown = 1;
  bool any() const {
    return stop_answering_after >= 0 || drop_after >= 0 || tray_empty_after >= 0 || pause_after >= 0 || slowdown != 1;
  }
};

// --material's help, the same on every command that takes one.
extern const char* const kMaterialHelp;

// The profile (with its calibration overlay, as load_profile merges it) and --material's settings
// for its family, when one is given; `material_source` receives the material's file.
drivers::DeviceProfile load_cli_profile(const std::string& profile_path, const std::string& material,
                                        std::string* material_source = nullptr);

// Adds the --sim-* options to `cmd`.
void add_sim_fault_options(CLI::App& cmd, SimFaultArgs& faults);

// The device and profile a cut uses: --device, else the profile's [transport] default; the sim
// profile and `sim` stand in when neither is given.
struct Target {
  std::string device, profile_path, note;
};

// From --device (given: it was on the command line, even empty) and --profile.
Target cut_target(const std::string& device, bool device_given, const std::string& profile_path);

// No --device and no --profile's sim: the profile's [transport] default, said so in `note`.
void use_profile_device(Target& target, const drivers::DeviceProfile& profile);

drivers::CutSessionOptions session_options(const SimFaultArgs& faults);

// The device string made a transport, the --sim-* faults are for the simulator, and a USB
// device is the one the profile is for.
void check_device(const SimFaultArgs& faults, const drivers::CutSession& session, const drivers::DeviceProfile& profile,
                  const Target& target);

// Opens it; a failure is bad input (a malformed device) or kCannotWrite, its class leading the message.
void open_device(drivers::CutSession& session);

// popcut.cut.v1's `sim` object: what the simulated cutter did, held against the plan.
nlohmann::json sim_json(const drivers::SimCutter& cutter, const drivers::SimCheck& check, std::size_t first_stroke);

// A job that did not get through, or was cancelled: the message and exit code; nullopt when it got through.
std::optional<int> stopped_exit(const drivers::SendResult& sent, const drivers::DeviceProfile& profile,
                                std::size_t job_bytes, const std::string& device);

// A complete job on the simulator that did not cut the plan: the message and exit code.
// Commands that cut accept command_errors (the strokes are the plan's; the report lists the
// errors), where popcutd's sim_match asks for `exact`. `report` is named in the message.
std::optional<int> sim_exit(double slowdown, const drivers::DeviceProfile& profile, const drivers::SimCheck& check,
                            const std::string& report);

// Creates `out_dir` and writes the job this run sends into it (job.hpgl or job.gpgl, by `language`);
// returns the directory.
std::filesystem::path write_job_file(const std::string& out_dir, const EncodedJob& encoded, CutterLanguage language);

// A device check's job (test-cut, calibrate) sent as popcut cut sends one, from stroke 1.
struct DeviceRun {
  drivers::SendResult sent;
  std::optional<drivers::SimCheck> check;
  double wall_s = 0;          // from the first byte to the send's end (the device's drain, where it answers)
  double sim_motion_s = 0;    // `sim`: the simulator's own clock of its motion
  std::string described;      // the device as it describes itself
  nlohmann::json sim;         // `sim`: sim_json; else null
  std::optional<int> failed;  // the exit code when the job did not get through or the simulator did not cut it
};

// Makes the session for `target`, checks it, opens it and sends `job` (Ctrl-C cancels safely);
// on `sim` writes cut.svg into `out_dir` when it is not empty. Exit codes as popcut cut's.
DeviceRun run_device_job(const Target& target, const drivers::DeviceProfile& profile, const drivers::DevicePlan& job,
                         const SimFaultArgs& faults, const std::string& out_dir, bool progress_bar);

}  // namespace popcut::cli
