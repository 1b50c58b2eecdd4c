// Device-string parsing and the transport factory shared by `popcut cut` and popcutd.
#include "popcut/drivers/device.h"

#include <cctype>
#include <cstdio>

#include "backends.h"
#include "popcut/drivers/file_transport.h"

namespace popcut::drivers {
namespace {

TransportStatus bad(std::string_view text, const std::string& why) {
  return {TransportError::bad_argument, 0, why + " (in device '" + std::string(text) + "')"};
}

const char* const kForms = "expected sim, file:PATH, serial:/dev/PORT, serial:VID:PID[:SERIAL] or usb:VID:PID[:SERIAL]";

// Four hex digits; `what` names the part for the message.
bool hex16(std::string_view s, std::uint16_t& out) {
  if (s.size() != 4) return false;
  unsigned v = 0;
  for (char c : s) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
    v = v * 16 +
        static_cast<unsigned>(std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : std::tolower(c) - 'a' + 10);
  }
  out = static_cast<std::uint16_t>(v);
  return true;
}

// "VID:PID[:SERIAL]" after the scheme.
TransportStatus parse_ids(std::string_view text, std::string_view rest, DeviceAddress& out) {
  const std::size_t c1 = rest.find(':');
  if (c1 == std::string_view::npos) return bad(text, "expected VID:PID (four hex digits each, e.g. 0b4d:110a)");
  const std::size_t c2 = rest.find(':', c1 + 1);
  const std::string_view vid = rest.substr(0, c1);
  const std::string_view pid = rest.substr(c1 + 1, c2 == std::string_view::npos ? std::string_view::npos : c2 - c1 - 1);
  std::uint16_t v = 0, p = 0;
  if (!hex16(vid, v)) return bad(text, "vendor id '" + std::string(vid) + "' is not four hex digits (e.g. 0b4d)");
  if (!hex16(pid, p)) return bad(text, "product id '" + std::string(pid) + "' is not four hex digits (e.g. 110a)");
  out.vid = v;
  out.pid = p;
  if (c2 != std::string_view::npos) {
    out.serial_number = std::string(rest.substr(c2 + 1));
    if (out.serial_number.empty()) return bad(text, "empty serial number after VID:PID: (leave out the last ':')");
    for (char c : out.serial_number) {
      if (static_cast<unsigned char>(c) < 0x21 || static_cast<unsigned char>(c) > 0x7e) {
        return bad(text, "the serial number may hold printable characters only, no spaces");
      }
    }
  }
  return TransportStatus::success();
}

}  // namespace

std::string usb_id_string(std::uint16_t vid, std::uint16_t pid) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04x:%04x", static_cast<unsigned>(vid), static_cast<unsigned>(pid));
  return buf;
}

TransportStatus parse_device(std::string_view text, DeviceAddress& out) {
  out = DeviceAddress{};
  out.text = std::string(text);
  if (text.empty()) return bad(text, std::string("empty; ") + kForms);
  if (text == "sim") {
    out.kind = DeviceKind::sim;
    return TransportStatus::success();
  }
  const std::size_t colon = text.find(':');
  if (colon == std::string_view::npos) return bad(text, std::string("unknown device; ") + kForms);
  const std::string_view scheme = text.substr(0, colon), rest = text.substr(colon + 1);
  if (scheme == "file") {
    out.kind = DeviceKind::file;
    if (rest.empty()) return bad(text, "file: needs a path, e.g. file:job.hpgl");
    out.path = std::string(rest);
    return TransportStatus::success();
  }
  if (scheme == "serial") {
    out.kind = DeviceKind::serial;
    if (rest.empty()) return bad(text, "serial: needs a port (serial:/dev/ttyUSB0) or USB ids (serial:0403:6001)");
    if (rest.front() == '/') {
      out.path = std::string(rest);
      return TransportStatus::success();
    }
    return parse_ids(text, rest, out);
  }
  if (scheme == "usb") {
    out.kind = DeviceKind::usb;
    if (rest.empty()) return bad(text, "usb: needs VID:PID, e.g. usb:0b4d:110a");
    return parse_ids(text, rest, out);
  }
  return bad(text, "unknown scheme '" + std::string(scheme) + ":'; " + kForms);
}

MadeTransport make_transport(std::string_view device, const DeviceProfile& profile, const SimFaults& sim_faults) {
  MadeTransport m;
  m.status = parse_device(device, m.address);
  if (!m.status.ok()) return m;
  switch (m.address.kind) {
    case DeviceKind::sim:
      m.sim = std::make_shared<SimCutter>(profile, sim_faults);
      m.transport = std::make_unique<SimTransport>(m.sim);
      break;
    case DeviceKind::file: m.transport = std::make_unique<FileTransport>(m.address.path); break;
    case DeviceKind::serial: m.transport = make_serial_transport(m.address, profile, m.status); break;
    case DeviceKind::usb: m.transport = make_usb_transport(m.address, profile, m.status); break;
  }
  return m;
}

}  // namespace popcut::drivers
