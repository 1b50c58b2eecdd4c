// The designer's routes end to end: a real popcutd keeps drafts per token in SQLite across kill -9, answers edits with
// the pattern and check, refuses bad edits leaving the session as it was, and sends a design to a simulated cutter.
#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <csignal>
#include <string>
#include <thread>
#include <vector>

#include "popcut/io/design_json.h"
#include "pattern_compare.h"
#include "popcut/io/model_io.h"
#include "popcut/io/oa_model.h"
#include "popcut/pattern/face_pattern.h"
#include "popcutd_process.h"
#include "shared_testdata.h"

namespace {
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::read_file;
using popcut::testing::Reply;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-0123456789abcdef";
const std::string kOther = "other-0123456789abcdef";
const std::string kAdmin = "admin-0123456789abcdef";

std::string config(const TempDir& dir) {
  return dir.write("popcutd.toml",
                   "[server]\ndata_dir = \"" + (dir.path() / "data").string() +
                       "\"\n[limits]\ndesign_sessions = 2\n[[device]]\nname = \"sim-a\"\nprofile = \"" + kSrc +
                       "/configs/devices/sim.toml\"\ntransport = \"sim\"\nsim_time_scale = 0.01\n" +
                       "[[token]]\nname = \"kiosk\"\ntoken = \"" + kKiosk +
                       "\"\n[[token]]\nname = \"other\"\ntoken = \"" + kOther +
                       "\"\n[[token]]\nname = \"admin\"\ntoken = \"" + kAdmin + "\"\nrole = \"admin\"\n");
}

const std::string kEmptyPorch =
    R"({"format": "popcut.design.v1", "name": "Porch", "sheet": {"width": 100, "back": 80, "floor": 80}, "items": []})";

json wall(double t, double x0, double x1, double z1) {
  return {{"tool", "wall"}, {"t", t}, {"outline", {{x0, 0}, {x1, 0}, {x1, z1}, {x0, z1}}}};
}

std::string path(std::int64_t id, const std::string& rest = "") {
  return "/api/v1/designs/" + std::to_string(id) + rest;
}

std::int64_t create(httplib::Client& c) {
  const Reply r = post_json(c, "/api/v1/designs", kEmptyPorch);
  EXPECT_EQ(r.status, 201) << r.body.dump();
  return r.body.value("id", std::int64_t{0});
}

Reply add(httplib::Client& c, std::int64_t id, const json& item) {
  return post_json(c, path(id, "/items"), item.dump());
}

popcut::Pattern saved_pattern(httplib::Client& c, std::int64_t id) {
  const auto r = c.Get(path(id, "/design.json").c_str());
  EXPECT_TRUE(r && r->status == 200);
  return r ? popcut::parse_design(r->body, "saved").pattern() : popcut::Pattern();
}

// Sends the design to sim-a and waits for the job: done, and the simulator cut what was planned.
void expect_cut_as_planned(httplib::Client& c, std::int64_t id) {
  const Reply job = post_json(c, path(id, "/submit"), R"({"device": "sim-a"})");
  ASSERT_EQ(job.status, 201) << job.body.dump();
  const std::string job_path = "/api/v1/jobs/" + std::to_string(job.body["id"].get<std::int64_t>());
  ASSERT_TRUE(wait_until([&] { return get_json(c, job_path).body.value("state", "") == "done"; }, 120))
      << get_json(c, job_path).body.dump();
  EXPECT_TRUE(get_json(c, job_path).body.value("sim_match", false)) << "the simulator cut what was planned";
}

TEST(PopcutdDesign, TwoWallsMakeThePorchAndTheDraftSurvivesKill9) {
  TempDir dir("popcutd-design");
  const std::string cfg = config(dir), data = (dir.path() / "data").string();
  std::int64_t id = 0;
  {
    PopcutdProcess d(POPCUTD, cfg, data);
    httplib::Client c = d.client(kKiosk);
    id = create(c);
    // The front wall first: in drawing order the items are then [id 2, id 1], and the ids the
    // page knows must survive a restart.
    ASSERT_EQ(add(c, id, wall(42, 35, 65, 20)).status, 200);
    const Reply r = add(c, id, wall(30, 15, 85, 40));
    ASSERT_EQ(r.status, 200) << r.body.dump();
    EXPECT_TRUE(r.body["check"]["pops_up"].get<bool>());
    EXPECT_EQ(r.body["design"]["items"].size(), 2u);
    EXPECT_TRUE(r.body["can_undo"].get<bool>());
    EXPECT_GE(r.body["answer_ms"].get<double>(), 0.0);
    EXPECT_EQ(r.body["design"]["format"], "popcut.design.v1") << "the state carries the design as its file";
    EXPECT_EQ(r.body["pattern"]["format"], "popcut.pattern.v1");
    const popcut::Pattern porch =
        popcut::make_pattern(popcut::parse_model(read_file(kSrc + "/examples/faces/porch.json"), "porch"));
    EXPECT_EQ(r.body["pattern"]["faces"].size(), porch.faces.size());
    EXPECT_EQ(popcut::testing::compare_patterns(saved_pattern(c, id), porch), "")
        << "the saved design is examples/faces/porch.json's card";
    ASSERT_EQ(d.stop(SIGKILL), 128 + SIGKILL);
  }
  PopcutdProcess d(POPCUTD, cfg, data);
  httplib::Client c = d.client(kKiosk);
  const json list = get_json(c, "/api/v1/designs").body;
  ASSERT_EQ(list["designs"].size(), 1u) << list.dump();
  EXPECT_EQ(list["designs"][0]["name"], "Porch");
  EXPECT_EQ(list["designs"][0]["items"], 2);
  const json back = get_json(c, path(id)).body;
  ASSERT_EQ(back["design"]["items"].size(), 2u);
  EXPECT_EQ(back["design"]["items"][0]["id"], 2) << "the wall at t = 30 keeps its id";
  EXPECT_EQ(back["design"]["items"][0]["t"], 30.0);
  EXPECT_EQ(back["design"]["items"][1]["id"], 1);
  EXPECT_FALSE(back["can_undo"].get<bool>()) << "undo history lives in the session only (docs/api.md)";
  EXPECT_TRUE(back["check"]["pops_up"].get<bool>());
}

TEST(PopcutdDesign, RefusedEditsSayWhyAndLeaveTheSessionAsItWas) {
  TempDir dir("popcutd-design");
  PopcutdProcess d(POPCUTD, config(dir), (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const std::int64_t id = create(c);
  ASSERT_EQ(add(c, id, wall(30, 15, 85, 40)).status, 200);
  const json before = get_json(c, path(id)).body;
  struct Case {
    std::string body;
    int status;
    std::string field, says;
  };
  const std::vector<Case> cases = {
      {wall(30, 15, 185, 40).dump(), 422, "item.outline", "leaves the sheet"},
      {wall(95, 15, 85, 40).dump(), 422, "item.outline", ""},
      {R"({"tool": "wall", "t": 20, "outline": [[10, 0], [40, 30], [40, 0], [10, 30]]})", 422, "", ""},
      {R"({"tool": "opening", "t": 50, "outline": [[20, 5], [30, 5], [30, 15], [20, 15]]})", 422, "", ""},
      {R"({"tool": "tower", "t": 20, "outline": [[10, 0], [40, 0], [40, 30]]})", 422, "tool", "tower"},
      {R"({"tool": "wall", "t": 20, "outline": [[10, 0], [40, 0]]})", 422, "outline", ""},
      {R"({"tool": "roof", "t": 20, "top": false, "outline": [[10, 0], [40, 0], [40, 30]]})", 422, "top", ""},
      {R"({"tool": "wall", "t": 20)", 400, "", ""},
      {std::string(10 << 20, ' '), 413, "", ""},
      {R"({"tool": "wall", "t": 1e400, "outline": [[10, 0], [40, 0], [40, 30]]})", 400, "", ""},
  };
  for (const Case& k : cases) {
    const Reply raw = post_json(c, path(id, "/items"), k.body);
    EXPECT_EQ(raw.status, k.status) << k.body.substr(0, 80) << " -> " << raw.body.dump();
    const std::string message = raw.body["error"].value("message", "");
    EXPECT_FALSE(message.empty()) << k.body.substr(0, 80);
    if (!k.field.empty()) {
      EXPECT_EQ(raw.body["error"].value("field", ""), k.field) << message;
    }
    if (!k.says.empty()) {
      EXPECT_NE(message.find(k.says), std::string::npos) << message;
    }
  }
  EXPECT_EQ(get_json(c, path(id)).body, before) << "every refused edit left the design as it was";
  const Reply undo = post_json(c, path(id, "/undo"), "");
  EXPECT_EQ(undo.body["design"]["items"].size(), 0u) << "the refused edits are not in the undo history";
  EXPECT_EQ(post_json(c, path(id, "/undo"), "").status, 409);
}

TEST(PopcutdDesign, UndoRedoAndRemoveWorkByItem) {
  TempDir dir("popcutd-design");
  PopcutdProcess d(POPCUTD, config(dir), (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const std::int64_t id = create(c);
  std::vector<json> states;
  for (int i = 0; i < 4; ++i) {
    const Reply r = add(c, id, wall(10 + 10 * i, 10 + 5 * i, 90 - 5 * i, 50 - 8 * i));
    ASSERT_EQ(r.status, 200) << r.body.dump();
    states.push_back(r.body["pattern"]);
  }
  for (std::size_t i = 3; i-- > 0;) EXPECT_EQ(post_json(c, path(id, "/undo"), "").body["pattern"], states[i]);
  for (std::size_t i = 1; i < 4; ++i) EXPECT_EQ(post_json(c, path(id, "/redo"), "").body["pattern"], states[i]);
  EXPECT_EQ(post_json(c, path(id, "/redo"), "").status, 409);
  const std::int64_t second = get_json(c, path(id)).body["design"]["items"][1]["id"];
  const Reply removed = post_json(c, path(id, "/items/" + std::to_string(second) + "/remove"), "");
  ASSERT_EQ(removed.status, 200) << removed.body.dump();
  EXPECT_EQ(removed.body["design"]["items"].size(), 3u);
  EXPECT_EQ(post_json(c, path(id, "/items/999/remove"), "").status, 404);
  EXPECT_EQ(post_json(c, path(id, "/undo"), "").body["pattern"], states[3]);
}

TEST(PopcutdDesign, DraftsBelongToTheirTokenAndSessionsComeBackFromSQLite) {
  TempDir dir("popcutd-design");
  PopcutdProcess d(POPCUTD, config(dir), (dir.path() / "data").string());
  httplib::Client kiosk = d.client(kKiosk), other = d.client(kOther), admin = d.client(kAdmin);
  // [limits] design_sessions = 2: the first draft leaves memory when the third is opened and
  // comes back from its saved document, items and card intact.
  std::vector<std::int64_t> ids;
  for (int i = 0; i < 3; ++i) {
    ids.push_back(create(kiosk));
    ASSERT_EQ(add(kiosk, ids.back(), wall(20 + i, 10, 90, 30)).status, 200);
  }
  const json first = get_json(kiosk, path(ids[0])).body;
  EXPECT_EQ(first["design"]["items"].size(), 1u);
  EXPECT_EQ(first["design"]["items"][0]["t"], 20.0);
  EXPECT_EQ(get_json(other, path(ids[0])).status, 404);
  EXPECT_EQ(add(other, ids[0], wall(40, 10, 90, 30)).status, 404);
  EXPECT_EQ(get_json(other, "/api/v1/designs").body["designs"].size(), 0u);
  EXPECT_EQ(get_json(admin, "/api/v1/designs").body["designs"].size(), 3u);
  EXPECT_EQ(other.Delete(path(ids[0]).c_str())->status, 404);
  EXPECT_EQ(kiosk.Delete(path(ids[0]).c_str())->status, 200);
  EXPECT_EQ(get_json(kiosk, path(ids[0])).status, 404);
  EXPECT_EQ(get_json(kiosk, "/api/v1/designs").body["designs"].size(), 2u);
}

TEST(PopcutdDesign, EditsFromManyClientsAtOnceAreAllKept) {
  TempDir dir("popcutd-design");
  PopcutdProcess d(POPCUTD, config(dir), (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const std::int64_t id = create(c);
  std::vector<std::thread> clients;
  std::vector<int> failures(4, 0);
  for (int k = 0; k < 4; ++k) {
    clients.emplace_back([&, k] {
      httplib::Client mine = d.client(kKiosk);
      for (int i = 0; i < 5; ++i) {
        if (add(mine, id, wall(5 + 4 * i + k, 10 + k, 90 - k, 20 + i)).status != 200)
          ++failures[static_cast<std::size_t>(k)];
      }
    });
  }
  for (std::thread& t : clients) t.join();
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(failures[k], 0) << "client " << k;
  const json state = get_json(c, path(id)).body;
  EXPECT_EQ(state["design"]["items"].size(), 20u);
  // The saved draft holds every edit too: the session and its document never diverged.
  const auto saved = c.Get(path(id, "/design.json").c_str());
  ASSERT_TRUE(saved);
  EXPECT_EQ(popcut::parse_design(saved->body, "saved").items().size(), 20u);
}

TEST(PopcutdDesign, ExportsAndSendsTheDesignToTheCutter) {
  TempDir dir("popcutd-design");
  PopcutdProcess d(POPCUTD, config(dir), (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const std::int64_t id = create(c);
  ASSERT_EQ(add(c, id, wall(30, 15, 85, 40)).status, 200);
  const auto svg = c.Get(path(id, "/pattern.svg").c_str());
  ASSERT_TRUE(svg && svg->status == 200);
  EXPECT_NE(svg->body.find("<svg"), std::string::npos);
  const auto dxf = c.Get(path(id, "/pattern.dxf").c_str());
  ASSERT_TRUE(dxf && dxf->status == 200);
  EXPECT_NE(dxf->body.find("VALLEY"), std::string::npos);
  const auto pdf = c.Get(path(id, "/pattern.pdf").c_str());
  ASSERT_TRUE(pdf && pdf->status == 200);
  EXPECT_EQ(pdf->get_header_value("Content-Type"), "application/pdf");
  EXPECT_EQ(pdf->body.rfind("%PDF-", 0), 0u);
  EXPECT_EQ(post_json(c, path(id, "/submit"), R"({"device": "sim-a", "model": {}})").status, 400);
  const Reply job = post_json(c, path(id, "/submit"), R"({"device": "sim-a"})");
  ASSERT_EQ(job.status, 201) << job.body.dump();
  EXPECT_EQ(job.body["name"], "Porch");
  const std::string job_path = "/api/v1/jobs/" + std::to_string(job.body["id"].get<std::int64_t>());
  ASSERT_TRUE(wait_until([&] { return get_json(c, job_path).body.value("state", "") == "done"; }, 120))
      << get_json(c, job_path).body.dump();
  EXPECT_TRUE(get_json(c, job_path).body.value("sim_match", false)) << "the simulator cut what was planned";
  // The job cut the design's card: its pattern is the design's.
  const auto job_svg = c.Get((job_path + "/pattern.svg").c_str());
  ASSERT_TRUE(job_svg);
  EXPECT_EQ(job_svg->body, svg->body);
}

TEST(PopcutdDesign, ANameInLettersIsOneItemThatPopsUpAndIsCutAsPlanned) {
  TempDir dir("popcutd-design");
  PopcutdProcess d(POPCUTD, config(dir), (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const Reply fonts = get_json(c, "/api/v1/fonts");
  ASSERT_EQ(fonts.status, 200);
  EXPECT_EQ(fonts.body["default"], "DejaVu Sans");
  const json& list = fonts.body["fonts"];
  EXPECT_NE(std::find(list.begin(), list.end(), json("DejaVu Serif")), list.end()) << list.dump();
  const std::int64_t id = create(c);
  ASSERT_EQ(add(c, id, wall(20, 5, 95, 50)).status, 200);
  const json name = {{"tool", "wall"}, {"t", 40}, {"text", {{"string", "Zoë"}, {"size", 12}}}, {"at", {20, 0}}};
  const Reply r = add(c, id, name);
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_TRUE(r.body["check"].value("pops_up", false)) << r.body["check"].dump();
  ASSERT_EQ(r.body["design"]["items"].size(), 2u);
  EXPECT_EQ(r.body["design"]["items"][1]["text"]["string"], "Zoë") << "the text is kept as typed, not as outlines";
  EXPECT_EQ(r.body["design"]["items"][1]["at"], json({20, 0}));

  const json before = get_json(c, path(id)).body;
  json missing = name, mirrored = name, roof = name, long_text = name;
  missing["text"]["font"] = "Comic Sans Nowhere";
  mirrored["mirror"] = true;
  roof["tool"] = "roof";
  long_text["text"]["string"] = std::string(300, 'x');
  Reply bad = add(c, id, missing);
  EXPECT_EQ(bad.status, 422);
  EXPECT_EQ(bad.body["error"].value("field", ""), "item.text.font") << bad.body.dump();
  EXPECT_NE(bad.body["error"].value("message", "").find("DejaVu Sans"), std::string::npos)
      << "names the fonts there are";
  EXPECT_EQ(add(c, id, mirrored).status, 422);
  EXPECT_EQ(add(c, id, roof).status, 422);
  bad = add(c, id, long_text);
  EXPECT_EQ(bad.status, 413) << bad.body.dump();
  EXPECT_NE(bad.body["error"].value("message", "").find("300 characters; at most 200"), std::string::npos)
      << bad.body.dump();
  EXPECT_EQ(get_json(c, path(id)).body, before) << "every refused text left the design as it was";

  expect_cut_as_planned(c, id);
}

// A webOAcard card posted as it is starts a draft of its faces: the editor's card exactly (one
// with holes seen through walls, with its faces that would not stand, one with loose pieces),
// edited on and cut as planned.
TEST(PopcutdDesign, AWebOAcardCardStartsADraftOfItsFacesThatIsCutAsPlanned) {
  POPCUT_NEEDS_SHARED_TESTDATA();
  TempDir dir("popcutd-design");
  PopcutdProcess d(POPCUTD, config(dir), (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const std::string college = read_file(popcut::testing::shared_testdata("webOAcard/demo/college.oa"));
  const Reply r = post_json(c, "/api/v1/designs", college);
  ASSERT_EQ(r.status, 201) << r.body.dump();
  EXPECT_EQ(r.body["check"]["not_standing"].size(), 3u) << "as the editor's own college: " << r.body["check"].dump();
  const json& items = r.body["design"]["items"];
  EXPECT_TRUE(std::any_of(items.begin(), items.end(), [](const json& it) { return it.contains("holes"); }))
      << "college's walls are seen through each other's windows";
  const std::int64_t id = r.body["id"].get<std::int64_t>();
  EXPECT_EQ(popcut::testing::compare_patterns(saved_pattern(c, id),
                                              popcut::make_pattern(popcut::parse_oa_model(college, "college.oa"))),
            "")
      << "the draft is the card popcut reads from the .oa file";
  // Edited on like any draft: a wall in front with its top, then undone.
  ASSERT_EQ(add(c, id, wall(95, 5, 20, 10)).status, 200);
  ASSERT_EQ(post_json(c, path(id, "/undo"), "").status, 200);

  const Reply castle =
      post_json(c, "/api/v1/designs", read_file(popcut::testing::shared_testdata("webOAcard/demo/castle.oa")));
  ASSERT_EQ(castle.status, 201) << castle.body.dump();
  EXPECT_FALSE(castle.body["check"].value("pops_up", true))
      << "the editor's castle leaves loose pieces; so does its draft";
  const Reply bad = post_json(c, "/api/v1/designs",
                              R"({"settings": {"cardW": 120, "cardH": 100}, "faces": [{"contours": [],
                                  "type": "HFACE", "mode": 0, "t": 10, "contoursType": ""}]})");
  EXPECT_EQ(bad.status, 422) << bad.body.dump();
  EXPECT_EQ(bad.body["error"].value("field", ""), "faces[0].type") << bad.body.dump();

  expect_cut_as_planned(c, id);
}

}  // namespace
