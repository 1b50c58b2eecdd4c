// The designer page in headless Chromium (WebDriver) against a real popcutd: cards drawn by mouse clicks on the edit
// plane, automatic tops, undo/redo, a failing face shown, a refused edit explained, and a card with a name in letters
// sent to the cutter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <utility>
#include <vector>

#include "kiosk_browser.h"
#include "pattern_compare.h"
#include "popcut/io/design_json.h"
#include "popcut/design/oa_design.h"
#include "popcut/io/model_io.h"
#include "popcut/io/oa_model.h"
#include "popcutd_process.h"
#include "shared_testdata.h"

namespace {
using nlohmann::json;
using popcut::testing::base64_decode;
using popcut::testing::Browser;
using popcut::testing::PopcutdProcess;
using popcut::testing::read_file;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kToken = "kiosk-change-me-0123456789";  // configs/popcutd.toml's kiosk token

// SwiftShader's WebGL, so the 3D view renders in a headless browser without a GPU.
const std::vector<std::string> kWebGl = {"--use-angle=swiftshader", "--enable-unsafe-swiftshader",
                                         "--window-size=1280,900"};

class Designer : public ::testing::Test {
 protected:
  TempDir dir_{"popcut-designer"};
  PopcutdProcess d_{POPCUTD, kSrc + "/configs/popcutd.toml", (dir_.path() / "data").string()};
  Browser b_{(dir_.path() / "chromium").string(), kWebGl};

