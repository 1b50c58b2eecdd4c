// popcutd driving serial cutters end to end: sim-plotter processes on pseudo-terminals, power cycles, kills and
// resumes.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <set>
#include <sstream>

#include "cut_job.h"
#include "popcut/drivers/profile.h"
#include "popcutd_fixture.h"
#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::read_file;
using popcut::testing::Reply;
using popcut::testing::wait_until;
using namespace popcut::testing::e2e;

// popcutd driving a serial cutter: `popcut sim-plotter` on a pseudo-terminal (its own process,
// one session each: a fresh one is a power-cycled cutter), libserialport under the modem-line shim.
// popcutd is restarted on the data directory whenever the cutter's port changes.
class SerialPopcutd : public PopcutClient {
 protected:
  void SetUp() override {
    // The simulator's profile (XON/XOFF, ESC.O) with the plotters' 256-byte buffer and shorter waits.
    profile_ = dir_.write("plotter.toml", read_file(kSrc + "/configs/devices/sim.toml"));
    edit_profile("buffer_bytes = 1024", "buffer_bytes = 256");
    edit_profile("timeout_ms = 5000", "timeout_ms = 3000\nhold_timeout_ms = 8000");
  }
  void edit_profile(const std::string& from, const std::string& to) {
    std::string p = read_file(profile_);
    const std::size_t at = p.find(from);
    ASSERT_NE(at, std::string::npos) << "the profile has " << from;
    p.replace(at, from.size(), to);
    std::ofstream(profile_) << p;
  }
  std::unique_ptr<popcut::testing::SimPlotterProcess> plotter(const std::string& name, std::vector<std::string> args) {
    args.insert(args.end(), {"--buffer", "256"});
    return std::make_unique<popcut::testing::SimPlotterProcess>(POPCUT_CLI, args,
                                                                (dir_.path() / (name + ".json")).string());
  }
  // popcutd with one device, "cutter", on the plotter's port; these tests are about the line, so
  // jobs follow each other without the sheet step (popcutd_sheets_test.cpp has that).
  std::unique_ptr<PopcutdProcess> start_on(const popcut::testing::SimPlotterProcess& p) {
    std::ostringstream o;
    o << "[server]\ndata_dir = \"unused\"\nmaterials_dir = \"" << kSrc << "/configs/materials\"\n"
      << "[[device]]\nname = \"cutter\"\nprofile = \"" << profile_ << "\"\ntransport = \"serial:" << p.port() << "\"\n"
      << "confirm_sheet = false\n"
      << "[[token]]\nname = \"kiosk\"\ntoken = \"" << kKiosk << "\"\n"
      << "[[token]]\nname = \"admin\"\ntoken = \"" << kAdmin << "\"\nrole = \"admin\"\n";
    return std::make_unique<PopcutdProcess>(POPCUTD, dir_.write("serial.toml", o.str()), data_,
                                            std::vector<std::string>{std::string("LD_PRELOAD=") + POPCUT_PTY_PRELOAD});
  }
  // The job's plan as the cutter should cut it, in plotter units, strokes numbered from 1.
  std::vector<popcut::PlotterPath> planned(std::int64_t id) const {
    const std::string path = data_ + "/jobs/" + std::to_string(id) + "/plan.json";
    return popcut::plan_in_plotter_units(popcut::daemon::plan_from_json(read_file(path), path),
                                         popcut::drivers::load_profile(profile_).dialect);
  }
  // "" when the plotter cut every planned stroke of the job in order (a seam's strokes cut twice in
  // between); else how far it got. `resumed_after`: where the second run started, for the message.
  std::string missing_from_cut(const json& report, std::int64_t id, std::int64_t resumed_after) const {
    const auto cut = popcut::testing::sim_plotter_strokes(report);
    const auto plan = planned(id);
    std::size_t next = 0;
    for (const auto& st : cut) {
      if (next < plan.size() && st == plan[next]) ++next;
    }
    if (next == plan.size()) return "";
    return "the first " + std::to_string(next) + " of " + std::to_string(plan.size()) + " strokes cut in order (" +
           std::to_string(cut.size()) + " cut, resumed from " + std::to_string(resumed_after + 1) + ")";
  }
  static std::vector<popcut::PlotterPath> from_stroke(const std::vector<popcut::PlotterPath>& all, std::int64_t after) {
    return {all.begin() + std::min<std::ptrdiff_t>(after, static_cast<std::ptrdiff_t>(all.size())), all.end()};
  }
  // A job cut on a cutter that stops answering (and cutting) mid-job: interrupted, E < M.
  json interrupted_on_a_stuck_cutter(const std::string& name) {
    // Slow enough that its buffer holds strokes it received and never cuts when it stops.
    auto stuck = plotter(name, {"--stop-after", "1500", "--slowdown", "0.3"});
    const auto d = start_on(*stuck);
    httplib::Client c = d->client(kKiosk);
    const std::int64_t id = submit(c, submission(example("voxel/townhouse.json"), "device", "cutter", name));
    EXPECT_TRUE(wait_until([&] { return final_state(job(c, id)); }, 120)) << "the cut ends; log:\n" << d->log();
    const json j = job(c, id);
    EXPECT_EQ(d->stop(SIGTERM), 0) << "popcutd stops cleanly";
    EXPECT_EQ(stuck->wait(), 0) << "the plotter ends when popcutd closes the port: " << stuck->log();
    EXPECT_EQ(j["state"], "interrupted") << "a cutter that stops mid-job leaves the job interrupted: " << j.dump();
    EXPECT_EQ(j["error"]["code"], "device_error") << j.dump();
    EXPECT_TRUE(j["strokes_executed"].is_number()) << "the cutter answered ESC.O: E is known: " << j.dump();
    EXPECT_GT(j.value("strokes_executed", std::int64_t{0}), 0)
        << "the cutter was seen to execute strokes (else resuming "
           "after them would be a restart): "
        << j.dump();
    EXPECT_LT(j.value("strokes_executed", std::int64_t{0}), j["strokes_sent"].get<std::int64_t>())
        << "the cutter holds strokes it received and never cut (else this test proves nothing): " << j.dump();
    EXPECT_EQ(j["resume_from"], j["strokes_sent"]) << "by default it resumes after the strokes received";
    EXPECT_TRUE(j["resume_point"].is_null()) << "not resumed yet: " << j.dump();
    const auto cut = popcut::testing::sim_plotter_strokes(stuck->report());
    const auto plan = planned(id);
    EXPECT_GE(cut.size(), j.value("strokes_executed", std::size_t{0}))
        << "E never claims a stroke the cutter did not cut";
    EXPECT_LT(cut.size(), static_cast<std::size_t>(j["strokes_sent"].get<std::int64_t>()) + 1)
        << "it cut no more than it received";
    EXPECT_EQ(cut, std::vector<popcut::PlotterPath>(
                       plan.begin(), plan.begin() + static_cast<std::ptrdiff_t>(std::min(cut.size(), plan.size()))))
        << "what it cut before it stopped is the plan's beginning";
    return j;
  }
  std::string profile_;
};

