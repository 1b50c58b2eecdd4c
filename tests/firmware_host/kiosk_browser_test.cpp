// The kiosk page in headless Chromium (driven over WebDriver by chromedriver) against a real popcutd.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <fstream>
#include <thread>

#include "kiosk_browser.h"
#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::base64_decode;
using popcut::testing::Browser;
using popcut::testing::get_json;
using popcut::testing::kRendered;
using popcut::testing::PopcutdProcess;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;

TEST(Kiosk, PicksAnExampleQueuesItAndSeesItCut) {
  TempDir dir("popcut-kiosk");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url",
            {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=kiosk-change-me-0123456789"}});
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.querySelectorAll('#example option').length").get<int>() > 3; }, 60))
      << "the page lists the examples";
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.querySelectorAll('#device option').length").get<int>() == 2; }, 60))
      << "the page lists both cutters";
  b.click("#example option[value='voxel-castle']");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 60))
      << "the pattern renders and Queue becomes available; page says: "
      << b.run("return document.body.innerText").dump();
  ASSERT_TRUE(wait_until([&] { return b.run(kRendered + "return rendered('preview')").get<bool>(); }, 60))
      << "the card preview shows";
  EXPECT_TRUE(b.run(kRendered + "return rendered('pattern')").get<bool>()) << "the pattern shows";
  // The slider asks for another angle; the picture changes.
  const std::string before = b.run("return document.getElementById('preview').src").get<std::string>();
  b.run("const a = document.getElementById('angle'); a.value = 150; a.dispatchEvent(new Event('input'));");
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.getElementById('preview').src").get<std::string>() != before; }, 60))
      << "moving the opening-angle slider renders a new preview";
  EXPECT_EQ(b.run("return document.getElementById('angle-value').textContent").get<std::string>(), "150")
      << "the angle is shown";
  const std::string at150 = b.run("return document.getElementById('preview').src").get<std::string>();
  b.run("const a = document.getElementById('angle'); a.value = 60; a.dispatchEvent(new Event('input'));");
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.getElementById('preview').src").get<std::string>() != at150; }, 60))
      << "and again at 60 degrees";
  b.click("#device option[value='sim-b']");
  b.click("#queue");
  ASSERT_TRUE(
      wait_until([&] { return b.run("return document.querySelectorAll('#jobs .job').length").get<int>() == 1; }, 60))
      << "the queued card appears under My cards";
  std::string state;
  ASSERT_TRUE(wait_until(
      [&] {
        state = b.run("return document.querySelector('#jobs .job').dataset.state").get<std::string>();
        return state == "done" || state == "failed" || state == "cancelled";
      },
      300))
      << "the card finishes on the simulated cutter";
  EXPECT_EQ(state, "done") << "the card was cut; page: " << b.run("return document.body.innerText").dump();
  EXPECT_EQ(b.run("return document.querySelector('#jobs .job progress').value").get<double>(), 1.0)
      << "the progress bar is full";
  EXPECT_NE(b.run("return document.querySelector('#jobs .job .where').textContent").get<std::string>().find("on sim-b"),
            std::string::npos)
      << "it says which cutter cut it";
  {
    // The press sent its own Idempotency-Key, a version 4 UUID, recorded with the job.
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open_v2((dir.path() / "data" / "jobs.db").c_str(), &db, SQLITE_OPEN_READONLY, nullptr),
              SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT owner, key FROM idempotency", -1, &st, nullptr), SQLITE_OK);
    ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
    EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "kiosk");
    const std::string key = reinterpret_cast<const char*>(sqlite3_column_text(st, 1));
    EXPECT_EQ(key.size(), 36u) << key;
    EXPECT_EQ(key[14], '4') << key;
    EXPECT_EQ(sqlite3_step(st), SQLITE_DONE) << "one press, one key";
    sqlite3_finalize(st);
    sqlite3_close(db);
  }
  // Every kiosk file came from the daemon: nothing from elsewhere.
  EXPECT_EQ(
      b.run("return performance.getEntriesByType('resource').filter(e => !e.name.startsWith(location.origin)).length")
          .get<int>(),
      0)
      << "no resource is loaded from outside popcutd";
  const std::string png = base64_decode(b.session("GET", "/screenshot").get<std::string>());
  EXPECT_EQ(png.substr(1, 3), "PNG") << "a screenshot of the page";
  std::ofstream(POPCUT_KIOSK_SCREENSHOT, std::ios::binary) << png;
}

