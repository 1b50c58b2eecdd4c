// A Silhouette Cameo 4 over USB: GP-GL through the unmodified libusb backend, against a umockdev description and a
// simulated cutter.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "popcut/drivers/device.h"
#include "popcut/drivers/job_sender.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/ports.h"
#include "popcut/drivers/sim_cutter.h"
#include "popcut/io/model_io.h"
#include "cut_job.h"
#include "popcutd_process.h"
#include "usb_mock.h"

namespace {

using namespace popcut;
using namespace popcut::drivers;
using popcut::testing::UsbMockDevice;

const std::string kSource = POPCUT_SOURCE_DIR;
const char* const kNode = "/dev/bus/usb/001/003";  // the description's N: line
const char* const kDevice = "usb:0b4d:1137:S4A012345";

class SilhouetteUsb : public ::testing::Test {
 protected:
  void SetUp() override {
    const char* preload = std::getenv("LD_PRELOAD");
    ASSERT_TRUE(preload && std::strstr(preload, "umockdev-preload")) << "run under umockdev-wrapper (CTest does)";
    profile_ = load_profile(kSource + "/configs/devices/silhouette-cameo4.toml");
    device_.strings = popcut::testing::usb_strings("Silhouette", "CAMEO 4", "S4A012345");
    std::string error;
    ASSERT_TRUE(bed_.add(kSource + "/tests/data/umockdev/silhouette-cameo4.umockdev", kNode, device_, error)) << error;
  }
  // The cutter at the far end, with `faults`. A USB device NAKs bulk OUT while its buffer is full:
  // to the simulator, a line it holds.
  void plug_in(SimFaults faults = {}) {
    DeviceProfile far = profile_;
    far.transport.flow = FlowControl::rts_cts;
    std::lock_guard<std::mutex> lock(device_.mutex);
    device_.cutter = std::make_shared<SimCutter>(far, faults);
  }
  StrokePlan townhouse() const {
    PlanOptions o = profile_.plan;
    o.optimise_work = 1000;  // these tests are about the transport, not ordering
    return plan_strokes(make_pattern(load_model(kSource + "/examples/voxel/townhouse.json")), o);
  }
  SendResult send(const EncodedJob& job) {
    MadeTransport t = make_transport(kDevice, profile_);
    EXPECT_TRUE(t.status.ok()) << t.status.message;
    const TransportStatus open = t.transport->open();
    EXPECT_TRUE(open.ok()) << open.message;
    if (!open.ok()) return {};
    SendOptions o = send_options(profile_);
    o.motion = motion_schedule(job.bytes, profile_);
    const SendResult r = send_job(*t.transport, job, o);
    t.transport->close();
    return r;
  }
  std::vector<SimStroke> cut() {
    std::lock_guard<std::mutex> lock(device_.mutex);
    device_.cutter->run_to_end();
    return device_.cutter->strokes();
  }