TEST_F(SerialPopcutd, ResumeAfterTheExecutedStrokesOnAPowerCycledCutterCutsExactlyTheRest) {
  // ESC.B answers move E as the cutter works through its buffer (ESC.O pings only when it runs
  // empty, which a busy cutter never does: E would stay 0, and resuming after it would be a restart).
  edit_profile("drain_query = \"esc_o\"", "drain_query = \"esc_b\"");
  const json a = interrupted_on_a_stuck_cutter("a");
  const json b = interrupted_on_a_stuck_cutter("b");
  ASSERT_FALSE(HasFailure()) << "both jobs were interrupted with E < M";
  const std::int64_t ia = a["id"], ib = b["id"];
  const std::int64_t e = a["strokes_executed"], total = a["strokes_total"];
  const std::string resume_a = "/api/v1/jobs/" + std::to_string(ia) + "/resume";
  auto fresh_a = plotter("fresh-a", {"--slowdown", "0.05"});  // the power-cycled cutter: an empty buffer
  {
    const auto d = start_on(*fresh_a);
    httplib::Client c = d->client(kKiosk);
    httplib::Client admin = d->client(kAdmin);
    // Held, so that the resumed job waits as `ready` for the crash below.
    ASSERT_EQ(post_json(admin, "/api/v1/devices/cutter/pause", "").status, 200);
    struct Bad {
      std::string path, body, code, field;
    };
    for (const Bad& bad :
         {Bad{resume_a, R"({"from": "sideways"})", "bad_request", "from"},
          Bad{resume_a, R"({"from": 1})", "bad_request", "from"},
          Bad{resume_a, R"({"frm": "executed"})", "bad_request", "frm"},
          Bad{resume_a, R"({"from": "executed", "from": "received"})", "bad_request", "from"},
          Bad{resume_a, R"(["executed"])", "bad_request", ""}, Bad{resume_a, "executed", "bad_json", ""},
          Bad{resume_a + "?from=executed", "", "bad_request", ""}}) {
      const Reply r = post_json(c, bad.path, bad.body);
      EXPECT_EQ(r.status, 400) << bad.path << " " << bad.body << ": " << r.body.dump();
      EXPECT_EQ(r.body["error"]["code"], bad.code) << bad.path << " " << bad.body << ": " << r.body.dump();
      if (!bad.field.empty()) {
        EXPECT_EQ(r.body["error"].value("field", ""), bad.field) << bad.body << ": the field is named";
      }
    }
    EXPECT_EQ(job(c, ia)["state"], "interrupted") << "bad requests change nothing";
    const Reply r = post_json(c, resume_a, R"({"from": "executed"})");
    EXPECT_EQ(r.status, 202) << "resume after the executed strokes accepted: " << r.body.dump();
    EXPECT_EQ(r.body["state"], "ready") << r.body.dump();
    EXPECT_EQ(r.body["resume_from"], e) << "the resumed run starts after the strokes executed: " << r.body.dump();
    EXPECT_EQ(r.body["resume_point"], "executed") << r.body.dump();
    EXPECT_EQ(r.body["strokes_sent"], e) << "a power-cycled cutter holds nothing: received drops to executed: "
                                         << r.body.dump();
    EXPECT_EQ(d->stop(SIGKILL), 128 + SIGKILL) << "a crash between accepting the resume and cutting";
  }
  {
    const auto d = start_on(*fresh_a);
    httplib::Client c = d->client(kKiosk);
    json j = job(c, ia);
    EXPECT_EQ(j["state"], "ready") << "the accepted resume survived the crash: " << j.dump();
    EXPECT_EQ(j["resume_from"], e) << "and so did its choice: " << j.dump();
    EXPECT_EQ(j["resume_point"], "executed") << j.dump();
    httplib::Client admin = d->client(kAdmin);
    ASSERT_EQ(post_json(admin, "/api/v1/devices/cutter/resume", "").status, 200);
    ASSERT_TRUE(wait_until([&] { return final_state(job(c, ia)); }, 120)) << "the resumed job ends; log:\n" << d->log();
    j = job(c, ia);
    EXPECT_EQ(j["state"], "done") << "the resumed job is done: " << j.dump();
    EXPECT_EQ(j["strokes_sent"], total) << j.dump();
    EXPECT_EQ(j["resume_from"], e) << "it still shows where the resumed run started: " << j.dump();
    EXPECT_EQ(d->stop(SIGTERM), 0);
  }
  ASSERT_EQ(fresh_a->wait(), 0) << fresh_a->log();
  const json ra = fresh_a->report();
  EXPECT_EQ(ra["overflow_bytes"], 0) << "the resumed job reached the plotter intact";
  EXPECT_EQ(popcut::testing::sim_plotter_strokes(ra), from_stroke(planned(ia), e))
      << "the power-cycled cutter cut exactly strokes " << e + 1 << ".." << total;

  // The other job, resumed after the strokes received (through the CLI): strokes M+1.. only.
  const std::int64_t m = b["strokes_sent"];
  auto fresh_b = plotter("fresh-b", {"--slowdown", "0.05"});
  {
    const auto d = start_on(*fresh_b);
    const std::string server = "--server http://127.0.0.1:" + std::to_string(d->port()) + " --token " + kKiosk;
    CliRun r = cli("resume " + std::to_string(ib) + " --from sideways " + server);
    EXPECT_EQ(r.code, 2) << "an unknown resume point is a usage error: " << r.err;
    EXPECT_NE(r.err.find("--from"), std::string::npos) << "the flag is named: " << r.err;
    r = cli("resume " + std::to_string(ib) + " --from received --json " + server);
    ASSERT_EQ(r.code, 0) << r.err;
    const json rb = json::parse(r.out, nullptr, false);
    EXPECT_EQ(rb["resume_from"], m) << "resumes after the strokes received: " << r.out;
    EXPECT_EQ(rb["resume_point"], "received") << r.out;
    httplib::Client c = d->client(kKiosk);
    ASSERT_TRUE(wait_until([&] { return final_state(job(c, ib)); }, 120)) << "the resumed job ends; log:\n" << d->log();
    EXPECT_EQ(job(c, ib)["state"], "done") << job(c, ib).dump();
    r = cli("resume " + std::to_string(ib) + " " + server);
    EXPECT_EQ(r.code, 2) << "a done job does not resume: " << r.err;
    EXPECT_NE(r.err.find("409 conflict"), std::string::npos) << r.err;
    EXPECT_EQ(d->stop(SIGTERM), 0);
  }
  ASSERT_EQ(fresh_b->wait(), 0) << fresh_b->log();
  EXPECT_EQ(popcut::testing::sim_plotter_strokes(fresh_b->report()), from_stroke(planned(ib), m))
      << "the cutter cut exactly strokes " << m + 1 << "..";
}

