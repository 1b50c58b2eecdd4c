// Device profiles: every shipped file loads; bad profiles are refused naming file, section and key.
#include <gtest/gtest.h>

#include <filesystem>

#include "popcut/drivers/profile.h"
#include "popcut/error.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

using testing::shipped_profiles;

TEST(Profiles, EveryShippedProfileLoads) {
  const auto files = shipped_profiles();
  EXPECT_GE(files.size(), 6u) << "generic, Roland, Graphtec, US Cutter, Secabo and sim";
  for (const std::string& f : files) {
    try {
      const DeviceProfile p = load_profile(f);
      EXPECT_FALSE(p.name.empty()) << f;
      EXPECT_GT(p.dialect.area_max_x_pu, p.dialect.area_min_x_pu) << f;
      EXPECT_GE(p.dialect.area_min_x_pu, 0) << f << ": no profile ships with negative coordinates";
    } catch (const Error& e) {
      ADD_FAILURE() << f << ": " << e.what();
    }
  }
}

TEST(Profiles, ValuesArriveWhereTheyBelong) {
  const DeviceProfile p = load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/roland-gx24.toml");
  EXPECT_EQ(p.dialect.move_style, MoveStyle::inline_xy);
  EXPECT_EQ(p.dialect.force, ForceStyle::roland);
  EXPECT_FALSE(p.dialect.swap_axes) << "a swap alone would mirror the card";
  EXPECT_EQ(p.dialect.area_max_x_pu, 584 * 40) << "usable width in plotter units";
  EXPECT_EQ(p.transport.flow, FlowControl::xon_xoff);
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::mountain)].mode, ToolMode::perforate);
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::outline)].passes, 2);
  EXPECT_DOUBLE_EQ(p.tools[index_of(PlanKind::cut)].force_g, 110);
  EXPECT_DOUBLE_EQ(p.kinematics.travel_speed_mm_s, 500) << "cm/s in the file, mm/s inside";
}

struct Bad {
  const char* text;
  const char* location;  // expected "[section] key" (or line/column)
  const char* says;      // expected part of the message
};

