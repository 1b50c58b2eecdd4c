// USB backend left out of this build (POPCUT_WITH_USB=OFF): usb: devices are refused.
#include "backends.h"
#include "popcut/drivers/ports.h"

namespace popcut::drivers {

std::unique_ptr<Transport> make_usb_transport(const DeviceAddress& address, const DeviceProfile&,
                                              TransportStatus& status) {
  status = {TransportError::unsupported, 0,
            address.text + ": this popcut was built without USB support (POPCUT_WITH_USB=OFF; needs libusb-1.0)"};
  return nullptr;
}

}  // namespace popcut::drivers

namespace popcut::drivers {

TransportStatus list_usb_devices(std::vector<UsbDeviceInfo>& out) {
  out.clear();
  return {TransportError::unsupported, 0, "this popcut was built without USB support (POPCUT_WITH_USB=OFF)"};
}

}  // namespace popcut::drivers
