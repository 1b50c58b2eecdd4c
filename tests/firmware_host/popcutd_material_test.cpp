// popcutd jobs with a material: listed, validated field by field (4xx naming `material`), stored, cut with its passes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::get_json;
using popcut::testing::PopcutdProcess;
using popcut::testing::post_json;
using popcut::testing::post_mesh;
using popcut::testing::read_file;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-change-me-0123456789";

json box() { return json::parse(read_file(kSrc + "/examples/voxel/box.json")); }

json done_job(httplib::Client& c, std::int64_t id) {
  json job;
  EXPECT_TRUE(wait_until(
      [&] {
        job = get_json(c, "/api/v1/jobs/" + std::to_string(id)).body;
        return job["state"] == "done" || job["state"] == "failed";
      },
      120));
  return job;
}

TEST(PopcutdMaterials, ListedValidatedStoredAndCut) {
  TempDir dir("popcutd-material");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);

  const auto list = get_json(c, "/api/v1/materials");
  ASSERT_EQ(list.status, 200);
  ASSERT_EQ(list.body["materials"].size(), 7u) << list.body.dump();
  EXPECT_EQ(list.body["materials"][0]["name"], "card-160");
  EXPECT_EQ(list.body["materials"][0]["families"].size(), 6u);
  EXPECT_FALSE(list.body["materials"][0]["description"].get<std::string>().empty());

  const auto unknown =
      post_json(c, "/api/v1/jobs", json{{"device", "sim-a"}, {"material", "tin"}, {"model", box()}}.dump());
  EXPECT_EQ(unknown.status, 422);
  EXPECT_EQ(unknown.body["error"]["code"], "no_material");
  EXPECT_EQ(unknown.body["error"]["field"], "material");
  EXPECT_NE(
      unknown.body["error"]["message"].get<std::string>().find("unknown material \"tin\" (known: card-160, card-220"),
      std::string::npos)
      << unknown.body.dump();
  const auto wrong_type =
      post_json(c, "/api/v1/jobs", json{{"device", "sim-a"}, {"material", 5}, {"model", box()}}.dump());
  EXPECT_EQ(wrong_type.status, 400);
  EXPECT_EQ(wrong_type.body["error"]["field"], "material");
  const auto mesh = post_mesh(c, "/api/v1/jobs", read_file(kSrc + "/examples/meshes/house.obj"), "house.obj",
                              {{"profile", "sim"}, {"material", "../devices/sim"}});
  EXPECT_EQ(mesh.status, 422) << "an upload's material field is checked the same way";
  EXPECT_EQ(mesh.body["error"]["field"], "material");

  const auto plain = post_json(c, "/api/v1/jobs", json{{"device", "sim-a"}, {"model", box()}}.dump());
  const auto card =
      post_json(c, "/api/v1/jobs", json{{"device", "sim-a"}, {"material", "card-220"}, {"model", box()}}.dump());
  ASSERT_EQ(plain.status, 201) << plain.body.dump();
  ASSERT_EQ(card.status, 201) << card.body.dump();
  EXPECT_TRUE(plain.body["material"].is_null());
  EXPECT_EQ(card.body["material"], "card-220");
  const json a = done_job(c, plain.body["id"].get<std::int64_t>());
  const json b = done_job(c, card.body["id"].get<std::int64_t>());
  EXPECT_EQ(a["state"], "done") << a.dump();
  EXPECT_EQ(b["state"], "done") << b.dump();
  EXPECT_TRUE(b["sim_match"].get<bool>()) << "the simulator cut the material's plan: " << b.dump();
  EXPECT_GT(b["strokes_total"].get<int>(), a["strokes_total"].get<int>()) << "card-220's passes are strokes";
  EXPECT_EQ(b["material"], "card-220") << "stored with the job";

  // popcut submit --material: the same field.
  const std::string cmd = std::string(POPCUT_CLI) + " submit " + kSrc + "/examples/voxel/box.json --device sim-b" +
                          " --material vellum --wait --json --server http://127.0.0.1:" + std::to_string(d.port()) +
                          " --token " + kKiosk + " >" + (dir.path() / "out").string() + " 2>&1";
  ASSERT_EQ(WEXITSTATUS(std::system(cmd.c_str())), 0) << read_file((dir.path() / "out").string());
  const json submitted = json::parse(read_file((dir.path() / "out").string()));
  EXPECT_EQ(submitted["material"], "vellum");
  EXPECT_EQ(submitted["state"], "done");
  const std::string bad = std::string(POPCUT_CLI) + " submit " + kSrc + "/examples/voxel/box.json --device sim-b" +
                          " --material tin --server http://127.0.0.1:" + std::to_string(d.port()) + " --token " +
                          kKiosk + " >" + (dir.path() / "bad").string() + " 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2) << read_file((dir.path() / "bad").string());
  EXPECT_NE(read_file((dir.path() / "bad").string()).find("unknown material \"tin\""), std::string::npos);
}

// A material whose values suit its family's files but not this device (a force above the Cameo 4's
// FX range) is refused as the material, 422 no_material on the field, naming the file and key.
TEST(PopcutdMaterials, ValuesOutOfTheDevicesRangeRefuseTheMaterial) {
  TempDir dir("popcutd-material-range");
  const std::string table = " = { force_g = 30, speed_cm_s = 10, mode = \"score\" }\n";
  dir.write("materials/heavy.toml",
            "[material]\ndescription = \"too heavy for a Cameo\"\nsources = [\"a test\"]\n[silhouette]\n"
            "cut = { force_g = 900, speed_cm_s = 10 }\noutline = { force_g = 110, speed_cm_s = 10 }\nvalley" +
                table + "mountain" + table);
  const std::string config = dir.write(
      "popcutd.toml", "[server]\ndata_dir = \"" + (dir.path() / "data").string() + "\"\nmaterials_dir = \"" +
                          (dir.path() / "materials").string() + "\"\n[[device]]\nname = \"cameo\"\nprofile = \"" +
                          kSrc + "/configs/devices/silhouette-cameo4.toml\"\ntransport = \"sim\"\n[[token]]\n" +
                          "name = \"kiosk\"\ntoken = \"" + kKiosk + "\"\n");
  PopcutdProcess d(POPCUTD, config, (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const auto heavy =
      post_json(c, "/api/v1/jobs", json{{"device", "cameo"}, {"material", "heavy"}, {"model", box()}}.dump());
  EXPECT_EQ(heavy.status, 422) << heavy.body.dump();
  EXPECT_EQ(heavy.body["error"]["code"], "no_material");
  EXPECT_EQ(heavy.body["error"]["field"], "material");
  const std::string message = heavy.body["error"]["message"].get<std::string>();
  EXPECT_NE(message.find("heavy.toml: [silhouette.cut] force_g"), std::string::npos) << message;
  EXPECT_NE(message.find("material \"heavy\" does not suit this device"), std::string::npos) << message;
  EXPECT_EQ(get_json(c, "/api/v1/jobs").body["jobs"].size(), 0u) << "nothing was queued";
}

}  // namespace