TEST(Profiles, BadProfilesNameFileSectionAndKey) {
  const std::string ok = "[device]\nname = \"x\"\n";
  const Bad cases[] = {
      {"[device]\nname = \"x\"\nunits_per_mm = 0.5\n", "[device] units_per_mm", "out of range 1 to 1000"},
      {"[device]\nname = \"x\"\nspeed = 3\n", "[device] speed", "unknown key"},
      {"[device]\nname = \"x\"\n[motors]\n", "[motors]", "unknown section"},
      {"[device]\nname = \"x\"\n[tool.cut]\nforce_g = 5000\n", "[tool.cut] force_g", "out of range"},
      {"[device]\nname = \"x\"\n[tool.cut]\nforce = 50\n", "[tool.cut] force", "unknown key"},
      {"[device]\nname = \"x\"\n[tool.cut]\nmode = \"burn\"\n", "[tool.cut] mode", "not one of"},
      {"[device]\nname = \"x\"\n[tool.edge]\nmode = \"cut\"\n", "[tool.edge]", "unknown line kind"},
      {"[device]\nname = \"x\"\n[tool.valley]\npasses = 0\n", "[tool.valley] passes", "out of range 1 to 10"},
      {"[device]\nname = \"x\"\n[tool.cut]\npen = 0\n", "[tool.cut] pen", "out of range 1 to 8"},
      {"[device]\nname = \"x\"\n[tool.valley]\npasses = 1.5\n", "[tool.valley] passes", "whole number"},
      {"[device]\nname = \"x\"\n[hpgl]\nmove_style = \"fancy\"\n", "[hpgl] move_style", "\"separate\", \"inline\""},
      {"[device]\nname = \"x\"\n[hpgl]\nvelocity = \"yes\"\n", "[hpgl] velocity", "true or false"},
      {"[device]\nname = \"x\"\n[transport]\nflow_control = \"smoke\"\n", "[transport] flow_control", "not one of"},
      {"[device]\nname = \"x\"\n[transport]\nbuffer_bytes = 8\n", "[transport] buffer_bytes", "out of range"},
      {"[device]\nname = \"x\"\n[plan]\norder = [\"cut\", \"cut\", \"valley\", \"mountain\"]\n", "[plan] order",
       "appears twice"},
      {"[device]\nname = \"x\"\n[plan]\norder = [\"cut\"]\n", "[plan] order", "each of"},
      {"[device]\nname = \"x\"\n[plan]\nfold_gap_mm = -1\n", "[plan] fold_gap_mm", "out of range"},
      {"[device]\nname = \"x\"\narea_min_x_mm = -5\n", "[device] area_min_x_mm", "out of range 0"},
      {"[device]\nname = \"x\"\narea_max_x_mm = 0\n", "[device] area_max_x_mm", "must exceed"},
      {"[device]\nname = \"x\"\nswap_axes = true\n", "[device] swap_axes", "mirrors the card"},
      {"[device]\nname = \"x\"\nflip_y = true\n", "[device] flip_y", "flip_y = true mirrors the card"},
      {"[device]\nname = \"x\"\nswap_axes = true\nflip_x = true\nflip_y = true\n", "[device] swap_axes", "mirrors"},
      {"[device]\nname = \"x\"\nmirrored_frame = true\n", "[device] mirrored_frame", "needs a mirroring"},
      {"[hpgl]\ninit = \"IN;\"\n", "[device] name", "missing"},
      {"[device]\nname = \"x\"\n[hpgl]\nterminator = \"1\"\n", "[hpgl] terminator", "must be ';'"},
      {"[device]\nname = \"x\"\n[hpgl]\nterminator = \",\"\n", "[hpgl] terminator", "must be ';'"},
      {"[device]\nname = \"x\"\n[hpgl]\nterminator = \"\"\n", "[hpgl] terminator", "must be ';'"},
      {"[device]\nname = \"x\"\n[hpgl]\nterminator = \"\\r\"\n", "[hpgl] terminator", "must be ';'"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"IN;PA\"\n", "[hpgl] init", "'PA' is not ended by ';'"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"INSP1;\"\n", "[hpgl] init", "'IN' is not ended"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"IN;VS1.2.3;\"\n", "[hpgl] init", "numeric parameters"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"IN;OI;\"\n", "[hpgl] init", "'OI;' is an output instruction"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"IN;\\u0013\"\n", "[hpgl] init", "control or non-ASCII byte 0x13"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"\\u0000IN;\"\n", "[hpgl] init", "byte 0x00 at byte 1"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"\\u001b.B\"\n", "[hpgl] init", "not a set-up"},
      {"[device]\nname = \"x\"\n[hpgl]\ninit = \"IN;\\u001b.@1024\"\n", "[hpgl] init", "incomplete ESC"},
      {"[device]\nname = \"x\"\n[hpgl]\nfinish = \"PU;SP\"\n", "[hpgl] finish", "'SP' is not ended"},
      {"[device]\nname = \"x\"\n[plan]\nprecut_mm = 1\n", "[plan] precut_mm", "set blade_offset_mm"},
      {"[device]\nname = \"x\"\n[plan]\nblade_offset_mm = 0.3\nprecut_mm = 9\n", "[plan] precut_mm",
       "out of range 0 to 5"},
      {"[device]\nname = \n", "line 2", ""},
      {"[device]\nname = \"x\"\n[transport]\ndefault = \"bogus:thing\"\n", "[transport] default", "unknown scheme"},
      {"[device]\nname = \"x\"\n[transport]\ndefault = \"usb:0b4:110a\"\n", "[transport] default", "four hex digits"},
  };
  for (const Bad& b : cases) {
    try {
      parse_profile(b.text, "bad.toml");
      ADD_FAILURE() << "accepted:\n" << b.text;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_input) << b.text;
      EXPECT_EQ(e.source(), "bad.toml") << "names the file";
      EXPECT_EQ(e.location().rfind(b.location, 0), 0u) << "location for\n" << b.text << "was " << e.location();
      EXPECT_NE(e.message().find(b.says), std::string::npos) << "message for\n" << b.text << "was " << e.message();
    }
  }
  EXPECT_NO_THROW(parse_profile(ok, "ok.toml")) << "a name is all a profile needs";
  EXPECT_NO_THROW(parse_profile(
      ok + "[hpgl]\ninit = \"\\u001b.@1024;0:IN;\\n!ST1;\"\nfinish = \"PU;\\nSP0;\\n\"\nterminator = \";\\n\"\n",
      "ok.toml"))
      << "set-up sequences, Roland commands, newlines and a ';' + newline terminator are fine";
  EXPECT_NO_THROW(parse_profile(ok + "swap_axes = true\nflip_x = true\n", "ok.toml"))
      << "a swap and a flip: a quarter turn";
  EXPECT_NO_THROW(parse_profile(ok + "flip_x = true\nflip_y = true\n", "ok.toml")) << "two flips: a half turn";
  EXPECT_NO_THROW(parse_profile(ok + "swap_axes = true\nmirrored_frame = true\n", "ok.toml"))
      << "a mirrored device, mirrored back";
  EXPECT_NO_THROW(parse_profile(ok + "negative_coords = true\narea_min_x_mm = -5\n", "ok.toml"))
      << "negative coordinates when the device allows them";
  EXPECT_NO_THROW(parse_profile(ok + "[transport]\ndefault = \"serial:/dev/ttyUSB0\"\n", "ok.toml"))
      << "a well-formed default device";
}