// SIGTERM while cutting: popcutd aborts with the profile's ESC.K, which makes the cutter drop what
// its buffer holds. What it had received but not cut is gone, so the job's received count and the
// default resume point fall back to what it executed: resuming (the default) on the same cutter
// then cuts every stroke the first run left, none skipped. It used to resume after the strokes
// received, and those the cutter had dropped were never cut.
TEST_F(SerialPopcutd, AfterSigtermTheDefaultResumeCutsTheStrokesTheCutterDiscarded) {
  edit_profile("buffer_bytes = 256", "buffer_bytes = 1024");
  auto plot = std::make_unique<popcut::testing::SimPlotterProcess>(
      POPCUT_CLI, std::vector<std::string>{"--profile", profile_, "--buffer", "1024", "--slowdown", "0.5"},
      (dir_.path() / "sigterm.json").string());
  const int hold = ::open(plot->port().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);  // one session: the same sheet
  ASSERT_GE(hold, 0) << plot->port();
  std::int64_t id = 0;
  json j;
  {
    const auto d = start_on(*plot);
    httplib::Client c = d->client(kKiosk);
    id = submit(c, submission(example("voxel/townhouse.json"), "device", "cutter", "sigterm"));
    ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "cutting" && job(c, id)["strokes_sent"] >= 8; }, 120))
        << "the cut is under way; log:\n"
        << d->log();
    EXPECT_EQ(d->stop(SIGTERM), 0) << d->log();
  }
  const auto d = start_on(*plot);
  httplib::Client c = d->client(kKiosk);
  j = job(c, id);
  ASSERT_EQ(j["state"], "interrupted") << j.dump();
  const std::int64_t m = j["strokes_sent"], total = j["strokes_total"];
  ASSERT_LT(m, total) << "stopped mid-cut (else this test proves nothing)";
  const std::string message = j["error"].value("message", "");
  EXPECT_NE(message.find("the device discarded its buffer on the abort"), std::string::npos) << message;
  EXPECT_EQ(j["strokes_executed"].is_null() ? std::int64_t{0} : j["strokes_executed"].get<std::int64_t>(), m)
      << "received is what it executed: " << j.dump();
  ASSERT_EQ(post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", "").status, 202);
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); }, 120)) << d->log();
  EXPECT_EQ(job(c, id)["state"], "done") << job(c, id).dump();
  EXPECT_EQ(job(c, id)["resume_from"], m) << job(c, id).dump();
  EXPECT_EQ(d->stop(SIGTERM), 0);
  ::close(hold);
  ASSERT_EQ(plot->wait(), 0) << plot->log();
  const json report = plot->report();
  EXPECT_GT(report.value("discarded_bytes", 0), 0)
      << "the cutter dropped strokes it held (else this test proves nothing)";
  EXPECT_EQ(report["overflow_bytes"], 0);
  // Both runs on one sheet: every planned stroke cut, in order, the seam's cut twice at most.
  EXPECT_EQ(missing_from_cut(report, id, m), "") << "every stroke of the card was cut";
}

