// USB cutting through the unmodified libusb backend, against a cutter mocked by umockdev (run under its preload).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>
#include <umockdev.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <vector>

#include "popcut/drivers/device.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/ports.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/io/model_io.h"

// GObject's type macros are C: their casts are not ours to restyle.
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wpedantic"

namespace {

using namespace popcut;
using namespace popcut::drivers;

// The far end: a SimCutter behind usbdevfs URBs, plus the faults a USB cutter shows.
struct Device {
  std::mutex mutex;
  std::shared_ptr<SimCutter> cutter;
  std::size_t unplug_after = static_cast<std::size_t>(-1);  // bytes; then every ioctl fails ENODEV
  bool unplugged = false;
  struct Urb {
    UMockdevIoctlData* urb;
    UMockdevIoctlData* buffer;
  };
  std::vector<Urb> done;     // completed, waiting to be reaped
  std::vector<Urb> pending;  // IN transfers waiting for the device to say something
  std::vector<Urb> discarded;
  int claims = 0;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  // The cutter runs 100 times faster than the wall clock: a job's seconds of motion pass quickly.
  void run_clock() {
    const double t = 100 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (t > cutter->now_s()) cutter->advance(t);
  }
};
Device* g_device = nullptr;

}  // namespace

extern "C" {
struct CutterHandler {
  UMockdevIoctlBase parent;
};
struct CutterHandlerClass {
  UMockdevIoctlBaseClass parent_class;
};
G_DEFINE_TYPE(CutterHandler, cutter_handler, UMOCKDEV_TYPE_IOCTL_BASE)
}

namespace {

void complete_in(Device& d, Device::Urb u) {
  auto* urb = reinterpret_cast<usbdevfs_urb*>(u.urb->data);
  const IoResult got = d.cutter->reply(u.buffer->data, static_cast<std::size_t>(u.buffer->data_len), 0);
  urb->actual_length = static_cast<int>(got.bytes);  // a short (or zero-length) packet: what it had
  urb->status = 0;
  umockdev_ioctl_data_update(u.buffer, 0, u.buffer->data, u.buffer->data_len);
  umockdev_ioctl_data_update(u.urb, 0, u.urb->data, u.urb->data_len);
  d.done.push_back(u);
}

gboolean handle_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* client) {
  Device& d = *g_device;
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
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    }
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_DISCONNECT_CLAIM:  // libusb's auto-detach: take it from usblp and claim at once
      ++d.claims;
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_CLEAR_HALT:
    case USBDEVFS_RESET:
    case USBDEVFS_RESETEP: umockdev_ioctl_client_complete(client, 0, 0); return TRUE;
    case USBDEVFS_DISCARDURB:
      for (std::size_t i = 0; i < d.pending.size(); ++i) {
        if (d.pending[i].urb->client_addr == *reinterpret_cast<gulong*>(arg->data)) {
          reinterpret_cast<usbdevfs_urb*>(d.pending[i].urb->data)->status = -ENOENT;
          umockdev_ioctl_data_update(d.pending[i].urb, 0, d.pending[i].urb->data, d.pending[i].urb->data_len);
          d.discarded.push_back(d.pending[i]);
          d.pending.erase(d.pending.begin() + static_cast<std::ptrdiff_t>(i));
          umockdev_ioctl_client_complete(client, 0, 0);
          return TRUE;
        }
      }
      umockdev_ioctl_client_complete(client, -1, EINVAL);
      return TRUE;
    case USBDEVFS_SUBMITURB: {
      auto* urb = reinterpret_cast<usbdevfs_urb*>(data->data);
      const gsize offset = offsetof(usbdevfs_urb, buffer);
      UMockdevIoctlData* buffer =
          umockdev_ioctl_data_resolve(data, offset, static_cast<gsize>(urb->buffer_length), &err);
      if (err) {
        g_error_free(err);
        return FALSE;
      }
      g_object_ref(data);
      Device::Urb u{data, buffer};
      if (urb->type == USBDEVFS_URB_TYPE_CONTROL) {
        // Endpoint 0 (string descriptors): this cutter stalls them, as devices without strings do.
        urb->actual_length = 0;
        urb->status = -EPIPE;
        umockdev_ioctl_data_update(data, 0, data->data, data->data_len);
        d.done.push_back(u);
      } else if (urb->endpoint & 0x80) {
        d.pending.push_back(u);
      } else {
        std::size_t n = static_cast<std::size_t>(urb->buffer_length);
        const std::size_t before = d.cutter->report().bytes_received;
        if (before + n >= d.unplug_after) n = d.unplug_after > before ? d.unplug_after - before : 0;
        d.cutter->receive(buffer->data, n, 60);
        urb->actual_length = static_cast<int>(n);
        urb->status =
            n == static_cast<std::size_t>(urb->buffer_length) ? 0 : -ESHUTDOWN;  // as the kernel reports an unplug
        umockdev_ioctl_data_update(data, 0, data->data, data->data_len);
        d.done.push_back(u);
        if (d.cutter->report().bytes_received >= d.unplug_after) d.unplugged = true;
      }
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    }
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: {
      if (!d.discarded.empty()) {
        d.done.insert(d.done.begin(), d.discarded.begin(), d.discarded.end());
        d.discarded.clear();
      }
      if (d.done.empty() && !d.pending.empty()) {
        const Device::Urb u = d.pending.front();
        d.pending.erase(d.pending.begin());
        complete_in(d, u);
      }
      if (d.done.empty()) {
        umockdev_ioctl_client_complete(client, -1, d.unplugged ? ENODEV : EAGAIN);
        return TRUE;
      }
      const Device::Urb u = d.done.front();
      d.done.erase(d.done.begin());
      umockdev_ioctl_data_set_ptr(data, 0, u.urb);
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    }
    default: umockdev_ioctl_client_complete(client, -1, ENOTTY); return TRUE;
  }
}

}  // namespace

