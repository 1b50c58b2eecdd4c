// The GP-GL encoder (steps, resume, tools, holders, area) and the [gpgl] profile keys, each refusal naming file,
// [section] key and range.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "popcut/drivers/gpgl_reader.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/error.h"
#include "popcut/gpgl/gpgl.h"
#include "popcut/io/model_io.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

const std::string kGpgl = "[device]\nname = \"g\"\nlanguage = \"gpgl\"\narea_max_x_mm = 300.0\narea_max_y_mm = 300.0\n";

Error refusal(const std::string& text) {
  try {
    parse_profile(text, "g.toml");
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << text;
  return Error(ErrorCode::internal, "", "", "accepted");
}

// One 10 mm line along the pattern's x, then one along v, of two kinds.
StrokePlan two_lines() {
  StrokePlan plan;
  plan.sheet = Rect{{0, 0}, {20, 20}};
  plan.strokes.push_back(Stroke{PlanKind::valley, {{0, 0}, {10, 0}}});
  plan.strokes.push_back(Stroke{PlanKind::cut, {{0, 0}, {0, 10}}});
  return plan;
}

std::vector<DeviceCommand> commands(const std::string& bytes) {
  std::vector<DeviceCommand> out;
  for (DeviceCommand& c : parse_gpgl(bytes)) {
    if (!c.device_control) out.push_back(std::move(c));
  }
  return out;
}

std::vector<double> params_of(const std::string& bytes, const std::string& name) {
  for (const DeviceCommand& c : commands(bytes)) {
    if (c.name == name) return c.params;
  }
  return {};
}

TEST(GpglEncoder, StepSizesScaleTheCoordinates) {
  for (const auto& [step, units] : {std::pair{"0.1", 100.0}, std::pair{"0.05", 200.0}, std::pair{"0.025", 400.0}}) {
    const DeviceProfile p = parse_profile(kGpgl + "[gpgl]\nstep_mm = " + step + "\n", "g.toml");
    EXPECT_DOUBLE_EQ(p.dialect.units_per_mm_x, units / 10) << step;
    const std::string job = encode_for_device(two_lines(), p).bytes;
    EXPECT_EQ(params_of(job, "D"), (std::vector<double>{units, 0})) << step << ": 10 mm along x";
  }
  const Error odd = refusal(kGpgl + "[gpgl]\nstep_mm = 0.03\n");
  EXPECT_EQ(odd.location(), "[gpgl] step_mm");
  EXPECT_EQ(odd.source(), "g.toml");
  EXPECT_EQ(odd.message(), "must be one of 0.1, 0.05, 0.025, 0.01 (the device's GP-GL step setting)");
  const Error units = refusal(kGpgl + "units_per_mm = 40.0\n");
  EXPECT_EQ(units.location(), "[device] units_per_mm");
}

TEST(GpglEncoder, FillsTheJobLikeEveryLanguage) {
  const DeviceProfile p = parse_profile(kGpgl, "g.toml");
  const EncodedJob job = encode_for_device(two_lines(), p);
  EXPECT_EQ(job.bytes.rfind("\x1b\x04", 0), 0u);
  ASSERT_EQ(job.total_strokes, 2u);
  ASSERT_EQ(job.stroke_end.size(), 2u);
  ASSERT_EQ(job.stroke_cut_start.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(job.bytes[job.stroke_cut_start[i]], 'D') << "the knife goes down with the next command";
    EXPECT_EQ(job.bytes[job.stroke_end[i] - 1], '\x03');
    EXPECT_EQ(job.bytes[job.stroke_cut_start[i] - 1], '\x03');
  }
  EXPECT_EQ(job.command_end.back(), job.bytes.size());
  std::size_t etx = static_cast<std::size_t>(std::count(job.bytes.begin(), job.bytes.end(), '\x03'));
  EXPECT_EQ(job.command_end.size(), etx + 1) << "every command, ESC EOT included";
  EXPECT_TRUE(std::is_sorted(job.command_end.begin(), job.command_end.end()));
}

TEST(GpglEncoder, ResumeReinitialisesAndTravelsKnifeUp) {
  const DeviceProfile p =
      parse_profile(kGpgl + "[tool.valley]\nforce_g = 35.0\n[tool.cut]\nforce_g = 140.0\n", "g.toml");
  const EncodedJob whole = encode_for_device(two_lines(), p);
  const EncodedJob rest = encode_for_device(two_lines(), p, 2);
  EXPECT_EQ(rest.first_stroke, 2u);
  EXPECT_EQ(rest.total_strokes, 2u);
  ASSERT_EQ(rest.stroke_end.size(), 1u);
  EXPECT_EQ(rest.bytes.rfind("\x1b\x04", 0), 0u) << "initialises again";
  const std::vector<DeviceCommand> cmds = commands(rest.bytes);
  ASSERT_GE(cmds.size(), 4u);
  EXPECT_EQ(cmds[0].name, "FX");
  EXPECT_EQ(cmds[0].params, (std::vector<double>{20})) << "the cut's force (140 g at 7 g a level)";
  EXPECT_EQ(cmds[2].name, "M") << "travel to stroke 2 with the knife up";
  EXPECT_EQ(cmds[3].name, "D");
  EXPECT_EQ(whole.bytes.substr(whole.stroke_cut_start[1], whole.stroke_end[1] - whole.stroke_cut_start[1]),
            rest.bytes.substr(rest.stroke_cut_start[0], rest.stroke_end[0] - rest.stroke_cut_start[0]))
      << "the same cut";
  EXPECT_THROW(encode_for_device(two_lines(), p, 0), Error);
  EXPECT_THROW(encode_for_device(two_lines(), p, 3), Error);
}

TEST(GpglEncoder, ToolCommandsOnlyWhereTheSettingChanges) {
  const std::string same =
      "[tool.valley]\nforce_g = 70.0\nspeed_cm_s = 5.0\n[tool.cut]\nforce_g = 70.0\nspeed_cm_s = 3.0\n";
  const std::string job = encode_for_device(two_lines(), parse_profile(kGpgl + same, "g.toml")).bytes;
  std::vector<std::string> tools;
  for (const DeviceCommand& c : commands(job)) {
    if (c.name == "FX" || c.name == "!" || c.name == "J") tools.push_back(c.name + std::to_string(int(c.params[0])));
  }
  EXPECT_EQ(tools, (std::vector<std::string>{"FX10", "!5", "!3"})) << "FX once: both kinds press 70 g";
}

TEST(GpglEncoder, DualCarriageSelectsTheHolder) {
  const std::string two = "[gpgl]\ntool_holders = 2\ntool_in_params = true\n[tool.valley]\npen = 2\n";
  const std::string job = encode_for_device(two_lines(), parse_profile(kGpgl + two, "g.toml")).bytes;
  std::vector<std::string> got;
  for (const DeviceCommand& c : commands(job)) {
    if (c.name == "J" || c.name == "FX" || c.name == "!") {
      std::string s = c.name;
      for (double v : c.params) s += " " + std::to_string(int(v));
      got.push_back(s);
    }
  }
  EXPECT_EQ(got, (std::vector<std::string>{"J 2", "FX 6 2", "! 10 2", "J 1", "FX 17 1", "! 10 1", "J 0"}))
      << "each holder gets its own force and speed; J0 at the end";
  const std::string one = encode_for_device(two_lines(), parse_profile(kGpgl, "g.toml")).bytes;
  EXPECT_TRUE(params_of(one, "J").empty()) << "no J on a single-holder device";
  const Error pen = refusal(kGpgl + "[tool.valley]\npen = 2\n");
  EXPECT_EQ(pen.location(), "[tool.valley] pen");
  EXPECT_EQ(pen.message(), "2 is out of range 1 to 1 (the device's tool holders, [gpgl] tool_holders)");
}

TEST(GpglEncoder, OutOfAreaAndOutOfRangeAreRefused) {
  StrokePlan far = two_lines();
  far.sheet = Rect{{0, 0}, {400, 20}};
  EXPECT_THROW(encode_for_device(far, parse_profile(kGpgl, "g.toml")), Error) << "a sheet wider than the area";
  const Error force = refusal(kGpgl + "[tool.cut]\nforce_g = 400.0\n");
  EXPECT_EQ(force.location(), "[tool.cut] force_g");
  EXPECT_EQ(force.message(), "400 g is FX level 57, outside this device's 1..33 (7 g a level)");
  const Error speed = refusal(kGpgl + "[tool.cut]\nspeed_cm_s = 0.2\n");
  EXPECT_EQ(speed.location(), "[tool.cut] speed_cm_s");
  GpglDialect d;
  EXPECT_THROW(d.force_level(0.1), Error);
  EXPECT_EQ(d.speed_level(10), 10);
}

// The sheet's top edge at the device origin (sheet_at_origin), the card upright as loaded.
TEST(GpglEncoder, TheSheetSitsAtTheOriginOfAFlippedAxis) {
  const DeviceProfile p = load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/silhouette-cameo4.toml");
  const StrokePlan plan = two_lines();
  const auto paths = plan_in_plotter_units(plan, p.dialect);
  ASSERT_EQ(paths.size(), 2u);
  // Pattern (0,0)-(10,0) runs along the carriage at the sheet's bottom edge, 20 mm from the top.
  EXPECT_EQ(paths[0], (PlotterPath{{400, 0}, {400, 200}}));
  EXPECT_EQ(paths[1], (PlotterPath{{400, 0}, {200, 0}})) << "up the card is toward the sheet's top, the origin";
}

TEST(GpglProfile, KeysAreRangeChecked) {
  const struct {
    std::string text, location, message;
  } cases[] = {
      {"[gpgl]\ntool_holders = 3\n", "[gpgl] tool_holders", "3 is out of range 1 to 2"},
      {"[gpgl]\nforce_min = 5\nforce_max = 4\n", "[gpgl] force_max", "must be at least force_min (5)"},
      {"[gpgl]\nmedia = 99\n", "[gpgl] media", "99 is out of range 100 to 300"},
      {"[gpgl]\nhome = \"park\"\n", "[gpgl] home", "\"park\" is not one of \"none\", \"tt\", \"h\""},
      {"[gpgl]\nfinish = 1\n", "[gpgl] finish", "expected one of \"origin\", \"home\", \"none\""},
      {"[gpgl]\ncutter_offset_mm = 9.0\n", "[gpgl] cutter_offset_mm", "9 is out of range 0 to 5"},
      {"[gpgl]\nsetup = [\"D1,1\"]\n", "[gpgl] setup",
       "'D1,1' is not a set-up command that leaves the head and knife alone (allowed are FE, FF, FM, TB50-55, "
       "TB99, TG, TJ, TF, L, \\ and Z)"},
      {"[gpgl]\nsetup = [\"TB70\"]\n", "[gpgl] setup",
       "'TB70' is not a set-up command that leaves the head and knife alone (allowed are FE, FF, FM, TB50-55, "
       "TB99, TG, TJ, TF, L, \\ and Z)"},
      {"[gpgl]\nsetup = [\"FN1\"]\n", "[gpgl] setup", "'FN1' has a key of its own: [gpgl] orientation"},
      {"[gpgl]\nsetup = [\"FE0\\u0003FE1\"]\n", "[gpgl] setup",
       "control or non-ASCII byte 0x03 at byte 4 (popcut adds the ETX)"},
      {"[gpgl]\nsetup = [3]\n", "[gpgl] setup", "expected strings, one GP-GL command each"},
      {"[gpgl]\nspeed = 3\n", "[gpgl] speed", "unknown key"},
      {"[hpgl]\ninit = \"IN;\"\n", "[hpgl]", "is for hpgl devices, and [device] language is \"gpgl\""},
      {"[transport]\nabort = \"D1,1\\u0003\"\n", "[transport] abort",
       "must not lower the knife, it is sent to stop a job: 'D ...' cuts"},
      {"[transport]\nabort = \"\\u001b\\u0005\"\n", "[transport] abort",
       "'ESC ENQ' is not ESC EOT (initialise), the one device-control sequence that stops a job"},
      {"[transport]\nabort = \"FO0\\u0003\"\n", "[transport] abort",
       "'FO ...' is not a stop command (allowed: ESC EOT, H, TT, M x,y with the knife up, J n)"},
      {"[gpgl]\ncutter_offset_mm = 0.9\n[plan]\nblade_offset_mm = 0.3\n", "[gpgl] cutter_offset_mm",
       "the device would compensate the blade offset on top of [plan] blade_offset_mm: set one of them to 0"},
  };
  for (const auto& c : cases) {
    const Error e = refusal(kGpgl + c.text);
    EXPECT_EQ(e.source(), "g.toml") << c.text;
    EXPECT_EQ(e.location(), c.location) << c.text;
    EXPECT_EQ(e.message(), c.message) << c.text;
  }
  const DeviceProfile ok = parse_profile(kGpgl + "[transport]\nabort = \"\\u001b\\u0004H\\u0003\"\n", "g.toml");
  EXPECT_EQ(ok.transport.abort, "\x1b\x04H\x03");
  EXPECT_TRUE(ok.transport.abort_discards_buffer);
}

// Every shipped GP-GL profile's encoder is the GP-GL encoder with [device]'s frame.
TEST(GpglProfile, ShippedProfilesEncodeWithTheirDialect) {
  const Pattern pattern = make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/box.json"));
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = load_profile(file);
    if (p.language != CutterLanguage::gpgl) continue;
    const auto encoder = make_encoder(p);
    EXPECT_EQ(encoder->language(), CutterLanguage::gpgl) << file;
    GpglDialect d = p.gpgl;
    static_cast<PlotterFrame&>(d) = p.dialect;
    const StrokePlan plan = plan_strokes(pattern, p.plan);
    EXPECT_EQ(encoder->encode(plan, p.tools, 1).bytes, encode_gpgl_job(plan, d, p.tools).bytes) << file;
    EXPECT_EQ(p.transport.abort.find('D'), std::string::npos) << file;
  }
}

