// popcut import's card size in mm (--height-mm, --fit-mm) and its warnings about sheets too big for a device, run as a
// user would.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_run.h"

namespace {
namespace fs = std::filesystem;
using nlohmann::json;

using popcut::testing::CliRun;

class ImportSize : public popcut::testing::CliFixture {
 protected:
  ImportSize() : CliFixture("popcut-size") {}
  // A tower 20 wide and 100 high: a tall mesh, as a standing figure is.
  std::string tower() {
    const fs::path p = dir_ / "tower.obj";
    std::ofstream(p) << "v 0 0 0\nv 20 0 0\nv 20 0 100\nv 0 0 100\nv 0 10 0\nv 20 10 0\nv 20 10 100\nv 0 10 100\n"
                        "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n";
    return p.string();
  }
  std::string out(const std::string& name) { return (dir_ / name).string(); }
};

TEST_F(ImportSize, TallMeshWarnsNamingTheDevicesAndSizes) {
  const CliRun r = run("import " + tower() + " -o " + out("t.json"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("sheet 126.0 x "), std::string::npos) << "the sheet size is reported: " << r.out;
  // 120 mm across makes the tower 600 mm high, on a sheet over 1.2 m long: too long for the
  // 1 m flatbeds; a roll cutter takes the sheet's height along its feed.
  EXPECT_NE(r.err.find("popcut: warning: " + tower() + ": the sheet (126 x "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" does not fit generic-hpgl (at most 599.975 x 999.975 mm)"), std::string::npos)
      << "names the device and its size: " << r.err;
  EXPECT_NE(r.err.find("use --fit-mm sim"), std::string::npos) << "and says what to do: " << r.err;
  EXPECT_EQ(r.err.find("does not fit graphtec-ce ("), std::string::npos)
      << "the roll takes it along its feed: " << r.err;
  const CliRun j = run("import " + tower() + " -o " + out("t.json") + " --json");
  ASSERT_EQ(j.code, 0) << j.err;
  const json report = json::parse(j.out);
  ASSERT_TRUE(report["warnings"].is_array()) << j.out;
  EXPECT_FALSE(report["warnings"].empty()) << "the same warnings in the JSON report";
  EXPECT_GT(report["sheet_mm"]["height"].get<double>(), 1000) << "the flat sheet: " << j.out;
}

TEST_F(ImportSize, HeightAndFitSizeTheCard) {
  CliRun r = run("import " + tower() + " -o " + out("t.json") + " --height-mm 120 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  json j = json::parse(r.out);
  EXPECT_NEAR(j["closed_mm"]["height"].get<double>(), 120, 1e-3) << r.out;
  EXPECT_NEAR(j["sheet_mm"]["height"].get<double>(), 240, 2e-3) << r.out;
  EXPECT_TRUE(j["warnings"].empty()) << "a 240 mm sheet fits every shipped device: " << r.out;
  r = run("import " + tower() + " -o " + out("t.json") + " --fit-mm '100×90' --json");
  ASSERT_EQ(r.code, 0) << r.err;
  j = json::parse(r.out);
  EXPECT_LE(j["closed_mm"]["height"].get<double>(), 90) << r.out;
  EXPECT_LE(j["closed_mm"]["width"].get<double>(), 100) << r.out;
  r = run("import " + tower() + " -o " + out("t.json") + " --resolution 40 --fit-mm graphtec-ce --json");
  ASSERT_EQ(r.code, 0) << r.err;
  j = json::parse(r.out);
  EXPECT_LE(j["sheet_mm"]["width"].get<double>(), 600) << "the flat sheet fits across the roll: " << r.out;
  EXPECT_GT(j["sheet_mm"]["width"].get<double>(), 590) << "as large as it lets it be: " << r.out;
  const std::string warnings = j["warnings"].dump();
  EXPECT_NE(warnings.find("does not fit roland-gx24"), std::string::npos)
      << "the narrower roll is warned of: " << r.out;
  EXPECT_EQ(warnings.find("does not fit graphtec-ce ("), std::string::npos)
      << "not the roll it was fitted to: " << r.out;
  const CliRun cut = run("plan " + out("t.json") + " --profile " + std::string(POPCUT_SOURCE_DIR) +
                         "/configs/devices/graphtec-ce.toml -o " + out("t.hpgl"));
  EXPECT_EQ(cut.code, 0) << "the fitted card plans for that device: " << cut.err;
}

TEST_F(ImportSize, ConflictsAndBadValuesExit2NamingTheOption) {
  CliRun r = run("import " + tower() + " -o " + out("t.json") + " --width-mm 100 --height-mm 80");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--height-mm: give one of --width-mm, --voxel-mm, --height-mm and --fit-mm (each sets the "
                       "card's size), not both --width-mm and --height-mm"),
            std::string::npos)
      << r.err;
  r = run("import " + tower() + " -o " + out("t.json") + " --fit-mm 100x50 --width-mm 100");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("not both --width-mm and --fit-mm"), std::string::npos) << r.err;
  r = run("import " + tower() + " -o " + out("t.json") + " --fit-mm nowhere");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--fit-mm: 'nowhere' is neither WxH in mm (e.g. 148x105, or 148×105) nor a device ("),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("graphtec-ce"), std::string::npos) << "the devices it could name are listed: " << r.err;
  r = run("import " + tower() + " -o " + out("t.json") + " --height-mm -3");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--height-mm: the card's height must be a positive number of mm, not -3"), std::string::npos)
      << r.err;
}

}  // namespace
