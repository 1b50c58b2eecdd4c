// The mocked USB cutter: usbdevfs ioctls (claim, submit, reap, discard) answered by a SimCutter, plus string
// descriptors.
#include "usb_mock.h"

#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>

// GObject's type macros are C: their casts are not ours to restyle.
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wpedantic"

extern "C" {
struct PopcutUsbMock {
  UMockdevIoctlBase parent;
  popcut::testing::UsbMockDevice* device;
};
struct PopcutUsbMockClass {
  UMockdevIoctlBaseClass parent_class;
};
G_DEFINE_TYPE(PopcutUsbMock, popcut_usb_mock, UMOCKDEV_TYPE_IOCTL_BASE)
}

namespace popcut::testing {

void UsbMockDevice::run_clock() {
  const double t = time_scale * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (t > cutter->now_s()) cutter->advance(t);
}

namespace {

using drivers::IoResult;

void update(UMockdevIoctlData* d) { umockdev_ioctl_data_update(d, 0, d->data, d->data_len); }

void complete_in(UsbMockDevice& d, UsbMockDevice::Urb u) {
  auto* urb = reinterpret_cast<usbdevfs_urb*>(u.urb->data);
  const IoResult got = d.cutter->reply(u.buffer->data, static_cast<std::size_t>(u.buffer->data_len), 0);
  urb->actual_length = static_cast<int>(got.bytes);  // a short (or zero-length) packet: what it had
  urb->status = 0;
  update(u.buffer);
  update(u.urb);
  d.done.push_back(u);
}

// Endpoint 0: GET_DESCRIPTOR of a string the device has, else a stall.
void complete_control(UsbMockDevice& d, UsbMockDevice::Urb u) {
  auto* urb = reinterpret_cast<usbdevfs_urb*>(u.urb->data);
  guint8* setup = u.buffer->data;
  const std::size_t room = static_cast<std::size_t>(urb->buffer_length) - 8;
  const auto found = d.strings.find(setup[2]);
  urb->actual_length = 0;
  urb->status = -EPIPE;
  if (setup[0] == 0x80 && setup[1] == 6 && setup[3] == 3 && found != d.strings.end()) {
    std::vector<guint8> desc{0, 3};
    if (setup[2] == 0) {
      desc.insert(desc.end(), {0x09, 0x04});  // US English
    } else {
      for (const char c : found->second) desc.insert(desc.end(), {static_cast<guint8>(c), 0});
    }
    desc[0] = static_cast<guint8>(desc.size());
    const std::size_t n = std::min(room, desc.size());
    std::memcpy(setup + 8, desc.data(), n);
    urb->actual_length = static_cast<int>(n);
    urb->status = 0;
    update(u.buffer);
  }
  update(u.urb);
  d.done.push_back(u);
}

void complete_out(UsbMockDevice& d, UsbMockDevice::Urb u) {
  auto* urb = reinterpret_cast<usbdevfs_urb*>(u.urb->data);
  std::size_t n = static_cast<std::size_t>(urb->buffer_length);
  const std::size_t before = d.cutter->report().bytes_received;
  if (before + n >= d.unplug_after) n = d.unplug_after > before ? d.unplug_after - before : 0;
  d.cutter->receive(u.buffer->data, n, 60);
  urb->actual_length = static_cast<int>(n);
  urb->status = n == static_cast<std::size_t>(urb->buffer_length) ? 0 : -ESHUTDOWN;  // as the kernel reports an unplug
  update(u.urb);
  d.done.push_back(u);
  if (d.cutter->report().bytes_received >= d.unplug_after) d.unplugged = true;
}

gboolean submit(UsbMockDevice& d, UMockdevIoctlData* data) {
  auto* urb = reinterpret_cast<usbdevfs_urb*>(data->data);
  GError* err = nullptr;
  UMockdevIoctlData* buffer =
      umockdev_ioctl_data_resolve(data, offsetof(usbdevfs_urb, buffer), static_cast<gsize>(urb->buffer_length), &err);
  if (err) {
    g_error_free(err);
    return FALSE;
  }
  g_object_ref(data);
  const UsbMockDevice::Urb u{data, buffer};
  if (urb->type == USBDEVFS_URB_TYPE_CONTROL) {
    complete_control(d, u);
  } else if (urb->endpoint & 0x80) {
    d.pending.push_back(u);
  } else {
    complete_out(d, u);
  }
  return TRUE;
}

void reap(UsbMockDevice& d, UMockdevIoctlClient* client, UMockdevIoctlData* data) {
  if (!d.discarded.empty()) {
    d.done.insert(d.done.begin(), d.discarded.begin(), d.discarded.end());
    d.discarded.clear();
  }
  if (d.done.empty() && !d.pending.empty()) {
    const UsbMockDevice::Urb u = d.pending.front();
    d.pending.erase(d.pending.begin());
    complete_in(d, u);
  }
  if (d.done.empty()) {
    umockdev_ioctl_client_complete(client, -1, d.unplugged ? ENODEV : EAGAIN);
    return;
  }
  const UsbMockDevice::Urb u = d.done.front();
  d.done.erase(d.done.begin());
  umockdev_ioctl_data_set_ptr(data, 0, u.urb);
  umockdev_ioctl_client_complete(client, 0, 0);
}

void discard(UsbMockDevice& d, UMockdevIoctlClient* client, UMockdevIoctlData* arg) {
  for (std::size_t i = 0; i < d.pending.size(); ++i) {
    if (d.pending[i].urb->client_addr == *reinterpret_cast<gulong*>(arg->data)) {
      reinterpret_cast<usbdevfs_urb*>(d.pending[i].urb->data)->status = -ENOENT;
      update(d.pending[i].urb);
      d.discarded.push_back(d.pending[i]);
      d.pending.erase(d.pending.begin() + static_cast<std::ptrdiff_t>(i));
      umockdev_ioctl_client_complete(client, 0, 0);
      return;
    }
  }
  umockdev_ioctl_client_complete(client, -1, EINVAL);
}

gboolean handle_ioctl(UMockdevIoctlBase* base, UMockdevIoctlClient* client) {
  UsbMockDevice& d = *reinterpret_cast<PopcutUsbMock*>(base)->device;
  std::lock_guard<std::mutex> lock(d.mutex);
  const gulong request = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  const gsize size = (request >> _IOC_SIZESHIFT) & ((1 << _IOC_SIZEBITS) - 1);
  GError* err = nullptr;
  UMockdevIoctlData* data = size ? umockdev_ioctl_data_resolve(arg, 0, size, &err) : nullptr;
  if (err) {
    g_error_free(err);
    return FALSE;
  }
  d.run_clock();
  if (d.unplugged && request != USBDEVFS_REAPURBNDELAY && request != USBDEVFS_REAPURB) {
    umockdev_ioctl_client_complete(client, -1, ENODEV);
    return TRUE;
  }
  switch (request) {
    case USBDEVFS_GET_CAPABILITIES: {
      const guint32 caps = USBDEVFS_CAP_BULK_CONTINUATION | USBDEVFS_CAP_NO_PACKET_SIZE_LIM | USBDEVFS_CAP_ZERO_PACKET;
      umockdev_ioctl_data_update(data, 0, const_cast<guint8*>(reinterpret_cast<const guint8*>(&caps)), 4);
      break;
    }
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_DISCONNECT_CLAIM:  // libusb's auto-detach: take it from usblp and claim at once
      ++d.claims;
      break;
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_CLEAR_HALT:
    case USBDEVFS_RESET:
    case USBDEVFS_RESETEP: break;
    case USBDEVFS_DISCARDURB: discard(d, client, arg); return TRUE;
    case USBDEVFS_SUBMITURB:
      if (!submit(d, data)) return FALSE;
      break;
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: reap(d, client, data); return TRUE;
    default: umockdev_ioctl_client_complete(client, -1, ENOTTY); return TRUE;
  }
  umockdev_ioctl_client_complete(client, 0, 0);
  return TRUE;
}

}  // namespace
}  // namespace popcut::testing

