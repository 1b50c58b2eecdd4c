// Device strings (sim, file:PATH, serial:..., usb:...) and the one factory that turns them into a Transport.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/drivers/transport.h"

namespace popcut::drivers {

enum class DeviceKind { sim, file, serial, usb };

// A parsed device string. Forms (VID, PID: four hex digits each, as lsusb prints them):
//   sim                        the simulated cutter, in process
//   file:PATH                  a file or a printer-port node (/dev/usb/lp0)
//   serial:/dev/ttyUSB0        a serial port by name (any path starting with /)
//   serial:VID:PID[:SERIAL]    the serial port of a USB adapter with those ids (and serial number)
//   usb:VID:PID[:SERIAL]       a USB cutter spoken to directly over bulk endpoints
struct DeviceAddress {
  DeviceKind kind = DeviceKind::sim;
  std::string path;                       // file: and serial: by name
  std::optional<std::uint16_t> vid, pid;  // serial: by ids, usb:
  std::string serial_number;              // optional third part of VID:PID:SERIAL
  std::string text;                       // the string as given
};

// Parses a device string; bad_argument with what was expected when it is malformed.
TransportStatus parse_device(std::string_view text, DeviceAddress& out);

// "vvvv:pppp" in lower-case hex.
std::string usb_id_string(std::uint16_t vid, std::uint16_t pid);

struct MadeTransport {
  std::unique_ptr<Transport> transport;  // not yet opened; null when status is not ok
  std::shared_ptr<SimCutter> sim;        // for `sim`: the simulated device, to inspect afterwards
  DeviceAddress address;
  TransportStatus status;
};

// The transport for a device string, configured from the profile's [transport] (baud, framing,
// flow control, USB chunk size). Errors: bad_argument for a malformed string, unsupported for a
// backend this build leaves out (POPCUT_WITH_SERIAL / POPCUT_WITH_USB off). Nothing is opened
// here: open() finds the port or device and reports not_found, permission, busy.
// `sim_faults` apply to `sim` only.
MadeTransport make_transport(std::string_view device, const DeviceProfile& profile, const SimFaults& sim_faults = {});

}  // namespace popcut::drivers
