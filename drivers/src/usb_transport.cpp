// USB cutters through libusb: find by VID:PID (+ serial), detach usblp, claim, bulk OUT in chunks, bulk IN status.
#include <libusb.h>

#include <algorithm>
#include <thread>

#include "backends.h"
#include "popcut/drivers/ports.h"

namespace popcut::drivers {
namespace {

const char* const kUdevHint =
    "; popcut needs write access to the device node: install the shipped rule with "
    "`sudo cp configs/udev/60-popcut-cutters.rules /etc/udev/rules.d/ && sudo udevadm control --reload && "
    "sudo udevadm trigger`, add yourself to the plugdev group, then unplug and replug the cutter";

TransportStatus usb_status(int code, const std::string& what) {
  TransportError kind = TransportError::io;
  switch (code) {
    case LIBUSB_ERROR_ACCESS: kind = TransportError::permission; break;
    case LIBUSB_ERROR_NO_DEVICE: kind = TransportError::disconnected; break;
    case LIBUSB_ERROR_NOT_FOUND: kind = TransportError::not_found; break;
    case LIBUSB_ERROR_BUSY: kind = TransportError::busy; break;
    case LIBUSB_ERROR_TIMEOUT: kind = TransportError::timeout; break;
    case LIBUSB_ERROR_PIPE:
    case LIBUSB_ERROR_IO:
    case LIBUSB_ERROR_OVERFLOW: kind = TransportError::io; break;
    case LIBUSB_ERROR_NOT_SUPPORTED: kind = TransportError::unsupported; break;
    case LIBUSB_ERROR_INVALID_PARAM: kind = TransportError::bad_argument; break;
    default: break;
  }
  std::string msg = what + ": " + libusb_strerror(code);
  if (kind == TransportError::permission) msg += kUdevHint;
  if (kind == TransportError::disconnected) msg += " (the cutter was unplugged or switched off)";
  if (kind == TransportError::busy) msg += " (another program has claimed the cutter's interface)";
  return {kind, code, msg};
}

std::string string_descriptor(libusb_device_handle* h, std::uint8_t index) {
  if (!h || index == 0) return "";
  unsigned char buf[256];
  const int n = libusb_get_string_descriptor_ascii(h, index, buf, sizeof buf);
  return n > 0 ? std::string(reinterpret_cast<const char*>(buf), static_cast<std::size_t>(n)) : "";
}

// The first interface with a bulk OUT endpoint (printer class first), and its bulk IN if any.
struct Endpoints {
  int interface = -1;
  std::uint8_t out = 0, in = 0;
  int out_packet = 64;
};

Endpoints find_endpoints(libusb_device* dev) {
  Endpoints best;
  libusb_config_descriptor* cfg = nullptr;
  if (libusb_get_active_config_descriptor(dev, &cfg) != 0 && libusb_get_config_descriptor(dev, 0, &cfg) != 0)
    return best;
  for (int i = 0; i < cfg->bNumInterfaces; ++i) {
    for (int a = 0; a < cfg->interface[i].num_altsetting; ++a) {
      const libusb_interface_descriptor& d = cfg->interface[i].altsetting[a];
      Endpoints e;
      e.interface = d.bInterfaceNumber;
      for (int k = 0; k < d.bNumEndpoints; ++k) {
        const libusb_endpoint_descriptor& ep = d.endpoint[k];
        if ((ep.bmAttributes & LIBUSB_TRANSFER_TYPE_MASK) != LIBUSB_TRANSFER_TYPE_BULK) continue;
        if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) {
          if (!e.in) e.in = ep.bEndpointAddress;
        } else if (!e.out) {
          e.out = ep.bEndpointAddress;
          e.out_packet = std::max<int>(8, ep.wMaxPacketSize);
        }
      }
      if (!e.out) continue;
      if (best.interface < 0 || d.bInterfaceClass == LIBUSB_CLASS_PRINTER) best = e;
    }
  }
  libusb_free_config_descriptor(cfg);
  return best;
}

class UsbTransport final : public Transport {
 public:
  UsbTransport(DeviceAddress address, const DeviceProfile& profile)
      : address_(std::move(address)), chunk_(profile.transport.usb_chunk_bytes) {}
  ~UsbTransport() override {
    close();
    if (ctx_) libusb_exit(ctx_);
  }
  UsbTransport(const UsbTransport&) = delete;
  UsbTransport& operator=(const UsbTransport&) = delete;

  TransportStatus open() override {
    if (handle_) return {TransportError::bad_argument, 0, describe() + ": already open"};
    if (!ctx_) {
      if (const int rc = libusb_init(&ctx_); rc != 0) {
        ctx_ = nullptr;
        return usb_status(rc, "cannot start libusb");
      }
    }
    libusb_device** list = nullptr;
    const ssize_t count = libusb_get_device_list(ctx_, &list);
    if (count < 0) return usb_status(static_cast<int>(count), "cannot list USB devices");
    TransportStatus st{TransportError::not_found, 0,
                       "no USB device " + usb_id_string(*address_.vid, *address_.pid) +
                           (address_.serial_number.empty() ? "" : " with serial number " + address_.serial_number) +
                           " is connected (see `popcut devices`)"};
    for (ssize_t i = 0; i < count && !handle_; ++i) {
      libusb_device_descriptor desc{};
      if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
      if (desc.idVendor != *address_.vid || desc.idProduct != *address_.pid) continue;
      libusb_device_handle* h = nullptr;
      const std::string where = "USB " + usb_id_string(desc.idVendor, desc.idProduct) + " (bus " +
                                std::to_string(libusb_get_bus_number(list[i])) + " device " +
                                std::to_string(libusb_get_device_address(list[i])) + ")";
      if (const int rc = libusb_open(list[i], &h); rc != 0) {
        st = usb_status(rc, "cannot open " + where);
        continue;
      }
      if (!address_.serial_number.empty() && string_descriptor(h, desc.iSerialNumber) != address_.serial_number) {
        libusb_close(h);
        continue;
      }
      const Endpoints ep = find_endpoints(list[i]);
      if (ep.interface < 0) {
        libusb_close(h);
        st = {TransportError::unsupported, 0, where + " has no bulk OUT endpoint: it is not a cutter popcut can drive"};
        continue;
      }
      // usblp (or another driver) may own the interface: let libusb detach it and give it back.
      (void)libusb_set_auto_detach_kernel_driver(h, 1);
      if (const int rc = libusb_claim_interface(h, ep.interface); rc != 0) {
        libusb_close(h);
        st = usb_status(rc, "cannot claim interface " + std::to_string(ep.interface) + " of " + where);
        continue;
      }
      handle_ = h;
      ep_ = ep;
      where_ = where;
    }
    libusb_free_device_list(list, 1);
    return handle_ ? TransportStatus::success() : st;
  }