// A GP-GL cutter with no sheet loaded says so to ESC ENQ before the job: popcutd sends nothing,
// the job goes back in line and the device shows its tray empty; popcutd asks again every few
// seconds (this device confirms no sheets), and once a sheet is in, the card is cut.
TEST_F(SerialPopcutd, AGpglCutterWithNoSheetLoadedKeepsTheJobInLineUntilOneIs) {
  profile_ = dir_.write("cameo.toml", read_file(kSrc + "/configs/devices/silhouette-cameo4.toml"));
  edit_profile("[transport]\n", "[transport]\nbaud = 115200\ntimeout_ms = 3000\nhold_timeout_ms = 8000\n");
  auto plot = plotter("empty", {"--profile", profile_, "--tray-empty-after", "0"});
  const int hold = ::open(plot->port().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);  // one session: the same device
  ASSERT_GE(hold, 0) << plot->port();
  const auto d = start_on(*plot);
  httplib::Client c = d->client(kKiosk);
  const auto cutter = [&] { return popcut::testing::get_json(c, "/api/v1/devices").body["devices"][0]; };
  const std::int64_t id = submit(c, submission(example("voxel/box.json"), "device", "cutter", "empty"));
  ASSERT_TRUE(wait_until([&] { return cutter()["tray_empty"] == true; }, 60)) << d->log();
  json j = job(c, id);
  EXPECT_EQ(j["state"], "ready") << "back in line, not interrupted: " << j.dump();
  EXPECT_EQ(j["strokes_sent"], 0) << j.dump();
  EXPECT_TRUE(j["error"].is_null()) << j.dump();
  EXPECT_EQ(cutter()["sheet"], "awaiting_sheet");
  ASSERT_TRUE(
      wait_until([&] { return d->log().find("asking again whether a sheet is loaded") != std::string::npos; }, 30))
      << d->log();
  ASSERT_TRUE(wait_until([&] { return cutter()["tray_empty"] == true; }, 30)) << "still empty: " << d->log();
  EXPECT_EQ(job(c, id)["state"], "ready") << "never started on an empty tray";
  ASSERT_EQ(::kill(plot->pid(), SIGUSR1), 0) << "a sheet goes in";
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); }, 60)) << d->log();
  j = job(c, id);
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_EQ(cutter()["tray_empty"], false);
  EXPECT_EQ(d->stop(SIGTERM), 0);
  ::close(hold);
  ASSERT_EQ(plot->wait(), 0) << plot->log();
  const json report = plot->report();
  EXPECT_EQ(report["overflow_bytes"], 0);
  EXPECT_EQ(popcut::testing::sim_plotter_strokes(report), planned(id)) << "the whole card, once";
}