TEST(Kiosk, UploadsAModelPausesAndContinuesAWaitingCardAndCancelsItsOwnJobWhileItCuts) {
  TempDir dir("popcut-kiosk");
  const std::string cfg = dir.write(
      "slow.toml", "[server]\ndata_dir = \"x\"\n[[device]]\nname = \"slow\"\nprofile = \"" + kSrc +
                       "/configs/devices/sim.toml\"\ntransport = \"sim\"\nsim_time_scale = 1\nsim_slowdown = 20\n"
                       "confirm_sheet = true\n[[token]]\nname = \"kiosk\"\ntoken = \"kiosk-change-me-0123456789\"\n");
  PopcutdProcess d(POPCUTD, cfg, (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url",
            {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=kiosk-change-me-0123456789"}});
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.querySelectorAll('#example option').length").get<int>() > 3; }, 60))
      << "the page lists the examples";
  // This time the model comes from a file, as a visitor's own would.
  const json input = b.session("POST", "/element", {{"using", "css selector"}, {"value", "#upload"}});
  b.session("POST", "/element/" + input.begin().value().get<std::string>() + "/value",
            {{"text", kSrc + "/examples/voxel/castle.json"}});
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 60))
      << "the uploaded model renders and can be queued; page: " << b.run("return document.body.innerText").dump();
  EXPECT_EQ(b.run("return document.getElementById('model-name').textContent").get<std::string>(), "castle")
      << "named after the file";
  b.click("#queue");
  ASSERT_TRUE(wait_until(
      [&] {
        return b.run("const j = document.querySelector('#jobs .job'); return j ? j.dataset.state : ''")
                   .get<std::string>() == "cutting";
      },
      120))
      << "the castle is being cut (slowly)";
  EXPECT_FALSE(b.run("return document.querySelector('#jobs .job .pause').hidden").get<bool>())
      << "a job being cut can be paused";
  // A second card waits behind it: Pause holds it, Continue puts it back in line, Cancel gives it up.
  b.click("#queue");
  ASSERT_TRUE(wait_until(
      [&] {
        return b.run(
                    "const j = document.querySelectorAll('#jobs .job'); return j.length == 2 ? j[0].dataset.state : ''")
                   .get<std::string>() == "ready";
      },
      60))
      << "the second card is in line; page: " << b.run("return document.body.innerText").dump();
  const std::string second = "#jobs .job:first-child";
  httplib::Client c = d.client("kiosk-change-me-0123456789");
  const std::string second_id = b.run("return document.querySelector('" + second + "').dataset.id").get<std::string>();
  EXPECT_TRUE(b.run("return document.querySelector('" + second + " .continue').hidden").get<bool>());
  b.click(second + " .pause");
  const auto state_of = [&](const std::string& selector) {
    return b.run("return document.querySelector('" + selector + "').dataset.state").get<std::string>();
  };
  ASSERT_TRUE(wait_until([&] { return state_of(second) == "paused"; }, 60)) << "Pause holds the waiting card";
  EXPECT_EQ(get_json(c, "/api/v1/jobs/" + second_id).body["state"], "paused");
  EXPECT_TRUE(b.run("return document.querySelector('" + second + " .pause').hidden").get<bool>());
  b.click(second + " .continue");
  ASSERT_TRUE(wait_until([&] { return state_of(second) == "ready"; }, 60)) << "Continue puts it back in line";
  EXPECT_TRUE(b.run("return document.querySelector('" + second + " .continue').hidden").get<bool>());
  b.click(second + " .cancel");
  ASSERT_TRUE(wait_until([&] { return state_of(second) == "cancelled"; }, 60));
  b.click("#jobs .job:nth-child(2) .cancel");
  ASSERT_TRUE(wait_until([&] { return state_of("#jobs .job:nth-child(2)") == "cancelled"; }, 120))
      << "the kiosk cancels its own job mid-cut";
  EXPECT_TRUE(b.run("return document.querySelector('#jobs .job:nth-child(2) .cancel').hidden").get<bool>())
      << "no cancel button on a cancelled job";
  // The cancelled cut used the sheet: its owner is offered "Sheet loaded", and pressing it frees the cutter.
  EXPECT_EQ(get_json(c, "/api/v1/devices").body["devices"][0]["sheet"], "awaiting_sheet");
  ASSERT_TRUE(wait_until(
      [&] { return !b.run("return document.querySelector('#jobs .job:nth-child(2) .sheet').hidden").get<bool>(); }, 60))
      << "the owner's job shows the button; page: " << b.run("return document.body.innerText").dump();
  EXPECT_EQ(b.run("return document.querySelector('#jobs .job:nth-child(2) .sheet').textContent").get<std::string>(),
            "Sheet loaded");
  b.click("#jobs .job:nth-child(2) .sheet");
  ASSERT_TRUE(wait_until([&] { return get_json(c, "/api/v1/devices").body["devices"][0]["sheet"] == "loaded"; }, 60))
      << "the press confirmed the sheet";
  EXPECT_TRUE(wait_until(
      [&] { return b.run("return document.querySelector('#jobs .job:nth-child(2) .sheet').hidden").get<bool>(); }, 60))
      << "and the button goes";
}

// A visitor's 3D mesh: popcutd imports it with the options on the page, the card shows, it is cut.
TEST(Kiosk, UploadsAMeshImportsItAndSeesItCut) {
  TempDir dir("popcut-kiosk");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url",
            {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=kiosk-change-me-0123456789"}});
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.querySelectorAll('#device option').length").get<int>() == 2; }, 60))
      << "the page lists both cutters";
  b.run("document.getElementById('resolution').value = 30;");
  const json input = b.session("POST", "/element", {{"using", "css selector"}, {"value", "#upload"}});
  b.session("POST", "/element/" + input.begin().value().get<std::string>() + "/value",
            {{"text", kSrc + "/examples/meshes/house.obj"}});
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 120))
      << "the mesh is imported and can be queued; page: " << b.run("return document.body.innerText").dump();
  EXPECT_FALSE(b.run("return document.getElementById('import').hidden").get<bool>())
      << "the import options show for a mesh";
  EXPECT_EQ(
      b.run("return document.getElementById('model-name').textContent").get<std::string>().rfind("house.obj: 30 x ", 0),
      0u)
      << "the page says what the import made: "
      << b.run("return document.getElementById('model-name').textContent").dump();
  ASSERT_TRUE(wait_until([&] { return b.run(kRendered + "return rendered('preview')").get<bool>(); }, 60))
      << "the card preview shows";
  // A bad option: the importer's message shows on the page.
  b.run("document.getElementById('up').value = '-y';");
  b.click("#reimport");
  ASSERT_TRUE(
      wait_until([&] { return !b.run("return document.getElementById('model-error').hidden").get<bool>(); }, 60))
      << "an impossible orientation is refused";
  EXPECT_NE(b.run("return document.getElementById('model-error').textContent").get<std::string>().find("perpendicular"),
            std::string::npos)
      << "with the importer's message: " << b.run("return document.getElementById('model-error').textContent").dump();
  b.run("document.getElementById('up').value = '+z';");
  b.click("#reimport");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 120))
      << "imported again with a good orientation";
  b.click("#queue");
  std::string state;
  ASSERT_TRUE(wait_until(
      [&] {
        state =
            b.run("const j = document.querySelector('#jobs .job'); return j ? j.dataset.state : ''").get<std::string>();
        return state == "done" || state == "failed" || state == "cancelled";
      },
      300))
      << "the card finishes on the simulated cutter";
  EXPECT_EQ(state, "done") << "the imported card was cut; page: " << b.run("return document.body.innerText").dump();
  const std::string title = b.run("return document.querySelector('#jobs .job .title').textContent").get<std::string>();
  EXPECT_EQ(title.substr(title.find(' ') + 1), "house")
      << "the job is named after the file as the API names it: " << title;
}

}  // namespace

