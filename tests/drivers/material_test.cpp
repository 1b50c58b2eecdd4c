// Materials: every shipped file loads with all families; bad files are refused naming file, section and key; applied to
// profiles.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "popcut/drivers/material.h"
#include "popcut/drivers/profile.h"
#include "popcut/error.h"

namespace popcut::drivers {
namespace {

const std::string kConfigs = std::string(POPCUT_SOURCE_DIR) + "/configs";
const std::string kMaterials = kConfigs + "/materials";

// A complete family table: every kind, the folds scored.
std::string family(const std::string& name, const std::string& cut = "{ force_g = 100, speed_cm_s = 10 }") {
  return "[" + name + "]\ncut = " + cut +
         "\noutline = { force_g = 110, speed_cm_s = 10 }\n"
         "valley = { mode = \"score\", force_g = 30, speed_cm_s = 10 }\n"
         "mountain = { mode = \"score\", force_g = 30, speed_cm_s = 10 }\n";
}
const std::string kHeader = "[material]\ndescription = \"test stock\"\nsources = [\"a test\"]\n";

TEST(Materials, EveryShippedMaterialLoadsWithEveryFamily) {
  const std::vector<std::string> names = material_names(kMaterials);
  for (const char* want : {"copy-80", "card-160", "card-220", "card-300", "vellum", "kraft", "vinyl"})
    EXPECT_NE(std::find(names.begin(), names.end(), want), names.end()) << want;
  for (const std::string& n : names) {
    try {
      const Material m = find_material(kMaterials, n);
      EXPECT_EQ(m.name, n);
      EXPECT_FALSE(m.description.empty()) << n;
      EXPECT_FALSE(m.sources.empty()) << n << ": every material says where its numbers come from";
      EXPECT_EQ(m.family_list(), "generic, silhouette, graphtec, roland, uscutter, secabo") << n;
    } catch (const Error& e) {
      ADD_FAILURE() << n << ": " << e.what();
    }
  }
}

struct Bad {
  std::string text;
  const char* location;
  const char* says;
};

TEST(Materials, BadMaterialsNameFileSectionAndKey) {
  const Bad cases[] = {
      {family("generic"), "[material] description", "missing"},
      {"[material]\ndescription = \"x\"\n" + family("generic"), "[material] sources", "where the numbers come from"},
      {"[material]\ndescription = \"x\"\nsources = [1]\n" + family("generic"), "[material] sources", "strings"},
      {"[material]\ndescription = \"\"\nsources = [\"s\"]\n" + family("generic"), "[material] description", "empty"},
      {kHeader + "colour = \"red\"\n" + family("generic"), "[material] colour", "unknown key"},
      {kHeader, "[FAMILY]", "no device family"},
      {kHeader + family("cricut"), "[cricut]", "unknown section"},
      {kHeader + family("generic", "{ force_g = 9000, speed_cm_s = 10 }"), "[generic.cut] force_g",
       "out of range 1 to 2000"},
      {kHeader + family("generic", "{ speed_cm_s = 10 }"), "[generic.cut] force_g", "missing"},
      {kHeader + family("generic", "{ force_g = 100 }"), "[generic.cut] speed_cm_s", "missing"},
      {kHeader + family("generic", "{ force_g = 100, speed_cm_s = 500 }"), "[generic.cut] speed_cm_s", "out of range"},
      {kHeader + family("generic", "{ force_g = \"hard\", speed_cm_s = 10 }"), "[generic.cut] force_g", "a number"},
      {kHeader + family("generic", "{ force_g = 100, speed_cm_s = 10, pen = 2 }"), "[generic.cut] pen", "unknown key"},
      {kHeader + family("generic", "{ force_g = 100, speed_cm_s = 10, mode = \"cut\" }"), "[generic.cut] mode",
       "unknown key"},
      {kHeader + family("generic", "{ force_g = 100, speed_cm_s = 10, passes = 11 }"), "[generic.cut] passes",
       "out of range 1 to 10"},
      {kHeader + family("generic", "{ passes = 2, pass_force_g = [50], speed_cm_s = 10 }"),
       "[generic.cut] pass_force_g", "has 1 values for 2 passes"},
      {kHeader + family("generic", "{ passes = 2, pass_force_g = [50, 3000], speed_cm_s = 10 }"),
       "[generic.cut] pass_force_g", "value 2 (pass 2): 3000 is out of range 1 to 2000"},
      {kHeader + family("generic", "{ passes = 2, pass_force_g = [50, \"x\"], speed_cm_s = 10 }"),
       "[generic.cut] pass_force_g", "value 2 (pass 2): expected a number"},
      {kHeader + family("generic", "{ force_g = 100, pass_speed_cm_s = [5, 10], speed_cm_s = 10 }"),
       "[generic.cut] pass_speed_cm_s", "has 2 values for 1 passes"},
      {kHeader + family("generic", "{ force_g = 100, pass_force_g = 5, speed_cm_s = 10 }"),
       "[generic.cut] pass_force_g", "expected an array"},
      {kHeader + "[generic]\ncut = { force_g = 100, speed_cm_s = 10 }\n", "[generic] valley", "every line kind"},
      {kHeader + family("generic") + "edge = { force_g = 1, speed_cm_s = 1 }\n", "[generic] edge", "unknown key"},
      {kHeader + family("generic", "5"), "[generic] cut", "expected a table"},
      {"generic = 5\n" + kHeader, "[generic]", "expected a table"},
      {kHeader + "[generic]\ncut = { force_g = 100, speed_cm_s = 10 }\noutline = { force_g = 100, speed_cm_s = 10 }\n"
                 "valley = { force_g = 30, speed_cm_s = 10 }\nmountain = { mode = \"score\", force_g = 30, speed_cm_s "
                 "= 10 }\n",
       "[generic.valley] mode", "\"score\" or \"perforate\""},
      {kHeader + "[generic]\ncut = { force_g = 100, speed_cm_s = 10 }\noutline = { force_g = 100, speed_cm_s = 10 }\n"
                 "valley = { mode = \"skip\", force_g = 30, speed_cm_s = 10 }\nmountain = { mode = \"score\", force_g "
                 "= 30, speed_cm_s = 10 }\n",
       "[generic.valley] mode", "not \"skip\""},
      {kHeader + "[generic]\ncut = { force_g = 100, speed_cm_s = 10 }\noutline = { force_g = 100, speed_cm_s = 10 }\n"
                 "valley = { mode = \"score\", force_g = 30, speed_cm_s = 10, perforate_on_mm = 2 }\n"
                 "mountain = { mode = \"score\", force_g = 30, speed_cm_s = 10 }\n",
       "[generic.valley] perforate_on_mm", "only with mode = \"perforate\""},
      {kHeader + "[generic]\ncut = { force_g = 100, speed_cm_s = 10 }\noutline = { force_g = 100, speed_cm_s = 10 }\n"
                 "valley = { mode = \"perforate\", force_g = 30, speed_cm_s = 10, perforate_on_mm = 0 }\n"
                 "mountain = { mode = \"score\", force_g = 30, speed_cm_s = 10 }\n",
       "[generic.valley] perforate_on_mm", "out of range 0.1 to 100"},
      {"[material\n", "line 1", ""},
  };
  for (const Bad& c : cases) {
    try {
      parse_material(c.text, "m.toml", "m");
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_input) << c.text;
      EXPECT_EQ(e.source(), "m.toml") << c.text;
      EXPECT_NE(e.location().find(c.location), std::string::npos) << e.what() << "\nexpected " << c.location;
      EXPECT_NE(e.message().find(c.says), std::string::npos) << e.what() << "\nexpected " << c.says;
    }
  }
}

TEST(Materials, AppliedToAProfileItsFamilysValuesReplaceTheProfiles) {
  DeviceProfile p = load_profile(kConfigs + "/devices/roland-gx24.toml");
  ASSERT_EQ(p.family, DeviceFamily::roland);
  const int pen = p.tools[index_of(PlanKind::cut)].pen;
  const Material m =
      parse_material(kHeader + family("generic") +
                         "[roland]\ncut = { passes = 2, pass_force_g = [60, 140], pass_speed_cm_s = [8, 4] }\n"
                         "outline = { force_g = 150, speed_cm_s = 20, passes = 3 }\n"
                         "valley = { mode = \"perforate\", force_g = 70, speed_cm_s = 9, perforate_on_mm = 2, "
                         "perforate_off_mm = 0.5 }\n"
                         "mountain = { mode = \"score\", force_g = 45, speed_cm_s = 7 }\n",
                     "m.toml", "m");
  apply_material(p, m);
  const ToolSetting& cut = p.tools[index_of(PlanKind::cut)];
  EXPECT_EQ(cut.pen, pen) << "the pen stays the profile's";
  EXPECT_EQ(cut.pass_force_g, (std::vector<double>{60, 140}));
  EXPECT_EQ(cut.pass_speed_cm_s, (std::vector<double>{8, 4}));
  EXPECT_DOUBLE_EQ(cut.force_g, 140) << "without force_g: the last (full) pass's";
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::cut)].passes, 2);
  EXPECT_TRUE(p.plan.kinds[index_of(PlanKind::cut)].separate_passes);
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::outline)].passes, 3);
  EXPECT_FALSE(p.plan.kinds[index_of(PlanKind::outline)].separate_passes) << "one force: back and forth as before";
  EXPECT_DOUBLE_EQ(p.tools[index_of(PlanKind::outline)].force_g, 150);
  const KindPlan& valley = p.plan.kinds[index_of(PlanKind::valley)];
  EXPECT_EQ(valley.mode, ToolMode::perforate);
  EXPECT_DOUBLE_EQ(valley.perforate_on_mm, 2);
  EXPECT_DOUBLE_EQ(valley.perforate_off_mm, 0.5);
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::mountain)].mode, ToolMode::score)
      << "roland-gx24 perforates mountains; the material scores them";
  EXPECT_DOUBLE_EQ(p.tools[index_of(PlanKind::mountain)].speed_cm_s, 7);
}

