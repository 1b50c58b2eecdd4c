// A simulated cutter behind usbdevfs URBs in a umockdev testbed, for the USB tests and the transport benchmark.
#pragma once

#include <umockdev.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "popcut/drivers/sim_cutter.h"

namespace popcut::testing {

// The far end of one mocked USB device: bulk OUT feeds `cutter`, bulk IN carries its replies,
// endpoint 0 answers string descriptors from `strings` (none: it stalls them, as devices without
// strings do). Lock `mutex` to look at it while a transport may be talking to it.
struct UsbMockDevice {
  struct Urb {
    UMockdevIoctlData* urb;
    UMockdevIoctlData* buffer;
  };
  std::mutex mutex;
  std::shared_ptr<drivers::SimCutter> cutter;
  std::map<std::uint8_t, std::string> strings;              // index -> text (index 0: language ids)
  std::size_t unplug_after = static_cast<std::size_t>(-1);  // bytes; then every ioctl fails ENODEV
  bool unplugged = false;
  int claims = 0;
  // The cutter runs this many times faster than the wall clock: a job's seconds of motion pass quickly.
  double time_scale = 100;
  std::vector<Urb> done;     // completed, waiting to be reaped
  std::vector<Urb> pending;  // IN transfers waiting for the device to say something
  std::vector<Urb> discarded;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  void* handler = nullptr;  // the ioctl handler while attached
  // Moves the cutter's clock on to the scaled wall clock.
  void run_clock();
};

// Answers the usbdevfs ioctls of `node` (e.g. "/dev/bus/usb/001/002") in `bed` as `device` would,
// until detach_usb_mock. False with `error` set when umockdev refuses.
bool attach_usb_mock(UMockdevTestbed* bed, const std::string& node, UsbMockDevice& device, std::string& error);
void detach_usb_mock(UMockdevTestbed* bed, const std::string& node, UsbMockDevice& device);

// A umockdev testbed with one device described by a file in umockdev-record's format and a mock
// cutter on its node; the testbed (and the redirection of /sys and /dev) ends with it.
class UsbTestbed {
 public:
  UsbTestbed() : bed_(umockdev_testbed_new()) {}
  ~UsbTestbed();
  UsbTestbed(const UsbTestbed&) = delete;
  UsbTestbed& operator=(const UsbTestbed&) = delete;
  // Loads `description` and attaches `device` to `node`; false with `error` set.
  bool add(const std::string& description, const std::string& node, UsbMockDevice& device, std::string& error);
  UMockdevTestbed* bed() const { return bed_; }

 private:
  UMockdevTestbed* bed_;
  std::vector<std::pair<std::string, UsbMockDevice*>> nodes_;
};

// The string descriptors of a description's device: its sysfs manufacturer, product and serial
// at the indices its device descriptor gives (1, 2, 3 in the shipped descriptions).
std::map<std::uint8_t, std::string> usb_strings(const std::string& manufacturer, const std::string& product,
                                                const std::string& serial);

}  // namespace popcut::testing
