// The kiosk page in headless Chromium: what shows of a model after a failed upload, examples named by their models, and
// card sizes for a mesh.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "kiosk_browser.h"
#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::base64_decode;
using popcut::testing::Browser;
using popcut::testing::kRendered;
using popcut::testing::PopcutdProcess;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kTower =
    "v 0 0 0\nv 20 0 0\nv 20 0 100\nv 0 0 100\nv 0 10 0\nv 20 10 0\nv 20 10 100\nv 0 10 100\n"
    "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n";

// The kiosk on the sample configuration (two sim cutters), examples and cutters listed.
class KioskPage {
 public:
  explicit KioskPage(TempDir& dir)
      : d_(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string()),
        b_((dir.path() / "chromium").string()) {
    b_.session("POST", "/url",
               {{"url", "http://127.0.0.1:" + std::to_string(d_.port()) + "/?token=kiosk-change-me-0123456789"}});
    ready_ =
        wait_until([&] { return b_.run("return document.querySelectorAll('#device option').length").get<int>() == 2; },
                   60) &&
        wait_until([&] { return b_.run("return document.querySelectorAll('#example option').length").get<int>() > 3; },
                   60);
  }
  bool ready() const { return ready_; }
  Browser& browser() { return b_; }
  std::string text(const std::string& id) {
    return b_.run("return document.getElementById('" + id + "').textContent").get<std::string>();
  }
  std::string value(const std::string& id) {
    return b_.run("return document.getElementById('" + id + "').value").get<std::string>();
  }
  bool flag(const std::string& js) { return b_.run("return " + js).get<bool>(); }
  void upload(const std::string& path) {
    const json input = b_.session("POST", "/element", {{"using", "css selector"}, {"value", "#upload"}});
    const std::string id = input.begin().value().get<std::string>();
    b_.session("POST", "/element/" + id + "/clear");
    b_.session("POST", "/element/" + id + "/value", {{"text", path}});
  }
  // A model is shown in full: both pictures rendered and Queue available.
  bool shown() {
    return wait_until(
        [&] {
          return !flag("document.getElementById('queue').disabled") &&
                 b_.run(kRendered + "return rendered('preview') && rendered('pattern')").get<bool>();
        },
        120);
  }
  std::string page() { return b_.run("return document.body.innerText").dump(); }

 private:
  PopcutdProcess d_;
  Browser b_;
  bool ready_ = false;
};

// Nothing of the model before may stay: no picture, label or job name of it, and no Queue.
void expect_cleared(KioskPage& k, const std::string& before, const std::string& failed) {
  EXPECT_FALSE(k.flag("document.getElementById('pattern').src.startsWith('blob:')")) << "the old pattern is gone";
  EXPECT_FALSE(k.flag("document.getElementById('preview').src.startsWith('blob:')")) << "the old preview is gone";
  EXPECT_EQ(k.text("model-name").find(before), std::string::npos) << "the old label is gone: " << k.text("model-name");
  EXPECT_NE(k.text("model-name").find(failed), std::string::npos)
      << "the label names the failed file: " << k.text("model-name");
  EXPECT_EQ(k.value("name"), "") << "the old job name is gone";
  EXPECT_TRUE(k.flag("document.getElementById('queue').disabled")) << "nothing can be queued";
  EXPECT_FALSE(k.flag("document.getElementById('model-error').hidden") || k.text("model-error").empty())
      << "the error shows";
}