  popcut::testing::UsbTestbed bed_;
  UsbMockDevice device_;
  DeviceProfile profile_;
};

TEST_F(SilhouetteUsb, LibusbEnumeratesTheDescription) {
  plug_in();
  std::vector<UsbDeviceInfo> usb;
  ASSERT_TRUE(list_usb_devices(usb).ok());
  ASSERT_EQ(usb.size(), 1u) << "the Cameo (its root hub has no descriptors)";
  EXPECT_EQ(usb_id_string(usb[0].vid, usb[0].pid), "0b4d:1137") << "the Cameo 4 profile's first usb_ids";
  EXPECT_TRUE(usb[0].has_bulk_out);
  EXPECT_EQ(usb[0].serial_number, "S4A012345") << "from its string descriptor, over endpoint 0";
  EXPECT_EQ(usb[0].product, "CAMEO 4");
}

// The whole townhouse in GP-GL over bulk OUT, ESC ENQ answered over bulk IN; the simulator cut
// exactly the plan.
TEST_F(SilhouetteUsb, TownhouseCutsThePlan) {
  plug_in();
  const StrokePlan plan = townhouse();
  const EncodedJob job = encode_for_device(plan, profile_);
  const SendResult r = send(job);
  ASSERT_TRUE(r.complete()) << r.status.message;
  EXPECT_EQ(r.drained_by, DrainedBy::esc_enq) << "done when the device answered ready";
  EXPECT_GT(r.status_queries, 0) << "ESC ENQ asked and answered over bulk IN";
  EXPECT_EQ(device_.claims, 1) << "interface 0 claimed once";
  const std::vector<SimStroke> strokes = cut();
  EXPECT_FALSE(first_difference(plan_in_plotter_units(plan, profile_.dialect), strokes).has_value())
      << "the simulator cut the plan, stroke for stroke";
  std::lock_guard<std::mutex> lock(device_.mutex);
  const SimReport& rep = device_.cutter->report();
  EXPECT_EQ(rep.overflow_bytes, 0u);
  EXPECT_TRUE(rep.unknown.empty()) << "every byte was GP-GL the device knows";
  EXPECT_EQ(rep.bytes_received, job.bytes.size() + 2 * static_cast<std::size_t>(r.status_queries))
      << "the job and the ESC ENQ queries (2 bytes each), nothing else";
}

// A device with no sheet loaded says so before a byte of the job goes out; nothing is cut.
TEST_F(SilhouetteUsb, AnEmptyTrayBeforeTheJobEndsItCleanly) {
  SimFaults f;
  f.tray_empty_after_bytes = 0;
  plug_in(f);
  const SendResult r = send(encode_for_device(townhouse(), profile_));
  EXPECT_FALSE(r.complete());
  EXPECT_EQ(r.device_stop, DeviceStop::tray_empty) << r.status.message;
  EXPECT_EQ(r.last_stroke_written, 0u) << "nothing of the job was sent";
  EXPECT_TRUE(cut().empty());
}

// Paused mid-job (its pause key): popcut stops sending, finishes the command in flight, and the
// counts say where to resume.
TEST_F(SilhouetteUsb, APauseMidJobEndsItWithAResumePoint) {
  const StrokePlan plan = townhouse();
  const EncodedJob job = encode_for_device(plan, profile_);
  SimFaults f;
  f.pause_after_bytes = job.stroke_end[20];
  plug_in(f);
  const SendResult r = send(job);
  EXPECT_FALSE(r.complete());
  EXPECT_EQ(r.device_stop, DeviceStop::paused) << r.status.message;
  EXPECT_LT(r.last_stroke_written, job.stroke_end.size()) << "it stopped sending";
  EXPECT_GE(r.last_stroke_sent, 1u);
  EXPECT_LE(r.last_stroke_sent, r.last_stroke_written);
}

// Unplugged mid-job: disconnected, with the last stroke certainly received; plugged in again, the
// resume from there completes the card with no stroke missing.
TEST_F(SilhouetteUsb, UnplugMidJobIsResumable) {
  plug_in();
  const StrokePlan plan = townhouse();
  const EncodedJob job = encode_for_device(plan, profile_);
  device_.unplug_after = job.stroke_end[30] + 5;
  const SendResult r = send(job);
  ASSERT_EQ(r.status.error, TransportError::disconnected) << r.status.message;
  ASSERT_GE(r.last_stroke_sent, 31u) << "stroke 31 ended 5 bytes before the unplug";
  // The cutter kept its buffer and cut it; the cable goes back in once it has stopped (GP-GL's
  // init, ESC EOT, makes the device drop whatever it still holds).
  EXPECT_EQ(cut().size(), r.last_stroke_sent) << "it cut every stroke it certainly received";
  {
    std::lock_guard<std::mutex> lock(device_.mutex);
    device_.unplugged = false;
    device_.unplug_after = static_cast<std::size_t>(-1);
  }
  const SendResult resumed = send(encode_for_device(plan, profile_, r.last_stroke_sent + 1));
  ASSERT_TRUE(resumed.complete()) << resumed.status.message;
  const std::vector<SimStroke> strokes = cut();
  const std::vector<PlotterPath> planned = plan_in_plotter_units(plan, profile_.dialect);
  ASSERT_EQ(strokes.size(), planned.size()) << "every stroke once: none skipped, none twice";
  EXPECT_FALSE(first_difference(planned, strokes).has_value());
}

// popcut devices, a process of its own on the same testbed (it inherits the preload and the
// testbed's directory): the Cameo is listed by its profile's device name, ready to copy as --device.
TEST_F(SilhouetteUsb, PopcutDevicesListsTheCameoByItsProfilesName) {
  plug_in();
  const std::string out = ::testing::TempDir() + "popcut-devices.txt";
  const std::string cmd = std::string(POPCUT_CLI) + " devices >" + out + " 2>&1";
  const auto slurp = [&] {
    std::ostringstream text;
    text << std::ifstream(out).rdbuf();
    return text.str();
  };
  ASSERT_EQ(std::system((cmd + " --json").c_str()), 0);
  const nlohmann::json j = nlohmann::json::parse(slurp());
  ASSERT_EQ(j["usb"].size(), 1u) << j.dump();
  const nlohmann::json& cameo = j["usb"][0];
  EXPECT_EQ(cameo["device"], kDevice) << "the serial number from its string descriptor";
  EXPECT_EQ(cameo["product"], "CAMEO 4");
  EXPECT_TRUE(cameo["bulk_out"].get<bool>());
  ASSERT_EQ(cameo["names"].size(), 1u) << cameo.dump();
  EXPECT_EQ(cameo["names"][0], profile_.name);
  EXPECT_NE(cameo["profiles"][0].get<std::string>().find("silhouette-cameo4.toml"), std::string::npos);
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  const std::string text = slurp();
  EXPECT_NE(text.find(std::string(kDevice) + "  bus 1 address 3  CAMEO 4  " + profile_.name + " (profile "),
            std::string::npos)
      << text;
}

// popcutd, a process of its own on the testbed, pauses the Cameo's cut over USB and continues it:
// the pause drains the device and lifts the knife, continue re-sends the init, and the cutter (the
// same one, the same sheet) cut every stroke of the card once.
TEST_F(SilhouetteUsb, PopcutdPausesAndContinuesACutOverUsb) {
  plug_in();
  {
    std::lock_guard<std::mutex> lock(device_.mutex);
    device_.time_scale = 2;  // townhouse's 42 s of motion in about 21 s: time to pause mid-cut
  }
  popcut::testing::TempDir dir("popcutd-usb");
  const std::string data = (dir.path() / "data").string();
  const std::string cfg = dir.write(
      "usb.toml", "[server]\ndata_dir = \"x\"\n[[device]]\nname = \"cameo\"\nprofile = \"" + kSource +
                      "/configs/devices/silhouette-cameo4.toml\"\ntransport = \"" + kDevice +
                      "\"\nconfirm_sheet = false\n[[token]]\nname = \"kiosk\"\ntoken = \"kiosk-0123456789abcdef\"\n");
  popcut::testing::PopcutdProcess d(POPCUTD, cfg, data);
  httplib::Client c = d.client("kiosk-0123456789abcdef");
  const nlohmann::json body = {
      {"device", "cameo"},
      {"model", nlohmann::json::parse(popcut::testing::read_file(kSource + "/examples/voxel/townhouse.json"))}};
  const popcut::testing::Reply r = popcut::testing::post_json(c, "/api/v1/jobs", body.dump());
  ASSERT_EQ(r.status, 201) << r.body.dump();
  const std::string path = "/api/v1/jobs/" + std::to_string(r.body["id"].get<std::int64_t>());
  const auto job = [&] { return popcut::testing::get_json(c, path).body; };
  ASSERT_TRUE(
      popcut::testing::wait_until([&] { return job()["state"] == "cutting" && job()["strokes_sent"] >= 5; }, 60))
      << d.log();
  ASSERT_EQ(popcut::testing::post_json(c, path + "/pause", "").status, 202);
  ASSERT_TRUE(popcut::testing::wait_until([&] { return job()["state"] != "cutting"; }, 120)) << d.log();
  nlohmann::json j = job();
  ASSERT_EQ(j["state"], "paused") << j.dump() << d.log();
  const std::int64_t after = j["strokes_sent"];
  EXPECT_LT(after, j["strokes_total"].get<std::int64_t>()) << "paused mid-cut";
  EXPECT_EQ(j["strokes_executed"], after) << "the Cameo drained: what it received, it cut";
  ASSERT_EQ(popcut::testing::post_json(c, path + "/continue", "").status, 200);
  ASSERT_TRUE(
      popcut::testing::wait_until([&] { return job()["state"] != "ready" && job()["state"] != "cutting"; }, 120))
      << d.log();
  j = job();
  EXPECT_EQ(j["state"], "done") << j.dump() << d.log();
  const std::string plan_path = data + "/jobs/" + std::to_string(j["id"].get<std::int64_t>()) + "/plan.json";
  const StrokePlan plan = popcut::daemon::plan_from_json(popcut::testing::read_file(plan_path), plan_path);
  EXPECT_FALSE(first_difference(plan_in_plotter_units(plan, profile_.dialect), cut()).has_value())
      << "every stroke once, in order, across the pause";
}

}  // namespace
