// The daemon's one seam to a cutter: send an encoded job, report strokes fully sent, stop safely on request.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <vector>
#include <string>

#include "config.h"
#include "cut_job.h"
#include "popcut/drivers/sim_cutter.h"

namespace popcut::daemon {

struct CutOutcome {
  enum class Kind { complete, stopped, failed } kind = Kind::failed;
  std::size_t strokes_sent = 0;  // of the job given (which may start at a resumed stroke)
  std::string error;             // failed: what the transport said
  // sim devices: the knife-down paths the simulated cutter made (complete cuts only), for the
  // caller to hold against its plan
  std::optional<std::vector<drivers::SimStroke>> sim_cut;
};

class DeviceLink {
 public:
  virtual ~DeviceLink() = default;
  // Sends `job`; `progress` after every stroke fully sent. When `stop` becomes true the command
  // in flight is completed, the knife lifted and the tool put away (the profile's finish), and
  // the outcome is `stopped`.
  virtual CutOutcome cut(const EncodedCut& job, const std::atomic<bool>& stop,
                         const std::function<void(std::size_t strokes_sent)>& progress) = 0;
  virtual std::string describe() const = 0;
};

// sim (a simulated cutter per job, optionally paced to wall-clock time) or file:PATH.
std::unique_ptr<DeviceLink> make_device_link(const DeviceConfig& device);

}  // namespace popcut::daemon