TEST(KioskModel, AFailedUploadLeavesNothingOfThePreviousModel) {
  TempDir dir("popcut-kiosk-model");
  KioskPage k(dir);
  ASSERT_TRUE(k.ready()) << k.page();
  k.upload(kSrc + "/examples/voxel/castle.json");
  ASSERT_TRUE(k.shown()) << "the castle shows: " << k.page();
  ASSERT_EQ(k.value("name"), "castle");
  // A mesh the importer refuses (three vertices declared, two given).
  k.upload(dir.write("broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"));
  ASSERT_TRUE(wait_until([&] { return !k.flag("document.getElementById('model-error').hidden"); }, 60)) << k.page();
  expect_cleared(k, "castle", "broken.off");
  EXPECT_NE(k.text("model-error").find("broken.off"), std::string::npos)
      << "the importer's message: " << k.text("model-error");
  const std::string png = base64_decode(k.browser().session("GET", "/screenshot").get<std::string>());
  EXPECT_EQ(png.substr(1, 3), "PNG") << "a screenshot of the page";
  std::ofstream((std::filesystem::path(POPCUT_KIOSK_SCREENSHOT).parent_path() / "kiosk-failed-upload.png").string(),
                std::ios::binary)
      << png;

  // The same after a model that is not JSON, and after one popcutd refuses.
  k.upload(kSrc + "/examples/voxel/castle.json");
  ASSERT_TRUE(k.shown()) << k.page();
  k.upload(dir.write("notes.json", "{ not json"));
  ASSERT_TRUE(wait_until([&] { return !k.flag("document.getElementById('model-error').hidden"); }, 60)) << k.page();
  expect_cleared(k, "castle", "notes");
  EXPECT_NE(k.text("model-error").find("not a JSON model"), std::string::npos) << k.text("model-error");
  k.upload(kSrc + "/examples/voxel/castle.json");
  ASSERT_TRUE(k.shown()) << k.page();
  k.upload(dir.write("flat.json", R"({"format": "popcut.voxel.v1", "voxel_mm": 2, "heights": "x"})"));
  ASSERT_TRUE(wait_until([&] { return !k.flag("document.getElementById('model-error').hidden"); }, 60)) << k.page();
  expect_cleared(k, "castle", "flat");
}

TEST(KioskModel, ExamplesShowTheirModelsNames) {
  TempDir dir("popcut-kiosk-model");
  KioskPage k(dir);
  ASSERT_TRUE(k.ready()) << k.page();
  EXPECT_EQ(k.browser()
                .run("return document.querySelector(\"#example option[value='voxel-castle']\").textContent")
                .get<std::string>(),
            "Castle gatehouse with towers")
      << "listed by the model's name, not its id";
  k.browser().click("#example option[value='voxel-castle']");
  ASSERT_TRUE(k.shown()) << k.page();
  EXPECT_EQ(k.text("model-name"), "Castle gatehouse with towers") << "and labelled so";
  EXPECT_EQ(k.value("name"), "Castle gatehouse with towers") << "the job takes that name";
}

TEST(KioskModel, AMeshIsSizedAndATooLargeSheetIsWarnedOf) {
  TempDir dir("popcut-kiosk-model");
  KioskPage k(dir);
  ASSERT_TRUE(k.ready()) << k.page();
  EXPECT_EQ(k.browser()
                .run("return Array.from(document.querySelectorAll('#fit-choices option')).map(o => o.value).join(',')")
                .get<std::string>(),
            "sim-a,sim-b")
      << "the cutters are offered to fit the card to";
  k.upload(dir.write("tower.obj", kTower));
  ASSERT_TRUE(k.shown()) << k.page();
  ASSERT_FALSE(k.flag("document.getElementById('model-warning').hidden"))
      << "a tower 120 mm across makes a sheet too long for sim-a: " << k.page();
  EXPECT_NE(k.text("model-warning").find("does not fit sim-a"), std::string::npos) << k.text("model-warning");
  k.browser().run("document.getElementById('height-mm').value = '120';");
  k.browser().click("#reimport");
  ASSERT_TRUE(wait_until([&] { return k.text("model-name").find(" x 240 mm") != std::string::npos; }, 120))
      << "imported 120 mm high, on a sheet 240 mm long: " << k.page();
  ASSERT_TRUE(k.shown()) << k.page();
  EXPECT_TRUE(k.flag("document.getElementById('model-warning').hidden"))
      << "nothing to warn of: " << k.text("model-warning");
  k.browser().run(
      "document.getElementById('height-mm').value = ''; document.getElementById('fit-mm').value = 'nowhere';");
  k.browser().click("#reimport");
  ASSERT_TRUE(wait_until([&] { return !k.flag("document.getElementById('model-error').hidden"); }, 60)) << k.page();
  EXPECT_NE(k.text("model-error").find("nor a device (sim-a, sim-b)"), std::string::npos) << k.text("model-error");
  EXPECT_FALSE(k.flag("document.getElementById('preview').src.startsWith('blob:')"))
      << "the 120 mm card is not shown any more";
}

}  // namespace
