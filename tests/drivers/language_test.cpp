// The cutter-language seam: the profile's language picks the encoder and the simulator's reader; typed choices.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "popcut/drivers/hpgl_reader.h"
#include "popcut/drivers/language.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/toml_section.h"
#include "popcut/error.h"
#include "popcut/io/model_io.h"
#include "shipped_profiles.h"

namespace popcut::drivers {
namespace {

// The Error `run` throws, or a test failure when it throws none.
template <class F>
Error thrown_by(F run, const std::string& what) {
  try {
    run();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << what;
  return Error(ErrorCode::internal, "", "", "accepted");
}

// The Error parse_profile throws for `text`.
Error refusal(const std::string& text) {
  return thrown_by([&] { parse_profile(text, "lang.toml"); }, text);
}

const std::string kBase = "[device]\nname = \"x\"\n";

TEST(CutterLanguage, DefaultsToHpglAndNamesItExplicitly) {
  EXPECT_EQ(parse_profile(kBase, "a.toml").language, CutterLanguage::hpgl) << "every existing profile is HP-GL";
  EXPECT_EQ(parse_profile(kBase + "language = \"hpgl\"\n", "a.toml").language, CutterLanguage::hpgl);
  for (const LanguageUnit* unit : language_units()) {
    EXPECT_EQ(kCutterLanguageNames.find(kCutterLanguageNames.name(unit->language)), unit->language)
        << "a name per unit";
    EXPECT_EQ(&language_unit(unit->language), unit);
  }
  EXPECT_EQ(language_unit(CutterLanguage::hpgl).section, "hpgl");
  EXPECT_EQ(language_unit(CutterLanguage::gpgl).section, "gpgl");
  EXPECT_EQ(parse_profile(kBase + "language = \"gpgl\"\n", "a.toml").language, CutterLanguage::gpgl);
}

TEST(CutterLanguage, AnUnknownLanguageIsRefusedAtItsKey) {
  const Error unknown = refusal(kBase + "language = \"camm\"\n");
  EXPECT_EQ(unknown.code(), ErrorCode::invalid_input);
  EXPECT_EQ(unknown.source(), "lang.toml");
  EXPECT_EQ(unknown.location(), "[device] language");
  EXPECT_EQ(unknown.message(), "\"camm\" is not one of \"hpgl\", \"gpgl\"");
  const Error typed = refusal(kBase + "language = 3\n");
  EXPECT_EQ(typed.location(), "[device] language");
  EXPECT_EQ(typed.message(), "expected one of \"hpgl\", \"gpgl\"");
}

// The encoder the profile picks writes exactly what encode_job writes, from stroke 1 and later.
TEST(CutterLanguage, TheProfilesEncoderIsTheHpglEncoder) {
  const Pattern pattern = make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/box.json"));
  for (const std::string& file : testing::shipped_profiles()) {
    const DeviceProfile p = load_profile(file);
    if (p.language != CutterLanguage::hpgl) continue;  // gpgl_encoder_test.cpp
    const StrokePlan plan = plan_strokes(pattern, p.plan);
    const auto encoder = make_encoder(p);
    ASSERT_NE(encoder, nullptr) << file;
    EXPECT_EQ(encoder->language(), CutterLanguage::hpgl) << file;
    const EncodedJob whole = encoder->encode(plan, p.tools, 1);
    EXPECT_EQ(whole.bytes, encode_hpgl(plan, p.dialect, p.tools)) << file;
    EXPECT_EQ(whole.stroke_end, encode_job(plan, p.dialect, p.tools).stroke_end) << file;
    ASSERT_GE(whole.total_strokes, 2u) << file;
    const EncodedJob rest = encode_for_device(plan, p, 2);
    EXPECT_EQ(rest.bytes, encode_job(plan, p.dialect, p.tools, 2).bytes) << file;
    EXPECT_EQ(rest.first_stroke, 2u) << file;
    EXPECT_THROW(encode_for_device(plan, p, 0), Error) << file << ": strokes are numbered from 1";
  }
}

// The dialect goes with the encoder: another profile's settings change the bytes.
TEST(CutterLanguage, TheEncoderIsBoundToTheProfilesDialect) {
  const Pattern pattern = make_pattern(load_model(std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/box.json"));
  DeviceProfile p = parse_profile(kBase, "a.toml");
  const StrokePlan plan = plan_strokes(pattern, p.plan);
  const std::string plain = encode_for_device(plan, p).bytes;
  p.dialect.init = "IN;DF;";
  EXPECT_EQ(encode_for_device(plan, p).bytes.rfind("IN;DF;", 0), 0u);
  EXPECT_NE(encode_for_device(plan, p).bytes, plain);
}

TEST(DeviceReader, TheProfilesReaderGivesEachCommandItsOp) {
  const auto reader = make_reader(parse_profile(kBase, "a.toml"));
  ASSERT_NE(reader, nullptr);
  std::vector<DeviceCommand> out;
  reader->feed("IN;SP2;VS10;!FS80;PU10,20;PD30,40;PR5,5;PA;DF;!ST1;OI;OS;OA;ZZ3;\x1b.B\x1b.Z\x1b.K\x1b.@1024:", out);
  reader->finish(out);
  std::vector<DeviceOp> ops;
  std::vector<bool> control;
  for (const DeviceCommand& c : out) ops.push_back(c.op), control.push_back(c.device_control);
  EXPECT_EQ(ops,
            (std::vector<DeviceOp>{
                DeviceOp::reset, DeviceOp::select_tool, DeviceOp::speed, DeviceOp::force, DeviceOp::knife_up,
                DeviceOp::knife_down, DeviceOp::relative, DeviceOp::absolute, DeviceOp::defaults, DeviceOp::no_effect,
                DeviceOp::report_identity, DeviceOp::report_status, DeviceOp::report_position, DeviceOp::unknown,
                DeviceOp::query_free_buffer, DeviceOp::unknown_control, DeviceOp::abort, DeviceOp::handshake_setup}));
  EXPECT_EQ(control, (std::vector<bool>{false, false, false, false, false, false, false, false, false, false, false,
                                        false, false, false, true, true, true, true}));
  EXPECT_TRUE(reader->starts_device_control('\x1b'));
  EXPECT_FALSE(reader->starts_device_control('P'));
}

// A split write holds its bytes as pending, and discard_pending drops them (ESC.K).
TEST(DeviceReader, PendingBytesAndDiscard) {
  HpglReader hpgl;
  DeviceReader& reader = hpgl;
  std::vector<DeviceCommand> out;
  reader.feed("SP1;VS1", out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(reader.pending(), 3u) << "VS1 waits for its terminator";
  reader.discard_pending();
  EXPECT_EQ(reader.pending(), 0u);
  reader.feed("\x1b.", out);
  EXPECT_TRUE(reader.in_device_control());
  reader.feed("O", out);
  EXPECT_FALSE(reader.in_device_control());
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].op, DeviceOp::query_idle);
}

// TomlSection::choice maps names to values through the enum's table, not an index.
TEST(TomlChoice, ReturnsTheNamedValueOrTheFallback) {
  const toml::table t = parse_toml("flow = \"esc_b\"\nkind = \"outline\"\nparity = 1\nmode = \"burn\"\n", "c.toml");
  TomlSection s(&t, "x", "c.toml");
  EXPECT_EQ(s.choice("flow", FlowControl::none, kFlowControlNames), FlowControl::esc_b);
  EXPECT_EQ(s.choice("kind", PlanKind::cut, kPlanKindNames), PlanKind::outline);
  EXPECT_EQ(s.choice("absent", ToolMode::perforate, kToolModeNames), ToolMode::perforate) << "absent: the fallback";
  const Error burn = thrown_by([&] { s.choice("mode", ToolMode::cut, kToolModeNames); }, "mode = burn");
  EXPECT_EQ(burn.location(), "[x] mode");
  EXPECT_EQ(burn.message(), "\"burn\" is not one of \"cut\", \"score\", \"perforate\", \"skip\"");
  const Error number = thrown_by([&] { s.choice("parity", Parity::none, kParityNames); }, "parity = 1");
  EXPECT_EQ(number.location(), "[x] parity");
  EXPECT_EQ(number.message(), "expected one of \"none\", \"odd\", \"even\"");
}

// The choices' messages as they were written before the tables: each lists exactly its names.
TEST(TomlChoice, ProfileChoicesNameTheirAllowedValues) {
  const struct {
    std::string text, location, message;
  } cases[] = {
      {"[hpgl]\nmove_style = \"fancy\"\n", "[hpgl] move_style", "\"fancy\" is not one of \"separate\", \"inline\""},
      {"[hpgl]\ncoordinates = \"polar\"\n", "[hpgl] coordinates", "\"polar\" is not one of \"absolute\", \"relative\""},
      {"[hpgl]\nforce = \"fx\"\n", "[hpgl] force", "\"fx\" is not one of \"none\", \"fs\", \"roland\""},
      {"[transport]\nflow_control = \"smoke\"\n", "[transport] flow_control",
       "\"smoke\" is not one of \"none\", \"xon_xoff\", \"rts_cts\", \"esc_b\", \"dtr_dsr\", \"status\""},
      {"[transport]\nparity = \"mark\"\n", "[transport] parity", "\"mark\" is not one of \"none\", \"odd\", \"even\""},
      {"[transport]\ndrain_query = \"esc_e\"\n", "[transport] drain_query",
       "\"esc_e\" is not one of \"none\", \"esc_b\", \"esc_o\", \"esc_enq\""},
      {"[transport]\nerror_query = \"esc_b\"\n", "[transport] error_query",
       "\"esc_b\" is not one of \"none\", \"esc_e\""},
      {"[tool.cut]\nmode = \"burn\"\n", "[tool.cut] mode",
       "\"burn\" is not one of \"cut\", \"score\", \"perforate\", \"skip\""},
      {"[motors]\n", "[motors]",
       "unknown section (expected device, hpgl, gpgl, transport, kinematics, plan, tool.KIND)"},
      {"[tool.edge]\n", "[tool.edge]", "unknown line kind (expected valley, mountain, cut, outline)"},
      {"[plan]\norder = [\"fold\"]\n", "[plan] order", "\"fold\" is not a line kind (valley, mountain, cut, outline)"},
      {"[plan]\norder = [\"cut\"]\n", "[plan] order", "must list each of valley, mountain, cut, outline once"},
  };
  for (const auto& c : cases) {
    const Error e = refusal(kBase + c.text);
    EXPECT_EQ(e.location(), c.location) << c.text;
    EXPECT_EQ(e.message(), c.message) << c.text;
  }
}

TEST(TomlChoice, ProfileChoicesArriveAsValues) {
  const DeviceProfile p =
      parse_profile(kBase +
                        "[hpgl]\nmove_style = \"inline\"\ncoordinates = \"relative\"\nforce = \"none\"\n"
                        "[transport]\nflow_control = \"esc_b\"\nparity = \"even\"\nerror_query = \"esc_e\"\n"
                        "[tool.valley]\nmode = \"skip\"\n",
                    "v.toml");
  EXPECT_EQ(p.dialect.move_style, MoveStyle::inline_xy);
  EXPECT_EQ(p.dialect.coords, CoordMode::relative);
  EXPECT_EQ(p.dialect.force, ForceStyle::none);
  EXPECT_EQ(p.transport.flow, FlowControl::esc_b);
  EXPECT_EQ(p.transport.parity, Parity::even);
  EXPECT_EQ(p.transport.drain_query, DrainQuery::esc_b) << "esc_b flow control drains with ESC.B by default";
  EXPECT_TRUE(p.transport.error_query);
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::valley)].mode, ToolMode::skip);
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::mountain)].mode, ToolMode::score) << "folds score by default";
  EXPECT_EQ(p.plan.kinds[index_of(PlanKind::cut)].mode, ToolMode::cut);
  const DeviceProfile d = parse_profile(kBase, "d.toml");
  EXPECT_EQ(d.transport.drain_query, DrainQuery::none);
  EXPECT_FALSE(d.transport.error_query);
  EXPECT_EQ(d.dialect.force, ForceStyle::fs);
}

}  // namespace
}  // namespace popcut::drivers
