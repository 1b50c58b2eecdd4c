// Serial backend left out of this build (POPCUT_WITH_SERIAL=OFF): serial: devices are refused.
#include "backends.h"

namespace popcut::drivers {

std::unique_ptr<Transport> make_serial_transport(const DeviceAddress& address, const DeviceProfile&,
                                                 TransportStatus& status) {
  status = {
      TransportError::unsupported, 0,
      address.text + ": this popcut was built without serial support (POPCUT_WITH_SERIAL=OFF; needs libserialport)"};
  return nullptr;
}

}  // namespace popcut::drivers