  void SetUp() override {
    b_.session("POST", "/url", {{"url", "http://127.0.0.1:" + std::to_string(d_.port()) + "/design?token=" + kToken}});
    ASSERT_TRUE(wait_until([&] { return revision() >= 1; }, 60))
        << "the page starts a new card; it says: " << b_.run("return document.body.innerText").dump();
  }
  int revision() {
    const json r = b_.run("return Number(document.body.dataset.revision || 0)");
    return r.is_number() ? r.get<int>() : 0;
  }
  int items() { return b_.run("return document.querySelectorAll('#items li').length").get<int>(); }
  std::string text(const std::string& id) {
    return b_.run("return document.getElementById('" + id + "').textContent").get<std::string>();
  }
  // Clicks the edit plane at plane point (a, b) mm: a wall's (x, z), a roof's (x, y).
  void click_plane(double a, double b) {
    const json p = b_.run(
        "const svg = document.getElementById('edit'), m = svg.getScreenCTM();"
        "const wall = ['wall', 'opening'].includes(document.querySelector('.tool[aria-pressed=true]').dataset.tool);"
        "const x = " +
        std::to_string(a) + ", y = wall ? -" + std::to_string(b) + " : " + std::to_string(b) +
        ";"
        "return [m.a * x + m.c * y + m.e, m.b * x + m.d * y + m.f];");
    b_.click_at(static_cast<int>(std::lround(p[0].get<double>())), static_cast<int>(std::lround(p[1].get<double>())));
  }
  // Sets the edit plane, then clicks twice (a rectangle's corners, a circle's centre and rim); waits for the answer.
  void two_clicks(double t, double a0, double b0, double a1, double b1) {
    b_.type("#plane-t", std::to_string(static_cast<int>(t)));
    const int before = revision();
    click_plane(a0, b0);
    click_plane(a1, b1);
    ASSERT_TRUE(wait_until([&] { return revision() > before || !text("edit-error").empty(); }, 60));
  }
  json design() {
    httplib::Client c = d_.client(kToken);
    const int id = b_.run("return Number(localStorage.getItem('popcut-design'))").get<int>();
    const auto r = c.Get(("/api/v1/designs/" + std::to_string(id) + "/design.json").c_str());
    return r ? json::parse(r->body) : json();
  }
  void screenshot(const std::string& name) {
    const std::string png = base64_decode(b_.session("GET", "/screenshot").get<std::string>());
    EXPECT_EQ(png.substr(1, 3), "PNG");
    std::ofstream(std::string(POPCUT_SCREENSHOT_DIR) + "/" + name, std::ios::binary) << png;
  }
};

TEST_F(Designer, TwoWallsClickedOnThePlaneMakeThePorchWithItsTops) {
  two_clicks(30, 15, 0, 85, 40);
  ASSERT_EQ(items(), 1) << text("edit-error");
  // The wall's automatic top: a mountain where the top leaves the wall (v = 40 - 30) and a valley
  // where it meets the back board (v = 40), both across the wall's 70 mm.
  const json lines = b_.run(
      "return Array.from(document.querySelectorAll('#pattern g.mountain line, #pattern g.valley line'))"
      ".map(l => [l.parentNode.getAttribute('class'), +l.getAttribute('x1'), +l.getAttribute('y1'),"
      " +l.getAttribute('x2'), +l.getAttribute('y2')])");
  EXPECT_NE(std::find(lines.begin(), lines.end(), json{"mountain", 15, -10, 85, -10}), lines.end()) << lines.dump();
  EXPECT_NE(std::find(lines.begin(), lines.end(), json{"valley", 15, -40, 85, -40}), lines.end()) << lines.dump();
  two_clicks(42, 35, 0, 65, 20);
  ASSERT_EQ(items(), 2) << text("edit-error");
  EXPECT_EQ(text("verdict").rfind("Pops up", 0), 0u) << text("verdict");
  const json saved = design();
  EXPECT_EQ(saved["items"][0]["outline"], json::parse("[[15, 0], [85, 0], [85, 40], [15, 40]]"));
  EXPECT_EQ(saved["items"][1]["outline"], json::parse("[[35, 0], [65, 0], [65, 20], [35, 20]]"));
  const popcut::Pattern porch =
      popcut::make_pattern(popcut::parse_model(read_file(kSrc + "/examples/faces/porch.json"), "porch"));
  EXPECT_EQ(popcut::testing::compare_patterns(popcut::parse_design(saved.dump(), "saved").pattern(), porch), "")
      << "the saved design is examples/faces/porch.json's card";
  EXPECT_TRUE(b_.run("return !!document.querySelector('#view3d canvas')").get<bool>())
      << "the 3D view renders (WebGL): " << text("view3d");
}

TEST_F(Designer, UndoAndRedoTenStepsShowEachState) {
  std::vector<std::string> patterns = {
      b_.run("return document.getElementById('pattern').innerHTML").get<std::string>()};
  for (int i = 0; i < 10; ++i) {
    two_clicks(5 + 5 * i, 5 + 2 * i, 0, 95 - 2 * i, 70 - 5 * i);
    ASSERT_EQ(items(), i + 1) << text("edit-error");
    patterns.push_back(b_.run("return document.getElementById('pattern').innerHTML").get<std::string>());
  }
  for (int i = 9; i >= 0; --i) {
    const int before = revision();
    b_.click("#undo");
    ASSERT_TRUE(wait_until([&] { return revision() > before; }, 60));
    EXPECT_EQ(items(), i);
    EXPECT_EQ(b_.run("return document.getElementById('pattern').innerHTML").get<std::string>(),
              patterns[static_cast<std::size_t>(i)]);
  }
  EXPECT_TRUE(b_.run("return document.getElementById('undo').disabled").get<bool>());
  for (int i = 1; i <= 10; ++i) {
    const int before = revision();
    b_.click("#redo");
    ASSERT_TRUE(wait_until([&] { return revision() > before; }, 60));
    EXPECT_EQ(items(), i);
    EXPECT_EQ(b_.run("return document.getElementById('pattern').innerHTML").get<std::string>(),
              patterns[static_cast<std::size_t>(i)]);
  }
  // Edit to repaint in this browser, for the note (not asserted: timings belong to benchmarks).
  std::vector<double> ms = b_.run("return window.designTimings").get<std::vector<double>>();
  std::sort(ms.begin(), ms.end());
  if (!ms.empty())
    std::printf("edit to repaint: %zu edits, p50 %.1f ms, max %.1f ms\n", ms.size(), ms[ms.size() / 2], ms.back());
}

TEST_F(Designer, AWallWithoutTopsShowsTheFaceThatWouldNotStand) {
  b_.click("#tops");
  two_clicks(30, 20, 0, 80, 40);
  ASSERT_EQ(items(), 1) << text("edit-error");
  EXPECT_EQ(text("verdict").rfind("Does not pop up", 0), 0u) << text("verdict");
  EXPECT_EQ(b_.run("return document.querySelectorAll('#pattern .failing-face').length").get<int>(), 1)
      << "the wall is painted as failing in the pattern";
  const std::string check = text("check");
  EXPECT_NE(check.find("would not stand"), std::string::npos) << check;
  EXPECT_NE(check.find("not reached from the back board"), std::string::npos) << check;
  EXPECT_EQ(design()["items"][0].value("top", true), false);
  screenshot("design-failing.png");
}

TEST_F(Designer, ARefusedEditSaysWhyAndChangesNothing) {
  two_clicks(30, 15, 0, 85, 40);
  ASSERT_EQ(items(), 1);
  b_.click(".tool[data-tool='opening']");
  two_clicks(50, 20, 10, 30, 20);  // no wall stands at depth 50
  ASSERT_TRUE(wait_until([&] { return !text("edit-error").empty(); }, 30));
  EXPECT_NE(text("edit-error").find("not inside"), std::string::npos) << text("edit-error");
  EXPECT_EQ(items(), 1);
  EXPECT_EQ(design()["items"].size(), 1u) << "the session is unchanged";
}

TEST_F(Designer, ADoorTwoRoundWindowsAndANameInLettersGoToTheCutter) {
  b_.type("#name", "House");
  b_.run("document.getElementById('name').dispatchEvent(new Event('change'))");
  two_clicks(30, 15, 0, 85, 45);
  b_.click(".tool[data-tool='opening']");
  two_clicks(30, 45, 0, 55, 20);
  // Two round windows: one drawn with the circle tool (centre, then a point on the circle), one its mirror.
  b_.click("#mirror");
  b_.click(".shape[data-shape='circle']");
  two_clicks(30, 25, 30, 30, 30);
  ASSERT_EQ(items(), 3) << text("edit-error");
  EXPECT_GE(design()["items"][2]["outline"].size(), 30u) << "a circle within 0.02 mm of a 5 mm radius";
  EXPECT_EQ(text("verdict").rfind("Pops up", 0), 0u) << text("verdict") << " / " << text("check");
  EXPECT_NE(text("check").find("cut out"), std::string::npos) << "the discs drop out of the windows: " << text("check");
  EXPECT_EQ(design().value("name", ""), "House");
  // The owner's name in letters, on a wall of its own in front of the house, beside the door.
  b_.click("#mirror");
  b_.click(".tool[data-tool='wall']");
  b_.click(".shape[data-shape='text']");
  b_.type("#text-string", "Ada");
  b_.type("#text-size", "8");
  b_.type("#plane-t", "40");
  const int before = revision();
  click_plane(60, 0);
  ASSERT_TRUE(wait_until([&] { return revision() > before || !text("edit-error").empty(); }, 60));
  ASSERT_EQ(items(), 4) << text("edit-error");
  const json letters = design()["items"][3];
  EXPECT_EQ(letters["text"], json({{"string", "Ada"}, {"font", "DejaVu Sans"}, {"size", 8}})) << letters.dump();
  EXPECT_EQ(letters["at"], json({60, 0}));
  EXPECT_EQ(text("verdict").rfind("Pops up", 0), 0u) << text("verdict") << " / " << text("check");
  EXPECT_EQ(b_.run("return document.querySelectorAll('#edit > text').length").get<int>(), 1)
      << "the letters are shown where they stand on the plane (besides the preview under the cursor)";
  b_.run("const a = document.getElementById('angle'); a.value = 75; a.dispatchEvent(new Event('input'));");
  screenshot("design.png");
  b_.click("#send");
  std::string state;
  ASSERT_TRUE(wait_until(
      [&] {
        state = b_.run("return document.getElementById('job').dataset.state || ''").get<std::string>();
        return state == "done" || state == "failed" || state == "cancelled";
      },
      300))
      << text("job");
  EXPECT_EQ(state, "done") << text("job");
}

TEST_F(Designer, APolygonClosesOnADoubleClickOrItsFirstCornerAndTheDraftComesBackOnReload) {
  b_.click(".shape[data-shape='polygon']");
  b_.type("#plane-t", "20");
  int before = revision();
  // A gable wall: four corners, the last double-clicked.
  for (const auto& [a, z] : std::vector<std::pair<double, double>>{{10, 0}, {40, 0}, {40, 30}, {25, 40}}) {
    click_plane(a, z);
  }
  click_plane(25, 40);
  ASSERT_TRUE(wait_until([&] { return revision() > before || !text("edit-error").empty(); }, 60));
  ASSERT_EQ(items(), 1) << text("edit-error");
  EXPECT_EQ(design()["items"][0]["outline"].size(), 4u);
  // A second wall closed by clicking its first corner again.
  b_.type("#plane-t", "40");
  before = revision();
  for (const auto& [a, z] : std::vector<std::pair<double, double>>{{60, 0}, {90, 0}, {90, 20}, {60, 20}, {60, 0}}) {
    click_plane(a, z);
  }
  ASSERT_TRUE(wait_until([&] { return revision() > before || !text("edit-error").empty(); }, 60));
  ASSERT_EQ(items(), 2) << text("edit-error");
  EXPECT_TRUE(text("edit-error").empty()) << text("edit-error");
  // The draft is popcutd's: a reload of the page shows it again, from the server.
  b_.session("POST", "/url", {{"url", "http://127.0.0.1:" + std::to_string(d_.port()) + "/design?token=" + kToken}});
  ASSERT_TRUE(wait_until([&] { return revision() >= 1; }, 60));
  EXPECT_EQ(items(), 2);
}

// Ledge off: a square window's paper is cut all round and drops out instead of folding down.
TEST_F(Designer, AWindowWithoutALedgeDropsOut) {
  two_clicks(30, 15, 0, 85, 45);
  b_.click(".tool[data-tool='opening']");
  b_.click("#ledge");
  two_clicks(30, 40, 20, 60, 35);
  ASSERT_EQ(items(), 2) << text("edit-error");
  EXPECT_EQ(design()["items"][1].value("ledge", true), false) << design()["items"][1].dump();
  EXPECT_NE(text("items").find("drops out"), std::string::npos) << text("items");
  EXPECT_EQ(text("verdict").rfind("Pops up", 0), 0u) << text("verdict");
  EXPECT_NE(text("check").find("cut out"), std::string::npos) << text("check");
}

// Open… takes a webOAcard card: the page shows its faces as items (named after the file), its
// pattern and its check, and the draft is the card popcut reads from the file.
TEST_F(Designer, OpeningAWebOAcardCardShowsItsFacesAsItemsToEditOn) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  const std::string house = popcut::testing::shared_testdata("webOAcard/demo/house.oa");
  const std::size_t faces =
      popcut::design_from_oa(popcut::parse_oa_card(read_file(house), house), house).items().size();
  const int before = revision();
  b_.choose_file("#open", house);
  ASSERT_TRUE(wait_until([&] { return items() == static_cast<int>(faces) || !text("edit-error").empty(); }, 60))
      << text("edit-error") << " / items: " << items() << " of " << faces;
  ASSERT_TRUE(wait_until([&] { return revision() > before && design().value("name", "") == "house"; }, 60))
      << "the draft takes the file's name: " << design().dump().substr(0, 200);
  EXPECT_EQ(b_.run("return document.getElementById('name').value").get<std::string>(), "house");
  EXPECT_EQ(text("verdict").rfind("Pops up", 0), 0u) << text("verdict");
  EXPECT_EQ(popcut::testing::compare_patterns(popcut::parse_design(design().dump(), "saved").pattern(),
                                              popcut::make_pattern(popcut::parse_oa_model(read_file(house), house))),
            "");
  b_.run("const a = document.getElementById('angle'); a.value = 75; a.dispatchEvent(new Event('input'));");
  screenshot("design-oa.png");
}

}  // namespace