// configs/udev lets the user reach every cutter a shipped profile names, and each USB id names one
// profile, so `popcut devices` lists an attached cutter under one device name.
TEST(GpglProfile, UdevRulesCoverEveryShippedUsbIdOnce) {
  std::ifstream in(std::string(POPCUT_SOURCE_DIR) + "/configs/udev/60-popcut-cutters.rules");
  std::stringstream rules;
  rules << in.rdbuf();
  std::map<std::string, std::string> owner;
  int silhouettes = 0;
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = load_profile(file);
    silhouettes += p.family == DeviceFamily::silhouette;
    for (const std::string& id : p.transport.usb_ids) {
      const std::string rule =
          "ATTRS{idVendor}==\"" + id.substr(0, 4) + "\", ATTRS{idProduct}==\"" + id.substr(5) + "\"";
      EXPECT_NE(rules.str().find("SUBSYSTEM==\"usb\", " + rule), std::string::npos)
          << file << ": no udev rule for " << id;
      const auto [it, fresh] = owner.emplace(id, p.name);
      EXPECT_TRUE(fresh) << id << " is in two profiles: " << it->second << " and " << p.name;
    }
  }
  EXPECT_EQ(silhouettes, 4);
  EXPECT_EQ(owner["0b4d:1137"], "Silhouette Cameo 4");
  EXPECT_EQ(owner["0b4d:112f"], "Silhouette Cameo 3");
  EXPECT_EQ(owner["0b4d:113a"], "Silhouette Portrait 3");
  EXPECT_EQ(owner["0b4d:112c"], "Silhouette Curio");
}

}  // namespace
}  // namespace popcut::drivers
