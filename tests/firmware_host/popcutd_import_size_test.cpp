// popcutd sizes an uploaded mesh's card like popcut import (height-mm, fit-mm), warns of sheets too big for its
// devices, and names examples by their models.
#include <gtest/gtest.h>

#include <filesystem>

#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::PopcutdProcess;
using popcut::testing::Reply;
using popcut::testing::TempDir;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-change-me-0123456789";
// A tower 20 wide and 100 high: at the default 120 mm across, a sheet over 1.2 m long.
const std::string kTower =
    "v 0 0 0\nv 20 0 0\nv 20 0 100\nv 0 0 100\nv 0 10 0\nv 20 10 0\nv 20 10 100\nv 0 10 100\n"
    "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n";

Reply post_mesh(httplib::Client& c, const std::string& path,
                const std::vector<std::pair<std::string, std::string>>& fields) {
  return popcut::testing::post_mesh(c, path, kTower, "tower.obj", fields);
}

// A flatbed (sim: 600 x 1000 mm) and a roll cutter that takes the sheet's width across its 600 mm
// and its height along the feed;
// examples from a folder of the test's own.
std::string size_config(const TempDir& dir) {
  std::filesystem::create_directories(dir.path() / "examples" / "voxel");
  std::filesystem::create_directories(dir.path() / "examples" / "faces");
  return dir.write("size.toml", "[server]\ndata_dir = \"x\"\nexamples_dir = \"" + (dir.path() / "examples").string() +
                                    "\"\n[limits]\nmodel_cells = 1000000\n"
                                    "[[device]]\nname = \"sim-a\"\nprofile = \"" +
                                    kSrc +
                                    "/configs/devices/sim.toml\"\ntransport = \"sim\"\n"
                                    "[[device]]\nname = \"roll\"\nprofile = \"" +
                                    kSrc +
                                    "/configs/devices/graphtec-ce.toml\"\ntransport = \"sim\"\n"
                                    "[[token]]\nname = \"kiosk\"\ntoken = \"" +
                                    kKiosk + "\"\n");
}

class PopcutdSize : public ::testing::Test {
 protected:
  PopcutdSize()
      : dir_("popcutd-size"), d_(POPCUTD, size_config(dir_), (dir_.path() / "data").string()), c_(d_.client(kKiosk)) {}
  TempDir dir_;
  PopcutdProcess d_;
  httplib::Client c_;
};

TEST_F(PopcutdSize, ImportSizesTheCardAndWarnsOfDevicesTooSmall) {
  Reply r = post_mesh(c_, "/api/v1/import", {});
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_GT(r.body["sheet_mm"]["height"].get<double>(), 1200) << "a tall sheet: " << r.body["sheet_mm"].dump();
  ASSERT_EQ(r.body["warnings"].size(), 1u)
      << "too long for the flatbed, not for the roll: " << r.body["warnings"].dump();
  EXPECT_NE(r.body["warnings"][0].get<std::string>().find("does not fit sim-a (at most 599.975 x 999.975 mm)"),
            std::string::npos)
      << r.body["warnings"].dump();

  r = post_mesh(c_, "/api/v1/import", {{"height-mm", "120"}});
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_NEAR(r.body["closed_mm"]["height"].get<double>(), 120, 1e-3) << r.body["closed_mm"].dump();
  EXPECT_TRUE(r.body["warnings"].empty()) << r.body["warnings"].dump();

  r = post_mesh(c_, "/api/v1/import", {{"fit-mm", "roll"}});
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_LE(r.body["sheet_mm"]["width"].get<double>(), 600)
      << "the flat sheet fits across the roll: " << r.body["sheet_mm"].dump();
  EXPECT_GT(r.body["sheet_mm"]["width"].get<double>(), 590) << r.body["sheet_mm"].dump();
  EXPECT_EQ(r.body["warnings"].dump().find("does not fit roll"), std::string::npos) << r.body["warnings"].dump();

  r = post_mesh(c_, "/api/v1/import", {{"fit-mm", "100×90"}});
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_LE(r.body["closed_mm"]["height"].get<double>(), 90) << r.body["closed_mm"].dump();
}