// A Cameo cutting card-220 (two passes, lighter first) when popcutd is killed: restarted, the job
// is interrupted with its material, and the default resume on the same sheet finishes the card with
// the material's forces and speeds, every planned stroke cut in order.
TEST_F(SerialPopcutd, AMaterialJobKilledMidCutResumesWithItsMaterialOnTheSameSheet) {
  profile_ = dir_.write("cameo.toml", read_file(kSrc + "/configs/devices/silhouette-cameo4.toml"));
  // The resumed run waits (up to hold_timeout_ms) while the cutter still cuts what the killed run
  // left in its 1 KiB buffer: ~10 s at this slowdown, more on a loaded machine.
  edit_profile("[transport]\n", "[transport]\nbaud = 115200\ntimeout_ms = 3000\nhold_timeout_ms = 60000\n");
  // The Cameo's own 1 KiB (plotter() gives the HP-GL tests' 256 bytes, which the profile would overrun).
  auto plot = std::make_unique<popcut::testing::SimPlotterProcess>(
      POPCUT_CLI, std::vector<std::string>{"--profile", profile_, "--slowdown", "0.5"},
      (dir_.path() / "card.json").string());
  const int hold = ::open(plot->port().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);  // one session: the same sheet
  ASSERT_GE(hold, 0) << plot->port();
  json body = json::parse(submission(example("voxel/townhouse.json"), "device", "cutter", "card"));
  body["material"] = "card-220";
  std::int64_t id = 0;
  {
    const auto d = start_on(*plot);
    httplib::Client c = d->client(kKiosk);
    id = submit(c, body.dump());
    ASSERT_NE(id, 0);
    ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "cutting" && job(c, id)["strokes_sent"] >= 8; }, 120))
        << "the cut is under way; log:\n"
        << d->log();
    EXPECT_EQ(d->stop(SIGKILL), 128 + SIGKILL);
  }
  const auto d = start_on(*plot);
  httplib::Client c = d->client(kKiosk);
  json j = job(c, id);
  ASSERT_EQ(j["state"], "interrupted") << j.dump();
  EXPECT_EQ(j["material"], "card-220") << j.dump();
  const std::int64_t m = j["strokes_sent"], total = j["strokes_total"];
  ASSERT_LT(m, total) << "killed mid-cut (else this test proves nothing)";
  ASSERT_EQ(post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", "").status, 202);
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); }, 180)) << d->log();
  j = job(c, id);
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_EQ(j["strokes_sent"], total) << j.dump();
  EXPECT_EQ(d->stop(SIGTERM), 0);
  ::close(hold);
  ASSERT_EQ(plot->wait(), 0) << plot->log();
  const json report = plot->report();
  EXPECT_EQ(report["overflow_bytes"], 0);
  EXPECT_EQ(missing_from_cut(report, id, m), "");
  // The material's tool settings on both sides of the kill: its score, and both cut passes.
  std::set<std::pair<double, double>> before, after;
  for (std::size_t i = 0; i < report["strokes"].size(); ++i) {
    const json& st = report["strokes"][i];
    (i < static_cast<std::size_t>(m) / 2 ? before : after)
        .insert({st["force"].get<double>(), st["speed_cm_s"].get<double>()});
  }
  EXPECT_EQ(after.size(), 3u) << "score, light pass, full pass after the resume: " << report["strokes"].dump();
  for (const auto& setting : before)
    EXPECT_TRUE(after.count(setting)) << "the resumed run cuts with the settings the first one did: " << setting.first;
}

