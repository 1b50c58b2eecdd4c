// Serial port discovery left out of this build (POPCUT_WITH_SERIAL=OFF).
#include "popcut/drivers/ports.h"

namespace popcut::drivers {

TransportStatus list_serial_ports(std::vector<SerialPortInfo>& out) {
  out.clear();
  return {TransportError::unsupported, 0, "this popcut was built without serial support (POPCUT_WITH_SERIAL=OFF)"};
}

}  // namespace popcut::drivers