TEST(Materials, AKindTheProfileSkipsStaysSkipped) {
  DeviceProfile p = load_profile(kConfigs + "/devices/uscutter-mh.toml");
  ASSERT_EQ(p.plan.kinds[index_of(PlanKind::outline)].mode, ToolMode::skip);
  apply_material(p, find_material(kMaterials, "card-300"));
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::outline)].mode, ToolMode::skip);
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::mountain)].mode, ToolMode::perforate);
}

TEST(Materials, EachFamilyGetsItsOwnValues) {
  const Material m = find_material(kMaterials, "card-160");
  std::set<double> forces;
  for (const char* f : {"generic-hpgl", "graphtec-ce", "roland-gx24"}) {
    DeviceProfile p = load_profile(kConfigs + "/devices/" + f + ".toml");
    apply_material(p, m);
    const DeviceFamily fam = p.family;
    EXPECT_DOUBLE_EQ(p.tools[index_of(PlanKind::valley)].force_g,
                     (*m.families[static_cast<std::size_t>(fam)])[index_of(PlanKind::valley)].tool.force_g)
        << f;
    forces.insert(p.tools[index_of(PlanKind::outline)].force_g);
  }
  EXPECT_EQ(forces.size(), 2u) << "graphtec's forces are rounded to its 7 g levels, generic and roland's are not";
}