// Pause and continue over a real serial line: the cut stops after the stroke in flight once the
// cutter has drained, the knife up; continue re-sends the init and goes on, and the plotter, one
// session throughout (the same sheet), cut every stroke of the card exactly once.
TEST_F(SerialPopcutd, PauseAndContinueOverASerialLineCutTheCardOnce) {
  auto plot = plotter("paused", {"--slowdown", "0.3"});
  const int hold = ::open(plot->port().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);  // one session: the same sheet
  ASSERT_GE(hold, 0) << plot->port();
  const auto d = start_on(*plot);
  httplib::Client c = d->client(kKiosk);
  const std::int64_t id = submit(c, submission(example("voxel/townhouse.json"), "device", "cutter", "paused"));
  const std::string path = "/api/v1/jobs/" + std::to_string(id);
  ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "cutting" && job(c, id)["strokes_sent"] >= 5; }, 120))
      << d->log();
  ASSERT_EQ(post_json(c, path + "/pause", "").status, 202);
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)) || job(c, id)["state"] == "paused"; }, 120)) << d->log();
  json j = job(c, id);
  ASSERT_EQ(j["state"], "paused") << j.dump();
  const std::int64_t after = j["strokes_sent"], total = j["strokes_total"];
  EXPECT_LT(after, total) << "paused mid-cut";
  EXPECT_EQ(j["strokes_executed"], after) << "the cutter drained: what it received, it cut";
  ASSERT_EQ(post_json(c, path + "/continue", "").status, 200);
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); }, 180)) << d->log();
  j = job(c, id);
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_EQ(j["resume_from"], after);
  EXPECT_EQ(d->stop(SIGTERM), 0);
  ::close(hold);
  ASSERT_EQ(plot->wait(), 0) << plot->log();
  const json report = plot->report();
  EXPECT_EQ(report["overflow_bytes"], 0);
  EXPECT_EQ(popcut::testing::sim_plotter_strokes(report), planned(id)) << "every stroke once, in order";
  EXPECT_FALSE(report["knife_down_at_end"].get<bool>());
}

