// Discovery of cutters: serial ports (with their USB ids) and USB devices, for `popcut devices` and serial:VID:PID.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "popcut/drivers/transport.h"

namespace popcut::drivers {

struct SerialPortInfo {
  std::string path;                       // /dev/ttyUSB0
  std::string description;                // what the OS calls it
  std::optional<std::uint16_t> vid, pid;  // USB adapters only
  std::string serial_number;
};

struct UsbDeviceInfo {
  std::uint16_t vid = 0, pid = 0;
  int bus = 0, address = 0;
  std::string serial_number;  // empty when it has none or cannot be opened to read it
  std::string product;
  bool has_bulk_out = false;  // speaks to a host over a bulk OUT endpoint (printer-like)
};

// Serial ports the OS knows (libserialport); unsupported when built without it.
TransportStatus list_serial_ports(std::vector<SerialPortInfo>& out);
// USB devices on every bus (libusb); unsupported when built without it.
TransportStatus list_usb_devices(std::vector<UsbDeviceInfo>& out);

}  // namespace popcut::drivers
