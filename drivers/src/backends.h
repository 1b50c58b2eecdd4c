// Constructors of the optional backends; each lives in its own file, swapped by CMake options.
#pragma once

#include <memory>

#include "popcut/drivers/device.h"

namespace popcut::drivers {

// libserialport (serial_transport.cpp) or a stand-in refusing with `unsupported`.
std::unique_ptr<Transport> make_serial_transport(const DeviceAddress& address, const DeviceProfile& profile,
                                                 TransportStatus& status);
// libusb (usb_transport.cpp) or a stand-in refusing with `unsupported`.
std::unique_ptr<Transport> make_usb_transport(const DeviceAddress& address, const DeviceProfile& profile,
                                              TransportStatus& status);

}  // namespace popcut::drivers