// The device's profile says XON/XOFF; the plotter never says XOFF (it is set up for ESC.B), so
// its buffer overflows while every write succeeds. Its ESC.E answer fails the job for good: what
// it cut is not the job, and a resume would only cut the rest of a spoiled sheet.
TEST_F(SerialPopcutd, ACutterThatLostBytesFailsTheJobInsteadOfOfferingAResume) {
  std::string p = read_file(profile_);
  const std::size_t at = p.find("flow_control = \"xon_xoff\"");
  ASSERT_NE(at, std::string::npos);
  p.replace(at, std::string("flow_control = \"xon_xoff\"").size(), "flow_control = \"esc_b\"");
  const std::string plotter_profile = dir_.write("plotter-escb.toml", p);
  auto plot = plotter("lossy", {"--profile", plotter_profile, "--slowdown", "0.5"});
  const auto d = start_on(*plot);
  httplib::Client c = d->client(kKiosk);
  const std::int64_t id = submit(c, submission(example("voxel/townhouse.json"), "device", "cutter", "lossy"));
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, id)); }, 120)) << "the cut ends; log:\n" << d->log();
  const json j = job(c, id);
  EXPECT_EQ(post_json(c, "/api/v1/jobs/" + std::to_string(id) + "/resume", "").status, 409)
      << "a failed job does not resume";
  EXPECT_EQ(d->stop(SIGTERM), 0);
  ASSERT_EQ(plot->wait(), 0) << plot->log();
  ASSERT_GT(plot->report()["overflow_bytes"].get<int>(), 0) << "the plotter lost bytes";
  EXPECT_EQ(j["state"], "failed") << "not done, and not resumable: " << j.dump();
  EXPECT_EQ(j["error"]["code"], "device_error") << j.dump();
  EXPECT_NE(j["error"]["message"].get<std::string>().find("I/O error 16"), std::string::npos) << j.dump();
}

// A cutter with no handshake and no abort goes on cutting what a cancelled job left in its
// buffer. popcutd sends it nothing more until, by the profile's pace, it has cut that: the next
// job would otherwise overrun it. The test holds the port open, so that both jobs reach the same
// plotter session, as on a real cutter. (Without the wait this plotter does not overflow either:
// the allowance for a first travel across the area covers what a cutter within the margin holds
// here; the log line is what shows the wait.)
TEST_F(SerialPopcutd, ACutterWithNoHandshakeIsLeftToFinishItsBufferBeforeTheNextJob) {
  edit_profile("flow_control = \"xon_xoff\"", "flow_control = \"none\"");
  edit_profile("drain_query = \"esc_o\"", "drain_query = \"none\"");
  edit_profile("error_query = \"esc_e\"", "error_query = \"none\"");
  edit_profile("abort = \"\\u001b.K\"", "abort = \"\"");
  edit_profile("buffer_bytes = 256", "buffer_bytes = 1024");  // half of it is several seconds of cutting
  auto plot = std::make_unique<popcut::testing::SimPlotterProcess>(
      POPCUT_CLI, std::vector<std::string>{"--profile", profile_, "--slowdown", "1.2"},
      (dir_.path() / "nohandshake.json").string());
  const int hold = ::open(plot->port().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);  // one session for both jobs
  ASSERT_GE(hold, 0) << plot->port();
  const auto d = start_on(*plot);
  httplib::Client c = d->client(kKiosk);
  const std::int64_t first = submit(c, submission(example("voxel/townhouse.json"), "device", "cutter", "first"));
  // Nothing answers, so nothing is confirmed received while it cuts (strokes_sent stays low):
  // some seconds into the cut, its buffer holds strokes.
  ASSERT_TRUE(wait_until([&] { return job(c, first)["state"] == "cutting"; }, 60)) << "the cut starts; log:\n"
                                                                                   << d->log();
  std::this_thread::sleep_for(std::chrono::seconds(6));
  EXPECT_EQ(post_json(c, "/api/v1/jobs/" + std::to_string(first) + "/cancel", "").status / 100, 2);
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, first)); }, 60)) << d->log();
  EXPECT_EQ(job(c, first)["state"], "cancelled") << job(c, first).dump();
  const std::int64_t second = submit(c, submission(example("voxel/box.json"), "device", "cutter", "second"));
  ASSERT_TRUE(wait_until([&] { return final_state(job(c, second)); }, 120)) << d->log();
  EXPECT_EQ(job(c, second)["state"], "done") << job(c, second).dump();
  EXPECT_NE(d->log().find("may go on cutting for up to"), std::string::npos) << "the wait is logged: " << d->log();
  EXPECT_EQ(d->stop(SIGTERM), 0);
  ::close(hold);
  ASSERT_EQ(plot->wait(), 0) << plot->log();
  EXPECT_EQ(plot->report()["overflow_bytes"], 0) << "the second job did not overrun what the first left";
}

