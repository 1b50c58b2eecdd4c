// The operator page in headless Chromium (WebDriver) against a real popcutd: a shift on two simulated cutters.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>

#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "kiosk_browser.h"
#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::base64_decode;
using popcut::testing::Browser;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kAdmin = "admin-change-me-0123456789";
const std::string kKiosk = "kiosk-change-me-0123456789";

// sim-a cuts a castle in about 7 s (watchable); `slow` at its own pace (first ten minutes, then about 15 s).
std::string shift_config(const TempDir& dir, const std::string& name, double slow_scale, double slow_slowdown) {
  const std::string sim = kSrc + "/configs/devices/sim.toml";
  return dir.write(name,
                   "[server]\ndata_dir = \"x\"\n"
                   "[[device]]\nname = \"sim-a\"\nprofile = \"" +
                       sim +
                       "\"\ntransport = \"sim\"\nsim_time_scale = 0.25\n"
                       "[[device]]\nname = \"slow\"\nprofile = \"" +
                       sim + "\"\ntransport = \"sim\"\nsim_time_scale = " + std::to_string(slow_scale) +
                       "\nsim_slowdown = " + std::to_string(slow_slowdown) +
                       "\n"
                       "[[token]]\nname = \"kiosk\"\ntoken = \"" +
                       kKiosk +
                       "\"\n"
                       "[[token]]\nname = \"admin\"\ntoken = \"" +
                       kAdmin + "\"\nrole = \"admin\"\n");
}

std::int64_t submit(httplib::Client& c, const std::string& device, const std::string& name) {
  const std::string model = popcut::testing::read_file(kSrc + "/examples/voxel/castle.json");
  const popcut::testing::Reply r = post_json(
      c, "/api/v1/jobs", R"({"device": ")" + device + R"(", "name": ")" + name + R"(", "model": )" + model + "}");
  EXPECT_EQ(r.status, 201) << r.body.dump();
  return r.body.value("id", std::int64_t{0});
}

json job(httplib::Client& c, std::int64_t id) { return get_json(c, "/api/v1/jobs/" + std::to_string(id)).body; }

// The page as the operator sees it: small helpers over WebDriver.
struct Page {
  Browser& b;
  std::string js(const std::string& expr) {
    return b.run("const e = " + expr + "; return e === null ? '' : String(e);").get<std::string>();
  }
  std::string text(const std::string& css) {
    return b.run("const e = document.querySelector(" + json(css).dump() + "); return e ? e.textContent : ''")
        .get<std::string>();
  }
  bool exists(const std::string& css) {
    return b.run("return document.querySelector(" + json(css).dump() + ") !== null").get<bool>();
  }
  std::string attr(const std::string& css, const std::string& name) {
    return b
        .run("const e = document.querySelector(" + json(css).dump() + "); return e ? (e.getAttribute(" +
             json(name).dump() + ") || '') : ''")
        .get<std::string>();
  }
  // Clicks and waits for the page to say how the action went (the notice banner).
  std::string act(const std::string& css, const std::string& what) {
    b.run("document.getElementById('notice').textContent = '';");
    b.click(css);
    std::string said;
    wait_until(
        [&] {
          said = text("#notice");
          return said.rfind(what, 0) == 0;
        },
        30);
    return said;
  }
  std::string job_state(std::int64_t id) { return attr(".qjob[data-id='" + std::to_string(id) + "']", "data-state"); }
  // The page's viewport at width x height (the window's frame added), from the top.
  void screenshot(int width, int height, const std::string& path) {
    b.session("POST", "/window/rect", {{"width", width}, {"height", height}});
    const int frame = b.run("return window.outerHeight - window.innerHeight").get<int>();
    b.session("POST", "/window/rect", {{"width", width}, {"height", height + frame}});
    b.run("window.scrollTo(0, 0);");
    wait_until([&] { return b.run("return window.innerWidth").get<int>() == width; }, 10);
    const std::string png = base64_decode(b.session("GET", "/screenshot").get<std::string>());
    EXPECT_EQ(png.substr(1, 3), "PNG");
    std::ofstream(path, std::ios::binary) << png;
  }
};

std::map<std::int64_t, std::map<std::string, std::string>> jobs_in_database(const std::string& path) {
  std::map<std::int64_t, std::map<std::string, std::string>> out;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return out;
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(db,
                     "SELECT id, state, device, sim_match, resume_point, cutting_s > 0, strokes_sent = strokes_total "
                     "FROM jobs",
                     -1, &st, nullptr);
  const char* names[] = {"id", "state", "device", "sim_match", "resume_point", "cut_time", "all_sent"};
  while (sqlite3_step(st) == SQLITE_ROW) {
    auto& row = out[sqlite3_column_int64(st, 0)];
    for (int i = 1; i < 7; ++i) {
      const unsigned char* t = sqlite3_column_text(st, i);
      row[names[i]] = t ? reinterpret_cast<const char*>(t) : "";
    }
  }
  sqlite3_finalize(st);
  sqlite3_close(db);
  return out;
}