// init, finish and abort go out around popcut's own commands (abort mid-job): none may cut. Only
// set-up commands pass, so every drawing command of HP-GL is refused, by name.
TEST(Profile, SetUpStringsNeverLowerTheKnifeOrDraw) {
  const std::string base = "[device]\nname = \"x\"\n";
  const auto refused = [&](const std::string& section, const std::string& key, const std::string& value,
                           const std::string& says) {
    const std::string text = base + "[" + section + "]\n" + key + " = \"" + value + "\"\n";
    try {
      parse_profile(text, "k.toml");
      ADD_FAILURE() << key << " = " << value << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_input);
      EXPECT_EQ(e.source(), "k.toml");
      EXPECT_EQ(e.location(), "[" + section + "] " + key) << value;
      EXPECT_NE(e.message().find(says), std::string::npos) << key << " = " << value << ": " << e.message();
      EXPECT_NE(e.message().find("allowed are IN, DF, PU"), std::string::npos)
          << "says what may be used: " << e.message();
    }
  };
  for (const char* key : {"init", "finish"}) {
    refused("hpgl", key, "IN;PD4000,4000;", "'PD4000,4000;' lowers the knife");
    refused("hpgl", key, "IN;pd;", "'pd;' lowers the knife");  // HP-GL mnemonics in either case
    refused("hpgl", key, "SP1;PA100,100;", "'PA100,100;' moves with the knife perhaps down: put PU before it");
    refused("hpgl", key, "SP1;PR5,5;", "'PR5,5;' moves with the knife perhaps down");
    // Arcs, circles, edges and fills, labels, symbols, encoded polylines, ticks, and what changes
    // the drawing of later strokes (line type, scaling, rotation, window, polygon mode).
    for (const char* cmd :
         {"AA", "AR", "AT", "RT", "CI", "EA", "ER", "RA", "RR", "WG", "EW", "EP", "FP", "PM", "LB",  "SM", "PE",
          "BZ", "BR", "TL", "XT", "YT", "CP", "LT", "IP", "IR", "SC", "RO", "IW", "DI", "UC", "!ZZ", "!PG"}) {
      const std::string c = std::string(cmd) + "10,10;";
      refused("hpgl", key, "IN;PU;" + c, "'" + c + "' is not a set-up command");
    }
  }
  refused("transport", "abort", "PD;", "must not lower the knife");
  refused("transport", "abort", "\\u001b.KPA0,0;", "'PA0,0;' moves with the knife perhaps down");
  refused("transport", "abort", "\\u001b.KCI5;", "'CI5;' is not a set-up command");
  refused("transport", "abort", "LBabc", "'LB' is not a set-up command");  // a label's text is not HP-GL
  // What set-up needs still passes: initialise, lift, select and park the tool, absolute or
  // relative mode, a move once the knife is up, Roland's force and tool commands, ESC set-ups.
  EXPECT_NO_THROW(
      parse_profile(base + "[hpgl]\ninit = \"IN;PA;DF;SP1;VS10;FS40;!FS50;!ST1;\"\nfinish = \"PU;PA0,0;PR;SP0;!NR;\"\n"
                           "[transport]\nabort = \"\\u001b.KPU;PA0,0;\"\n",
                    "ok.toml"));
  EXPECT_NO_THROW(parse_profile(base + "[hpgl]\ninit = \"IN;PU0,0;PA100,100;\"\n", "ok.toml"))
      << "IN and PU lift the knife";
}

}  // namespace
}  // namespace popcut::drivers
