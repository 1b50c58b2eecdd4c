// Serial port discovery through libserialport: names, descriptions and the USB ids of adapters.
#include <libserialport.h>

#include "popcut/drivers/ports.h"

namespace popcut::drivers {

TransportStatus list_serial_ports(std::vector<SerialPortInfo>& out) {
  out.clear();
  sp_port** ports = nullptr;
  if (sp_list_ports(&ports) != SP_OK) {
    char* msg = sp_last_error_message();
    TransportStatus st{TransportError::io, sp_last_error_code(),
                       std::string("cannot list serial ports: ") + (msg ? msg : "?")};
    sp_free_error_message(msg);
    return st;
  }
  for (sp_port** p = ports; *p; ++p) {
    SerialPortInfo info;
    info.path = sp_get_port_name(*p);
    if (const char* d = sp_get_port_description(*p)) info.description = d;
    int vid = 0, pid = 0;
    if (sp_get_port_transport(*p) == SP_TRANSPORT_USB && sp_get_port_usb_vid_pid(*p, &vid, &pid) == SP_OK &&
        (vid || pid)) {
      info.vid = static_cast<std::uint16_t>(vid);
      info.pid = static_cast<std::uint16_t>(pid);
      if (const char* s = sp_get_port_usb_serial(*p)) info.serial_number = s;
    }
    out.push_back(std::move(info));
  }
  sp_free_port_list(ports);
  return TransportStatus::success();
}

}  // namespace popcut::drivers