extern "C" {
static void cutter_handler_class_init(CutterHandlerClass* klass) {
  UMOCKDEV_IOCTL_BASE_CLASS(klass)->handle_ioctl = handle_ioctl;
}
static void cutter_handler_init(CutterHandler*) {}
}

namespace {

// A printer-class cutter: device descriptor, then one configuration with bulk OUT 0x01 and IN 0x82.
const guint8 kDescriptors[] = {
    0x12, 0x01, 0x00, 0x02, 0x00, 0x00, 0x00, 0x40, 0x4d, 0x0b, 0x0a, 0x11, 0x00, 0x01, 0x01, 0x02, 0x03,
    0x01, 0x09, 0x02, 0x20, 0x00, 0x01, 0x01, 0x00, 0x80, 0x32, 0x09, 0x04, 0x00, 0x00, 0x02, 0x07, 0x01,
    0x02, 0x00, 0x07, 0x05, 0x01, 0x02, 0x40, 0x00, 0x00, 0x07, 0x05, 0x82, 0x02, 0x40, 0x00, 0x00,
};

class UsbMock : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* preload = std::getenv("LD_PRELOAD");
    ASSERT_TRUE(preload && std::strstr(preload, "umockdev-preload")) << "run under umockdev-wrapper (CTest does)";
    bed_ = umockdev_testbed_new();
    sys_ = umockdev_testbed_add_device(bed_, "usb", "usb1/1-1", nullptr, "busnum", "1", "devnum", "2", "speed", "480",
                                       "bConfigurationValue", "1", "idVendor", "0b4d", "idProduct", "110a", "dev",
                                       "189:1", nullptr, "DEVNAME", "/dev/bus/usb/001/002", "DEVTYPE", "usb_device",
                                       "BUSNUM", "001", "DEVNUM", "002", nullptr);
    umockdev_testbed_set_attribute_binary(bed_, sys_, "descriptors", const_cast<guint8*>(kDescriptors),
                                          sizeof kDescriptors);
    // The usbfs node libusb opens; its ioctls go to the handler attached below.
    gchar* root = umockdev_testbed_get_root_dir(bed_);
    const std::filesystem::path node = std::filesystem::path(root) / "dev/bus/usb/001/002";
    g_free(root);
    std::filesystem::create_directories(node.parent_path());
    std::ofstream(node.string()).put('\0');
    profile_ = load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/sim.toml");
    profile_.transport.flow = FlowControl::esc_b;  // paced by answers over bulk IN
    profile_.transport.drain_query = DrainQuery::esc_b;
    profile_.transport.usb_chunk_bytes = 64;
    device_.cutter = std::make_shared<SimCutter>(profile_);
    g_device = &device_;
    handler_ = static_cast<UMockdevIoctlBase*>(g_object_new(cutter_handler_get_type(), nullptr));
    GError* err = nullptr;
    ASSERT_TRUE(umockdev_testbed_attach_ioctl(bed_, "/dev/bus/usb/001/002", handler_, &err))
        << (err ? err->message : "");
  }
  void TearDown() override {
    if (bed_) umockdev_testbed_detach_ioctl(bed_, "/dev/bus/usb/001/002", nullptr);
    if (handler_) g_object_unref(handler_);
    if (bed_) g_object_unref(bed_);
    g_free(sys_);
    g_device = nullptr;
  }

  EncodedJob job() const {
    PlanOptions o = profile_.plan;
    o.optimise_work = 1000;  // a small work budget: these tests are about the transport, not ordering
    const StrokePlan plan =
        plan_strokes(make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/box.json")), o);
    return encode_job(plan, profile_.dialect, profile_.tools);
  }

  UMockdevTestbed* bed_ = nullptr;
  gchar* sys_ = nullptr;
  UMockdevIoctlBase* handler_ = nullptr;
  DeviceProfile profile_;
  Device device_;
};