// One shift, step by step: jobs a (overnight, interrupted), b (bird), c (cat), e (eel).
class OperatorShift : public ::testing::Test {
 protected:
  TempDir dir_{"popcut-operator"};
  std::string data_ = (dir_.path() / "data").string();
  std::unique_ptr<PopcutdProcess> d_;
  std::unique_ptr<Browser> browser_;
  std::int64_t a_ = 0, b_ = 0, c_ = 0, e_ = 0;

  static std::string row(std::int64_t id) { return ".qjob[data-id='" + std::to_string(id) + "']"; }
  json job_now(std::int64_t id) {
    httplib::Client k = d_->client(kKiosk);
    return job(k, id);
  }

  // Before the shift: a long cut on `slow`, and popcutd stopped (SIGTERM) in the middle of it.
  void interrupt_overnight() {
    PopcutdProcess first(POPCUTD, shift_config(dir_, "first.toml", 1, 20), data_);
    httplib::Client k = first.client(kKiosk);
    a_ = submit(k, "slow", "overnight");
    ASSERT_TRUE(wait_until(
        [&] {
          const json j = job(k, a_);
          return j["state"] == "cutting" && j.value("strokes_sent", 0) >= 2;
        },
        120))
        << first.log();
    EXPECT_EQ(first.stop(SIGTERM), 0);
  }

  void type_token(const std::string& token) {
    const json input = browser_->session("POST", "/element", {{"using", "css selector"}, {"value", "#admin-token"}});
    browser_->session("POST", "/element/" + input.begin().value().get<std::string>() + "/value", {{"text", token}});
    browser_->click("#sign-in");
  }

  void sign_in(Page& p) {
    browser_->session("POST", "/window/rect", {{"width", 1280}, {"height", 800}});
    browser_->session("POST", "/url", {{"url", "http://127.0.0.1:" + std::to_string(d_->port()) + "/operator"}});
    ASSERT_TRUE(wait_until([&] { return !p.b.run("return document.getElementById('login').hidden").get<bool>(); }, 30))
        << "the page asks for a token";
    type_token(kKiosk);
    ASSERT_TRUE(wait_until([&] { return p.text("#login-error").find("not an admin token") != std::string::npos; }, 30))
        << "a kiosk token is refused: " << p.text("#login-error");
    type_token(kAdmin);
    ASSERT_TRUE(
        wait_until([&] { return p.exists(".device[data-name='slow']") && p.exists(".device[data-name='sim-a']"); }, 30))
        << "both cutters show: " << p.text("body");
    EXPECT_EQ(p.b.run("return sessionStorage.getItem('popcut-admin-token')").get<std::string>(), kAdmin)
        << "the token is kept for this tab";
    EXPECT_EQ(p.job_state(a_), "interrupted") << "the job cut short overnight waits in the queue";
    EXPECT_TRUE(p.exists(row(a_) + " button.resume")) << "with a Resume button";
  }

  // The operator pauses sim-a, and three cards are queued for it from the kiosk.
  void pause_and_queue(Page& p) {
    EXPECT_EQ(p.act(".device[data-name='sim-a'] .pause-device", "Pausing sim-a"), "Pausing sim-a: done.");
    ASSERT_TRUE(wait_until([&] { return p.attr(".device[data-name='sim-a']", "data-state") == "paused"; }, 30));
    EXPECT_NE(p.text(".device[data-name='sim-a'] .big-state").find("PAUSED"), std::string::npos) << "said in words";
    httplib::Client k = d_->client(kKiosk);
    b_ = submit(k, "sim-a", "bird");
    c_ = submit(k, "sim-a", "cat");
    e_ = submit(k, "sim-a", "eel");
    ASSERT_TRUE(wait_until([&] { return p.job_state(e_) == "ready" && p.job_state(c_) == "ready"; }, 120))
        << "the jobs wait, planned: " << p.text("#queue");
  }

  // A move is done, and the moved job is then ahead of the other.
  void expect_moved(const std::string& said, std::int64_t moved, std::int64_t before) {
    EXPECT_EQ(said, "Moving job " + std::to_string(moved) + " ahead of job " + std::to_string(before) + ": done.");
    EXPECT_LT(job_now(moved)["place_in_line"].get<int>(), job_now(before)["place_in_line"].get<int>()) << said;
  }