  IoResult write(std::span<const std::uint8_t> data, std::chrono::milliseconds timeout) override {
    IoResult r;
    if (!handle_) return {0, {TransportError::bad_argument, 0, describe() + ": write before open"}};
    while (r.bytes < data.size()) {
      const std::size_t n = std::min(chunk_, data.size() - r.bytes);
      int done = 0;
      const int rc = libusb_bulk_transfer(handle_, ep_.out, const_cast<unsigned char*>(data.data() + r.bytes),
                                          static_cast<int>(n), &done, static_cast<unsigned>(timeout.count()));
      r.bytes += static_cast<std::size_t>(std::max(0, done));
      if (rc != 0) {
        r.status = usb_status(rc, "bulk OUT to " + where_);
        return r;
      }
    }
    return r;
  }

  IoResult read(std::span<std::uint8_t> buffer, std::chrono::milliseconds timeout) override {
    IoResult r;
    if (!handle_) return {0, {TransportError::bad_argument, 0, describe() + ": read before open"}};
    if (buffer.empty() || !ep_.in) {
      std::this_thread::sleep_for(timeout);
      if (!buffer.empty()) r.status = {TransportError::timeout, 0, where_ + " has no status endpoint (bulk IN)"};
      return r;
    }
    // A bulk IN transfer must take whole packets; answers are short, so read into a packet.
    unsigned char packet[512];
    int done = 0;
    const int rc = libusb_bulk_transfer(handle_, ep_.in, packet, sizeof packet, &done,
                                        static_cast<unsigned>(std::max<long>(1, timeout.count())));
    pending_.append(reinterpret_cast<const char*>(packet), static_cast<std::size_t>(std::max(0, done)));
    r.bytes = std::min(buffer.size(), pending_.size());
    std::copy_n(pending_.begin(), r.bytes, buffer.begin());
    pending_.erase(0, r.bytes);
    if (rc != 0 && r.bytes == 0) r.status = usb_status(rc, "bulk IN from " + where_);
    return r;
  }

  TransportStatus drain(std::chrono::milliseconds) override {
    // A bulk transfer completes when the device has taken the data: nothing is left on our side.
    return handle_ ? TransportStatus::success()
                   : TransportStatus{TransportError::bad_argument, 0, describe() + ": drain before open"};
  }

  void close() override {
    if (!handle_) return;
    libusb_release_interface(handle_, ep_.interface);  // usblp comes back (auto-detach)
    libusb_close(handle_);
    handle_ = nullptr;
  }

  std::string describe() const override { return address_.text; }
  bool answers() const override { return ep_.in != 0; }

 private:
  DeviceAddress address_;
  std::size_t chunk_;
  libusb_context* ctx_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  Endpoints ep_;
  std::string where_;
  std::string pending_;
};

}  // namespace

std::unique_ptr<Transport> make_usb_transport(const DeviceAddress& address, const DeviceProfile& profile,
                                              TransportStatus& status) {
  status = TransportStatus::success();
  return std::make_unique<UsbTransport>(address, profile);
}

TransportStatus list_usb_devices(std::vector<UsbDeviceInfo>& out) {
  out.clear();
  libusb_context* ctx = nullptr;
  if (const int rc = libusb_init(&ctx); rc != 0) return usb_status(rc, "cannot start libusb");
  libusb_device** list = nullptr;
  const ssize_t count = libusb_get_device_list(ctx, &list);
  if (count < 0) {
    libusb_exit(ctx);
    return usb_status(static_cast<int>(count), "cannot list USB devices");
  }
  for (ssize_t i = 0; i < count; ++i) {
    libusb_device_descriptor desc{};
    if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
    UsbDeviceInfo info;
    info.vid = desc.idVendor;
    info.pid = desc.idProduct;
    info.bus = libusb_get_bus_number(list[i]);
    info.address = libusb_get_device_address(list[i]);
    info.has_bulk_out = find_endpoints(list[i]).interface >= 0;
    libusb_device_handle* h = nullptr;
    if (libusb_open(list[i], &h) == 0) {  // without permission the strings stay unknown
      info.serial_number = string_descriptor(h, desc.iSerialNumber);
      info.product = string_descriptor(h, desc.iProduct);
      libusb_close(h);
    }
    out.push_back(std::move(info));
  }
  libusb_free_device_list(list, 1);
  libusb_exit(ctx);
  return TransportStatus::success();
}

}  // namespace popcut::drivers