TEST_F(PopcutdSize, BadSizesAre400NamingTheField) {
  struct Case {
    std::vector<std::pair<std::string, std::string>> fields;
    std::string field, says;
  };
  const std::vector<Case> cases = {
      {{{"height-mm", "tall"}}, "height-mm", "'tall' is not a number"},
      {{{"height-mm", "0"}}, "height-mm", "positive number of mm"},
      {{{"fit-mm", "nowhere"}}, "fit-mm", "nor a device (sim-a, roll)"},
      {{{"fit-mm", "100x0"}}, "fit-mm", "positive number of mm each way"},
      {{{"width-mm", "100"}, {"height-mm", "80"}}, "height-mm", "not both --width-mm and --height-mm"},
      {{{"resolution", "abc"}}, "resolution", "not a whole number"},
  };
  for (const std::string path : {"/api/v1/import", "/api/v1/jobs"}) {
    for (Case k : cases) {
      if (path == "/api/v1/jobs") k.fields.push_back({"device", "sim-a"});
      const Reply r = post_mesh(c_, path, k.fields);
      const json e = r.body.value("error", json::object());
      EXPECT_EQ(r.status, 400) << path << " " << json(k.fields).dump() << ": " << r.body.dump();
      EXPECT_EQ(e.value("code", ""), "bad_request") << r.body.dump();
      EXPECT_EQ(e.value("field", ""), k.field) << r.body.dump();
      EXPECT_NE(e.value("message", "").find(k.says), std::string::npos) << "says '" << k.says << "': " << r.body.dump();
    }
  }
}

TEST_F(PopcutdSize, SubmissionsAnswerWithWarnings) {
  // 600 mm high: a 1200 mm sheet, along the roll's feed but not on the flatbed's 1000 mm.
  Reply r = post_mesh(c_, "/api/v1/jobs", {{"device", "roll"}, {"height-mm", "600"}});
  ASSERT_EQ(r.status, 201) << r.body.dump();
  ASSERT_EQ(r.body["warnings"].size(), 1u) << r.body.dump();
  EXPECT_NE(r.body["warnings"][0].get<std::string>().find("does not fit sim-a"), std::string::npos) << r.body.dump();
  r = post_mesh(c_, "/api/v1/jobs", {{"device", "roll"}, {"fit-mm", "roll"}});
  ASSERT_EQ(r.status, 201) << "a card fitted to the roll is taken for it: " << r.body.dump();
  EXPECT_EQ(r.body["warnings"].dump().find("does not fit roll"), std::string::npos) << r.body.dump();
}

TEST_F(PopcutdSize, ExamplesAreNamedByTheirModels) {
  dir_.write("examples/voxel/tower.json",
             R"({"format": "popcut.voxel.v1", "name": "Tall tower", "voxel_mm": 2, "heights": [[3]]})");
  dir_.write("examples/voxel/plain.json", R"({"format": "popcut.voxel.v1", "voxel_mm": 2, "heights": [[3]]})");
  dir_.write(
      "examples/faces/gallery.json",
      R"({"format": "popcut.faces.v1", "title": "Gallery", "sheet": {"width": 60, "back": 50, "floor": 50}, "edits": []})");
  // A name longer than a job's 64 characters is shown shortened, not dropped for the id.
  dir_.write("examples/voxel/long.json", R"({"format": "popcut.voxel.v1", "name": ")" + std::string(70, 'w') +
                                             R"(", "voxel_mm": 2, "heights": [[3]]})");
  const Reply r = popcut::testing::get_json(c_, "/api/v1/examples");
  ASSERT_EQ(r.status, 200) << r.body.dump();
  EXPECT_EQ(r.body["examples"], json({"faces-gallery", "voxel-long", "voxel-plain", "voxel-tower"}))
      << "the ids, as before: " << r.body.dump();
  EXPECT_EQ(r.body["names"], json({{"faces-gallery", "Gallery"},
                                   {"voxel-long", std::string(63, 'w') + "\u2026"},
                                   {"voxel-plain", "voxel-plain"},
                                   {"voxel-tower", "Tall tower"}}))
      << "each by its model's name or title, else its id: " << r.body.dump();
}

}  // namespace