  // Eel ahead of cat by ▲, then cat onto bird by dragging (the page's drag-and-drop handlers).
  void reorder(Page& p) {
    expect_moved(p.act(row(e_) + " button.up", "Moving job " + std::to_string(e_)), e_, c_);
    p.b.run("document.getElementById('notice').textContent = '';");
    p.b.run("const dt = new DataTransfer(), from = document.querySelector(" + json(row(c_)).dump() +
            "), to = document.querySelector(" + json(row(b_)).dump() +
            ");"
            "const ev = (t) => new DragEvent(t, {dataTransfer: dt, bubbles: true, cancelable: true});"
            "from.dispatchEvent(ev('dragstart')); to.dispatchEvent(ev('dragover')); to.dispatchEvent(ev('drop'));"
            "from.dispatchEvent(ev('dragend'));");
    std::string dragged;
    ASSERT_TRUE(
        wait_until([&] { return (dragged = p.text("#notice")).rfind("Moving job " + std::to_string(c_), 0) == 0; }, 30))
        << "a drop asks popcutd to move the job: " << dragged;
    expect_moved(dragged, c_, b_);
  }

  // A simulated cutter's sheet is always loaded: no button for it.
  void sheet_loaded(Page& p) {
    httplib::Client k = d_->client(kKiosk);
    const json sim_a = get_json(k, "/api/v1/devices").body["devices"][0];
    ASSERT_TRUE(sim_a.contains("sheet")) << sim_a.dump();
    EXPECT_EQ(p.exists(".device[data-name='sim-a'] button.sheet"), sim_a["sheet"] != "loaded");
  }

  // Cat is cancelled while it waits; the cutter goes back to work; the overnight job is resumed and watched.
  void cut(Page& p) {
    const std::string c = std::to_string(c_), a = std::to_string(a_);
    EXPECT_EQ(p.act(row(c_) + " button.cancel", "Cancelling job " + c), "Cancelling job " + c + ": done.");
    EXPECT_EQ(p.act(".device[data-name='sim-a'] .resume-device", "Resuming sim-a"), "Resuming sim-a: done.");
    EXPECT_EQ(p.act(row(a_) + " button.resume", "Resuming job " + a), "Resuming job " + a + ": done.");
    double seen = 0;
    ASSERT_TRUE(wait_until(
        [&] {
          const std::string v =
              p.js("(document.querySelector(\".device[data-state='cutting'] progress\") || {value: null}).value");
          seen = v.empty() || v == "null" ? 0 : std::stod(v);
          return seen > 0 && seen < 1;
        },
        120))
        << "a cutter shows its progress part-way: " << p.text("#devices");
    EXPECT_NE(p.text(".device[data-state='cutting'] .big-state").find("CUTTING"), std::string::npos);
    ASSERT_TRUE(wait_until([&] { return p.job_state(a_) == "cutting"; }, 60)) << "the resumed job cuts on slow";
    EXPECT_TRUE(p.exists(row(a_) + " button.pause")) << "a cutting job offers Pause";
    // Mid-shift, as docs/images shows it: a desktop and a portrait tablet.
    p.screenshot(1280, 800, std::string(POPCUT_SCREENSHOT_DIR) + "/operator-desktop.png");
    p.screenshot(800, 1280, std::string(POPCUT_SCREENSHOT_DIR) + "/operator-tablet.png");
    browser_->session("POST", "/window/rect", {{"width", 1280}, {"height", 900}});
  }

  // Pausing a job: paused, then continued.
  void pause_job(Page& p) {
    const std::string a = std::to_string(a_);
    const std::string said = p.act(row(a_) + " button.pause", "Pausing job " + a);
    EXPECT_EQ(said, "Pausing job " + a + ": done.");
    ASSERT_TRUE(wait_until([&] { return p.job_state(a_) == "paused"; }, 60)) << said;
    EXPECT_EQ(p.act(row(a_) + " button.continue", "Continuing job " + a), "Continuing job " + a + ": done.");
  }

  int history_rows(Page& p) {
    return p.b.run("return document.querySelectorAll('#history tr.hjob').length").get<int>();
  }

  // Every job of the shift with its outcome; then the state filter.
  void history(Page& p) {
    const std::string a = "#history tr.hjob[data-id='" + std::to_string(a_) + "']";
    p.b.click("#history-apply");
    ASSERT_TRUE(wait_until([&] { return history_rows(p) == 4 && p.attr(a, "data-state") == "done"; }, 30))
        << p.text("#history");
    EXPECT_EQ(p.attr("#history tr.hjob[data-id='" + std::to_string(c_) + "']", "data-state"), "cancelled");
    EXPECT_NE(p.text(a).find("slow"), std::string::npos) << "cut on slow: " << p.text(a);
    p.b.run("document.getElementById('filter-state').value = 'done';");
    p.b.click("#history-apply");
    ASSERT_TRUE(wait_until([&] { return history_rows(p) == 3; }, 30)) << "only the done jobs: " << p.text("#history");
  }

