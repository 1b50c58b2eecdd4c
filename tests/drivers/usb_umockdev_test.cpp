// USB cutting through the unmodified libusb backend, against a cutter mocked by umockdev (run under its preload).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <umockdev.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "popcut/drivers/device.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/ports.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/io/model_io.h"
#include "usb_mock.h"

namespace {

using namespace popcut;
using namespace popcut::drivers;
using popcut::testing::UsbMockDevice;

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
    std::string error;
    ASSERT_TRUE(popcut::testing::attach_usb_mock(bed_, "/dev/bus/usb/001/002", device_, error)) << error;
    attached_ = true;
  }
  void TearDown() override {
    if (attached_) popcut::testing::detach_usb_mock(bed_, "/dev/bus/usb/001/002", device_);
    if (bed_) g_object_unref(bed_);
    g_free(sys_);
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
  bool attached_ = false;
  DeviceProfile profile_;
  UsbMockDevice device_;
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