TEST_F(SerialPopcutd, ASecondCancelGivesUpWaitingForACutterThatHoldsTheLine) {
  // The cutter says XOFF at 192 bytes and, a thousand times slower than the profile, keeps holding
  // the line: the abort cannot go out before the hold timeout of 60 s.
  edit_profile("hold_timeout_ms = 8000", "hold_timeout_ms = 60000");
  auto held = plotter("held", {"--slowdown", "1000"});
  const auto d = start_on(*held);
  httplib::Client c = d->client(kKiosk);
  const std::int64_t id = submit(c, submission(example("voxel/townhouse.json"), "device", "cutter", "held"));
  const std::string cancel = "/api/v1/jobs/" + std::to_string(id) + "/cancel";
  ASSERT_TRUE(wait_until([&] { return job(c, id)["state"] == "cutting" && job(c, id)["strokes_sent"] >= 1; }, 120))
      << "the cut starts; log:\n"
      << d->log();
  EXPECT_TRUE(job(c, id)["cancel"].is_null()) << "no cancel yet: " << job(c, id).dump();
  // Its buffer is full and the line held by now (it says XOFF at 192 bytes and then cuts a
  // thousand times slower than planned); else the abort goes through and the test fails below.
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const Reply first = post_json(c, cancel, "");
  EXPECT_EQ(first.status, 202) << "the first cancel is accepted: " << first.body.dump();
  EXPECT_EQ(first.body["state"], "cutting") << first.body.dump();
  EXPECT_EQ(first.body["cancel"], "requested") << first.body.dump();
  ASSERT_TRUE(wait_until([&] { return job(c, id)["cancel"] == "waiting_for_device"; }, 30))
      << "the job says its cancel waits for the cutter to let the abort through: " << job(c, id).dump() << "\n"
      << d->log();
  EXPECT_NE(d->log().find("holds the line (XOFF or CTS): waiting up to 60 s"), std::string::npos)
      << "and the log says so: " << d->log();
  const Reply second = post_json(c, cancel, "");
  EXPECT_EQ(second.status, 200)
      << "the second cancel gives up the wait, well before the 60 s hold timeout, and answers the "
         "outcome: "
      << second.body.dump();
  EXPECT_EQ(second.body["state"], "cancelled") << second.body.dump();
  EXPECT_EQ(second.body["error"]["code"], "device_error")
      << "the knife-up did not reach the cutter: " << second.body.dump();
  const std::string message = second.body["error"].value("message", "");
  EXPECT_EQ(message.find("cancelled during the cut: gave up waiting for the device"), 0u) << message;
  EXPECT_NE(message.find("neither the abort sequence nor the knife-up reached it"), std::string::npos) << message;
  EXPECT_NE(message.find("the device may still cut up to "), std::string::npos)
      << "says how much it may still cut: " << message;
  EXPECT_NE(message.find(" bytes (strokes "), std::string::npos) << "in bytes and strokes: " << message;
  EXPECT_EQ(job(c, id)["error"]["message"], message) << "the job keeps it";
  EXPECT_FALSE(job(c, id).contains("cancel")) << "a finished job has no cancel under way: " << job(c, id).dump();
  const Reply third = post_json(c, cancel, "");
  EXPECT_EQ(third.status, 409) << "a cancelled job is final: " << third.body.dump();
  EXPECT_EQ(d->stop(SIGTERM), 0) << "popcutd stops cleanly";
  EXPECT_EQ(held->wait(), 0) << held->log();
}

}  // namespace