  // Today's bar and each cutter's hours.
  void chart(Page& p) {
    p.b.run("const s = document.getElementById('stats-days'); s.value = '30'; s.dispatchEvent(new Event('change'));");
    const std::string today = "#chart-days g.day:last-of-type";
    ASSERT_TRUE(wait_until(
        [&] {
          return p.b.run("return document.querySelectorAll('#chart-days g.day').length").get<int>() == 30 &&
                 p.attr(today, "data-done") == "3";
        },
        30))
        << p.attr(today, "data-done");
    EXPECT_EQ(p.attr(today, "data-jobs"), "4") << "four cards submitted today";
    EXPECT_EQ(p.attr(today, "data-cancelled"), "1");
    EXPECT_EQ(p.b.run("return document.querySelectorAll('" + today + " rect').length").get<int>(), 2)
        << "a done and a cancelled part";
    EXPECT_EQ(p.attr("#chart-devices g[data-name='sim-a']", "data-jobs"), "2") << "cat never reached it";
    EXPECT_EQ(p.attr("#chart-devices g[data-name='slow']", "data-jobs"), "1");
    EXPECT_GT(std::stod(p.attr("#chart-devices g[data-name='slow']", "data-cutting-s")), 0);
    EXPECT_EQ(p.attr("#chart-devices g[data-name='sim-a']", "data-failure-rate"), "0");
  }

  // Afterwards, the simulated cuts and the database.
  void check_database() {
    for (const std::int64_t id : {a_, b_, e_})
      EXPECT_EQ(job_now(id).value("sim_match", false), true) << job_now(id).dump();
    EXPECT_EQ(d_->stop(SIGTERM), 0);
    const auto rows = jobs_in_database(data_ + "/jobs.db");
    ASSERT_EQ(rows.size(), 4u) << "no job lost, none added";
    EXPECT_EQ(rows.at(a_).at("state"), "done");
    EXPECT_EQ(rows.at(a_).at("device"), "slow") << "finished on the cutter holding its sheet";
    EXPECT_EQ(rows.at(a_).at("resume_point"), "received");
    for (const std::int64_t id : {a_, b_, e_}) {
      EXPECT_EQ(rows.at(id).at("state"), "done") << "job " << id;
      EXPECT_EQ(rows.at(id).at("sim_match"), "1") << "job " << id << " cut exactly as planned";
      EXPECT_EQ(rows.at(id).at("all_sent"), "1") << "job " << id;
      EXPECT_EQ(rows.at(id).at("cut_time"), "1") << "job " << id << " has its cutting time";
    }
    EXPECT_EQ(rows.at(b_).at("device"), "sim-a");
    EXPECT_EQ(rows.at(c_).at("state"), "cancelled");
    EXPECT_EQ(rows.at(c_).at("device"), "") << "the cancelled card never reached a cutter";
    EXPECT_EQ(rows.at(c_).at("cut_time"), "0");
  }
};

TEST_F(OperatorShift, RunsAShiftOnTwoCutters) {
  ASSERT_NO_FATAL_FAILURE(interrupt_overnight());
  d_ = std::make_unique<PopcutdProcess>(POPCUTD, shift_config(dir_, "shift.toml", 0.5, 1), data_);
  ASSERT_EQ(job_now(a_)["state"], "interrupted");
  browser_ = std::make_unique<Browser>((dir_.path() / "chromium").string());
  Page p{*browser_};
  ASSERT_NO_FATAL_FAILURE(sign_in(p));
  ASSERT_NO_FATAL_FAILURE(pause_and_queue(p));
  ASSERT_NO_FATAL_FAILURE(reorder(p));
  ASSERT_NO_FATAL_FAILURE(sheet_loaded(p));
  ASSERT_NO_FATAL_FAILURE(cut(p));
  ASSERT_NO_FATAL_FAILURE(pause_job(p));
  for (const std::int64_t id : {a_, b_, e_}) {
    ASSERT_TRUE(wait_until([&] { return job_now(id)["state"] == "done"; }, 300))
        << "job " << id << ": " << job_now(id).dump();
  }
  ASSERT_NO_FATAL_FAILURE(history(p));
  ASSERT_NO_FATAL_FAILURE(chart(p));
  EXPECT_EQ(
      p.b.run("return performance.getEntriesByType('resource').filter(e => !e.name.startsWith(location.origin)).length")
          .get<int>(),
      0)
      << "nothing is loaded from outside popcutd";
  p.screenshot(1280, 2400, std::string(POPCUT_SCREENSHOT_DIR) + "/operator-end.png");
  check_database();
}

}  // namespace
