// popcut reading webOAcard .oa files: validate on a demo card and on a broken one, and submit, as a user runs it.
#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <variant>

#include "cli_run.h"
#include "popcut/io/model_io.h"
#include "shared_testdata.h"

namespace {
namespace fs = std::filesystem;
using popcut::testing::CliRun;

class CliOa : public popcut::testing::CliFixture {
 protected:
  CliOa() : CliFixture("popcut-oa") {}
  static std::string demo(const std::string& name) {
    return popcut::testing::shared_testdata("webOAcard/demo/" + name);
  }
};

TEST_F(CliOa, ValidateReadsADemoCard) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  const CliRun r = run("validate " + demo("house.oa") + " --json");
  ASSERT_EQ(r.code, 0) << "the house pops up: exit 0: " << r.err << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["pops_up"].get<bool>()) << "the report says it pops up: " << r.out;
  EXPECT_GT(j["faces"].get<int>(), 10) << "the house has its walls and top faces: " << r.out;
  const CliRun render = run("render " + demo("house.oa") + " --angle 75 -o " + (dir_ / "house.png").string());
  EXPECT_EQ(render.code, 0) << "render reads .oa too: " << render.err;
}

TEST_F(CliOa, AMalformedFileExitsTwoNamingTheField) {
  const fs::path bad = dir_ / "bad.oa";
  std::ofstream(bad)
      << R"({"settings": {"cardW": 120, "cardH": 100}, "faces": [{"contours": [{"outer": [)"
         R"({"X": 1, "Y": 1}, {"X": "two", "Y": 1}, {"X": 2, "Y": 5}]}], "type": "VFACE", "mode": 0, "t": 5}]})";
  const CliRun r = run("validate " + bad.string());
  EXPECT_EQ(r.code, 2) << "bad input is exit 2: " << r.err;
  EXPECT_NE(r.err.find("bad.oa: faces[0].contours[0].outer[1].X: expected a number"), std::string::npos)
      << "the message names the file and the field: " << r.err;
}

// popcutd reads popcut's own models: submit sends a .oa card as the face model every command
// reads from it (popcut.faces.v1), as it sends a drawing. A loopback server stands in for popcutd
// and keeps what it was sent.
TEST_F(CliOa, SubmitSendsTheCardAsItsFaceModel) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  httplib::Server server;
  std::mutex m;
  std::string body;
  server.Post("/api/v1/jobs", [&](const httplib::Request& req, httplib::Response& res) {
    {
      const std::lock_guard lock(m);
      body = req.body;
    }
    const nlohmann::json job = {{"id", 7},
                                {"name", "house"},
                                {"owner", "kiosk"},
                                {"device", "a"},
                                {"profile", "sim"},
                                {"cut_on", nullptr},
                                {"state", "queued"},
                                {"strokes_total", 12},
                                {"strokes_sent", 0},
                                {"resume_from", 0},
                                {"resume_point", nullptr},
                                {"strokes_executed", nullptr},
                                {"progress", 0.0},
                                {"est_time_s", 3.5},
                                {"created_at", 1700000000},
                                {"started_at", nullptr},
                                {"finished_at", nullptr},
                                {"place_in_line", 1},
                                {"eta_s", nullptr}};
    res.status = 201;
    res.set_content(job.dump(), "application/json");
  });
  const int port = server.bind_to_any_port("127.0.0.1");
  std::thread serve([&] { server.listen_after_bind(); });
  const CliRun r =
      run("submit " + demo("house.oa") + " --device a --json --server http://127.0.0.1:" + std::to_string(port) +
          " --token kiosk-0123456789abcdef");
  server.stop();
  serve.join();
  ASSERT_EQ(r.code, 0) << "the card is queued: " << r.err << r.out;
  const nlohmann::json sent = nlohmann::json::parse(body);
  ASSERT_TRUE(sent.contains("model")) << "the job carries a model: " << body.substr(0, 200);
  EXPECT_EQ(sent["model"]["format"], "popcut.faces.v1") << "the card goes as popcut's face model, not as .oa JSON";
  const popcut::AnyModel got = popcut::parse_model(sent["model"].dump(), "sent");
  const popcut::AnyModel house = popcut::load_model(demo("house.oa"));
  ASSERT_TRUE(std::holds_alternative<popcut::FaceModel>(got)) << "a face model was sent";
  EXPECT_EQ(std::get<popcut::FaceModel>(got).face_count(), std::get<popcut::FaceModel>(house).face_count())
      << "the faces popcut reads from the .oa, all of them";
}

}  // namespace