extern "C" {
static void popcut_usb_mock_class_init(PopcutUsbMockClass* klass) {
  UMOCKDEV_IOCTL_BASE_CLASS(klass)->handle_ioctl = popcut::testing::handle_ioctl;
}
static void popcut_usb_mock_init(PopcutUsbMock* self) { self->device = nullptr; }
}

namespace popcut::testing {

bool attach_usb_mock(UMockdevTestbed* bed, const std::string& node, UsbMockDevice& device, std::string& error) {
  auto* handler = static_cast<PopcutUsbMock*>(g_object_new(popcut_usb_mock_get_type(), nullptr));
  handler->device = &device;
  GError* err = nullptr;
  const bool ok = umockdev_testbed_attach_ioctl(bed, node.c_str(), UMOCKDEV_IOCTL_BASE(handler), &err);
  if (!ok) error = err ? err->message : "umockdev_testbed_attach_ioctl failed";
  if (err) g_error_free(err);
  if (!ok) {
    g_object_unref(handler);
    return false;
  }
  device.handler = handler;
  return true;
}

void detach_usb_mock(UMockdevTestbed* bed, const std::string& node, UsbMockDevice& device) {
  umockdev_testbed_detach_ioctl(bed, node.c_str(), nullptr);
  if (device.handler) g_object_unref(device.handler);
  device.handler = nullptr;
}

UsbTestbed::~UsbTestbed() {
  for (const auto& [node, device] : nodes_) detach_usb_mock(bed_, node, *device);
  g_object_unref(bed_);
}

bool UsbTestbed::add(const std::string& description, const std::string& node, UsbMockDevice& device,
                     std::string& error) {
  GError* err = nullptr;
  if (!umockdev_testbed_add_from_file(bed_, description.c_str(), &err)) {
    error = description + ": " + (err ? err->message : "umockdev refused it");
    if (err) g_error_free(err);
    return false;
  }
  if (!attach_usb_mock(bed_, node, device, error)) return false;
  nodes_.emplace_back(node, &device);
  return true;
}

std::map<std::uint8_t, std::string> usb_strings(const std::string& manufacturer, const std::string& product,
                                                const std::string& serial) {
  return {{0, ""}, {1, manufacturer}, {2, product}, {3, serial}};
}

}  // namespace popcut::testing