TEST_F(UsbMock, DevicesListsTheCutter) {
  std::vector<UsbDeviceInfo> usb;
  ASSERT_TRUE(list_usb_devices(usb).ok());
  ASSERT_EQ(usb.size(), 1u) << "libusb enumerated the mocked device";
  EXPECT_EQ(usb_id_string(usb[0].vid, usb[0].pid), "0b4d:110a");
  EXPECT_TRUE(usb[0].has_bulk_out) << "from the configuration descriptor";
}

TEST_F(UsbMock, AJobGoesOutOverBulkOutPacedByBulkInAnswers) {
  const EncodedJob j = job();
  MadeTransport t = make_transport("usb:0b4d:110a", profile_);
  ASSERT_TRUE(t.status.ok()) << t.status.message;
  const TransportStatus open = t.transport->open();
  ASSERT_TRUE(open.ok()) << open.message;
  EXPECT_EQ(device_.claims, 1) << "the interface was claimed";
  EXPECT_TRUE(t.transport->answers()) << "a bulk IN endpoint carries answers";
  const SendResult r = send_job(*t.transport, j, send_options(profile_));
  t.transport->close();
  ASSERT_TRUE(r.complete()) << r.status.message;
  EXPECT_GT(r.buffer_queries, 0) << "ESC.B answers came back over bulk IN";
  EXPECT_EQ(r.drained_by, DrainedBy::esc_b);
  std::lock_guard<std::mutex> lock(device_.mutex);
  ASSERT_TRUE(device_.cutter->run_to_end());
  const auto planned = [&] {
    std::vector<PlotterPath> out;
    SimCutter ref(profile_);
    ref.receive(reinterpret_cast<const std::uint8_t*>(j.bytes.data()), j.bytes.size(), 1e9);
    ref.run_to_end();
    for (const auto& s : ref.strokes()) out.push_back(s.points_pu);
    return out;
  }();
  ASSERT_EQ(device_.cutter->strokes().size(), planned.size()) << "every stroke arrived";
  for (std::size_t i = 0; i < planned.size(); ++i)
    EXPECT_EQ(device_.cutter->strokes()[i].points_pu, planned[i]) << "stroke " << i + 1;
  EXPECT_EQ(device_.cutter->report().overflow_bytes, 0u);
  EXPECT_TRUE(device_.cutter->report().unknown.empty())
      << "only the job reached the cutter (no control-transfer bytes)";
  EXPECT_EQ(device_.cutter->report().bytes_received, j.bytes.size() + 3 * static_cast<std::size_t>(r.status_queries))
      << "the job and the ESC.B queries, nothing else";
}

TEST_F(UsbMock, UnplugMidJobIsDisconnectedWithTheLastStroke) {
  const EncodedJob j = job();
  device_.unplug_after = j.stroke_end[2] + 10;
  MadeTransport t = make_transport("usb:0b4d:110a", profile_);
  ASSERT_TRUE(t.transport->open().ok());
  const SendResult r = send_job(*t.transport, j, send_options(profile_));
  EXPECT_EQ(r.status.error, TransportError::disconnected) << r.status.message;
  EXPECT_NE(r.status.message.find("unplugged"), std::string::npos) << r.status.message;
  EXPECT_EQ(r.last_stroke_sent, 3u) << "stroke 3 ended 10 bytes before the unplug";
}

TEST_F(UsbMock, PermissionDeniedPointsToTheUdevRule) {
  // As an unprivileged user (root may open anything): the node is root's, mode 0600.
  gchar* root = umockdev_testbed_get_root_dir(bed_);
  const std::filesystem::path dir(root);
  g_free(root);
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (!e.is_symlink()) ::chmod(e.path().c_str(), e.is_directory() ? 0755 : e.is_socket() ? 0666 : 0644);
  }
  ::chmod(dir.c_str(), 01777);  // udev monitors bind their sockets here
  ::chmod((dir / "dev/bus/usb/001/002").c_str(), 0600);
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    if (::setgid(65534) != 0 || ::setuid(65534) != 0) ::_exit(3);
    MadeTransport t = make_transport("usb:0b4d:110a", profile_);
    const TransportStatus st = t.transport->open();
    const std::string msg = std::string(to_string(st.error)) + ": " + st.message;
    (void)!::write(fds[1], msg.data(), msg.size());
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string msg;
  char buf[512];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) msg.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the unprivileged child ran";
  EXPECT_EQ(msg.rfind("permission: ", 0), 0u) << msg;
  EXPECT_NE(msg.find("configs/udev/60-popcut-cutters.rules"), std::string::npos)
      << "names the rule to install: " << msg;
  EXPECT_NE(msg.find("replug"), std::string::npos) << "and what to do after: " << msg;
}

TEST_F(UsbMock, AbsentDeviceIsNotFound) {
  MadeTransport t = make_transport("usb:0b4d:9999", profile_);
  const TransportStatus st = t.transport->open();
  EXPECT_EQ(st.error, TransportError::not_found) << st.message;
  EXPECT_NE(st.message.find("popcut devices"), std::string::npos) << st.message;
}

}  // namespace