TEST(Materials, AMaterialWithoutTheDevicesFamilySaysWhichItHas) {
  DeviceProfile p = load_profile(kConfigs + "/devices/roland-gx24.toml");
  const Material m = parse_material(kHeader + family("generic") + family("graphtec"), "m.toml", "thin");
  try {
    apply_material(p, m);
    FAIL() << "applied a material with no roland values";
  } catch (const Error& e) {
    EXPECT_EQ(e.location(), "[roland]");
    EXPECT_NE(e.message().find("material \"thin\" has no values for the roland family"), std::string::npos) << e.what();
    EXPECT_NE(e.message().find("it has values for generic, graphtec"), std::string::npos) << e.what();
  }
}

TEST(Materials, AnUnknownNameListsTheKnownOnes) {
  for (const char* name : {"card-999", "../devices/sim", "", "card-160.toml"}) {
    try {
      find_material(kMaterials, name);
      ADD_FAILURE() << "found " << name;
    } catch (const Error& e) {
      EXPECT_EQ(e.location(), "material");
      EXPECT_NE(e.message().find(std::string("unknown material \"") + name + "\""), std::string::npos) << e.what();
      EXPECT_NE(e.message().find("known: card-160, card-220, card-300, copy-80, kraft, vellum, vinyl"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(Materials, ProfilesTakePerPassListsToo) {
  const DeviceProfile p =
      parse_profile("[device]\nname = \"x\"\n[tool.cut]\npasses = 2\npass_force_g = [50, 130]\n", "p.toml");
  EXPECT_EQ(p.tools[index_of(PlanKind::cut)].pass_force_g, (std::vector<double>{50, 130}));
  EXPECT_TRUE(p.plan.kinds[index_of(PlanKind::cut)].separate_passes);
  EXPECT_FALSE(p.plan.kinds[index_of(PlanKind::outline)].separate_passes);
  try {
    parse_profile("[device]\nname = \"x\"\n[tool.cut]\npass_speed_cm_s = [5, 10]\n", "p.toml");
    FAIL() << "two speeds for one pass";
  } catch (const Error& e) {
    EXPECT_EQ(e.location(), "[tool.cut] pass_speed_cm_s");
    EXPECT_NE(e.message().find("has 2 values for 1 passes"), std::string::npos) << e.what();
  }
}

// Each shipped material, applied to each shipped profile of a family it has values for, passes the profile language's
// own checks (a GP-GL device's FX and ! ranges), per pass too.
TEST(Materials, ShippedMaterialsSuitEveryShippedProfileTheyHaveAFamilyFor) {
  std::size_t applied = 0;
  for (const std::filesystem::directory_entry& e : std::filesystem::directory_iterator(kConfigs + "/devices")) {
    const DeviceProfile profile = load_profile(e.path().string());
    for (const std::string& n : material_names(kMaterials)) {
      const Material m = find_material(kMaterials, n);
      if (!m.families[static_cast<std::size_t>(profile.family)]) continue;
      DeviceProfile p = profile;
      try {
        apply_material(p, m);
        ++applied;
      } catch (const Error& err) {
        ADD_FAILURE() << n << " on " << e.path().filename() << ": " << err.what();
      }
    }
  }
  EXPECT_GE(applied, 70u) << "11 profiles times 7 materials";
}

// A value the material's ranges allow but the device's do not is refused naming the material's file and key.
TEST(Materials, AValueOutOfTheDevicesRangeIsRefusedNamingTheMaterialsKey) {
  const std::string cameo = kConfigs + "/devices/silhouette-cameo4.toml";
  const std::pair<std::string, std::string> cases[] = {
      {"{ force_g = 900, speed_cm_s = 10 }", "[silhouette.cut] force_g"},
      {"{ passes = 2, pass_force_g = [900, 100], speed_cm_s = 10 }", "[silhouette.cut] pass_force_g"},
      {"{ passes = 2, force_g = 100, pass_speed_cm_s = [150, 5] }", "[silhouette.cut] pass_speed_cm_s"},
  };
  for (const auto& [cut, where] : cases) {
    DeviceProfile p = load_profile(cameo);
    const Material m = parse_material(kHeader + family("silhouette", cut), "heavy.toml", "heavy");
    try {
      apply_material(p, m);
      ADD_FAILURE() << cut << " was applied";
    } catch (const Error& e) {
      EXPECT_EQ(e.source(), "heavy.toml") << e.what();
      EXPECT_EQ(e.location(), where) << e.what();
      EXPECT_NE(e.message().find("material \"heavy\" does not suit this device"), std::string::npos) << e.what();
      EXPECT_NE(e.message().find(cameo), std::string::npos) << e.what();
    }
  }
  // The profile's own per-pass values are checked as its single ones are.
  try {
    parse_profile(
        "[device]\nname = \"x\"\nlanguage = \"gpgl\"\nfamily = \"silhouette\"\n[tool.cut]\npasses = 2\n"
        "pass_force_g = [50, 500]\n",
        "p.toml");
    FAIL() << "a pass force above the device's range";
  } catch (const Error& e) {
    EXPECT_EQ(e.location(), "[tool.cut] pass_force_g") << e.what();
    EXPECT_NE(e.message().find("pass 2: "), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace popcut::drivers