// The material chosen on the page reaches the job: stored with it, cut with its forces.
TEST(Kiosk, TheMaterialChoiceReachesTheJob) {
  TempDir dir("popcut-kiosk-material");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url",
            {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=kiosk-change-me-0123456789"}});
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.querySelectorAll('#material option').length").get<int>() == 8; }, 60))
      << "the page offers the seven shipped materials and the cutter's own settings";
  EXPECT_EQ(b.run("return document.querySelector('#material').value").get<std::string>(), "")
      << "the cutter's own settings by default";
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.querySelectorAll('#example option').length").get<int>() > 3; }, 60));
  b.click("#example option[value='voxel-castle']");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 60));
  b.click("#material option[value='card-220']");
  b.click("#queue");
  ASSERT_TRUE(
      wait_until([&] { return b.run("return document.querySelectorAll('#jobs .job').length").get<int>() == 1; }, 60));
  const int id = std::stoi(b.run("return document.querySelector('#jobs .job').dataset.id").get<std::string>());
  httplib::Client c = d.client("admin-change-me-0123456789");
  json job;
  ASSERT_TRUE(wait_until(
      [&] {
        job = popcut::testing::get_json(c, "/api/v1/jobs/" + std::to_string(id)).body;
        return job["state"] == "done" || job["state"] == "failed";
      },
      300));
  EXPECT_EQ(job["state"], "done") << job.dump();
  EXPECT_EQ(job["material"], "card-220") << "the job holds the material the page chose";
  EXPECT_NE(b.run("return document.querySelector('#jobs .job .where').textContent").get<std::string>().find("card-220"),
            std::string::npos)
      << "and the page says so";
}
