// The GP-GL device side on sequences other programs send (inkscape-silhouette's Commands.md, Silhouette Studio
// captures, gerber2graphtec, SilhouetteTest), and the simulator executing and answering them.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "popcut/drivers/gpgl_reader.h"
#include "popcut/drivers/profile.h"
#include "popcut/drivers/sim_cutter.h"

namespace popcut::drivers {
namespace {

// Sequences below write ETX as |, ESC as ~, EOT as ^ and ENQ as ` (a hex escape would swallow
// the command letter after it).
std::string gp(std::string s) {
  for (char& c : s) c = c == '|' ? '\x03' : c == '~' ? '\x1b' : c == '^' ? '\x04' : c == '`' ? '\x05' : c;
  return s;
}

std::vector<DeviceCommand> parse(const std::string& text) { return parse_gpgl(gp(text)); }

std::vector<DeviceOp> ops_of(const std::vector<DeviceCommand>& cmds) {
  std::vector<DeviceOp> ops;
  for (const DeviceCommand& c : cmds) ops.push_back(c.op);
  return ops;
}

std::vector<std::string> names_of(const std::vector<DeviceCommand>& cmds) {
  std::vector<std::string> names;
  for (const DeviceCommand& c : cmds) names.push_back(c.name);
  return names;
}

// Commands.md, "Typical sequence" (after robocut and Graphtec.py's setup()).
const std::string kTypical =
    "~^~`TT|"
    "FG|"
    "FW132|!10|FX5|"
    "FC18|"
    "FY0|"
    "FN0|"
    "FE0|"
    "TB71|"
    "FA|"
    "FU5440,4070|"
    "FM1|"
    "TB50,1|"
    "FO5440|";

TEST(GpglReader, ReadsTheTypicalSequenceOfCommandsMd) {
  const std::vector<DeviceCommand> cmds = parse(kTypical);
  EXPECT_EQ(names_of(cmds), (std::vector<std::string>{"ESC EOT", "ESC ENQ", "TT", "FG", "FW", "!", "FX", "FC", "FY",
                                                      "FN", "FE", "TB", "FA", "FU", "FM", "TB", "FO"}));
  EXPECT_EQ(ops_of(cmds),
            (std::vector<DeviceOp>{DeviceOp::initialize, DeviceOp::query_state, DeviceOp::home,
                                   DeviceOp::report_version, DeviceOp::no_effect, DeviceOp::speed, DeviceOp::force,
                                   DeviceOp::no_effect, DeviceOp::no_effect, DeviceOp::no_effect, DeviceOp::no_effect,
                                   DeviceOp::report_calibration, DeviceOp::report_calibration, DeviceOp::no_effect,
                                   DeviceOp::no_effect, DeviceOp::no_effect, DeviceOp::unknown}))
      << "FO (feed) moves the media, which the simulator does not model: unknown, reported";
  EXPECT_TRUE(cmds[0].device_control && cmds[1].device_control);
  EXPECT_FALSE(cmds[2].device_control);
  EXPECT_EQ(cmds[13].params, (std::vector<double>{5440, 4070}));
  for (const DeviceCommand& c : cmds) EXPECT_FALSE(c.malformed) << c.name;
  // Offsets count the buffered bytes only: TT starts the buffer.
  EXPECT_EQ(cmds[2].offset, 0u);
  EXPECT_EQ(cmds[2].length, 3u) << "TT and its ETX";
  EXPECT_EQ(cmds[3].offset, 3u);
}

// Commands.md, "New Commands": Silhouette Studio 3.3 drawing a triangle, decimals in M and D.
TEST(GpglReader, TakesSilhouetteStudiosDecimalCoordinates) {
  const std::vector<DeviceCommand> cmds = parse(
      "FN0|TB50,0|\\30,30|FX1|!8|FC18|FE0,0|FF0,0,0|M175.24,577.08|"
      "D157.96,587.14|D678.70,884.62|D675.96,284.92|D157.96,587.14|D175.32,597.06|");
  ASSERT_EQ(cmds.size(), 14u);
  EXPECT_EQ(cmds[2].name, "\\");
  EXPECT_EQ(cmds[2].op, DeviceOp::no_effect);
  EXPECT_EQ(cmds[8].op, DeviceOp::knife_up);
  EXPECT_EQ(cmds[8].params, (std::vector<double>{175.24, 577.08}));
  EXPECT_EQ(cmds[9].op, DeviceOp::knife_down);
  for (const DeviceCommand& c : cmds) EXPECT_FALSE(c.malformed) << c.name;
}

// gerber2graphtec's start and end: commas end parameters and the next name ends the command.
TEST(GpglReader, SplitsGerber2graphtecsUnterminatedCommands) {
  const std::vector<DeviceCommand> cmds = parse(
      "FX10,0|&100,100,100,\\0,0,Z6096,5588,L0,M2032.000,254.000|D2100.500,254.000|"
      "&1,1,1,TB50,0|FO0|H,");
  EXPECT_EQ(names_of(cmds), (std::vector<std::string>{"FX", "&", "\\", "Z", "L", "M", "D", "&", "TB", "FO", "H"}));
  EXPECT_EQ(cmds[0].params, (std::vector<double>{10, 0}));
  EXPECT_EQ(cmds[1].params, (std::vector<double>{100, 100, 100}));
  EXPECT_EQ(cmds[3].params, (std::vector<double>{6096, 5588}));
  EXPECT_EQ(cmds[5].params, (std::vector<double>{2032, 254}));
  EXPECT_EQ(cmds[10].op, DeviceOp::home);
  EXPECT_TRUE(cmds[10].params.empty()) << "H, has no parameters";
  for (const DeviceCommand& c : cmds) EXPECT_FALSE(c.malformed) << c.name;
}

// Commands.md, "Cameo 4 Pro": the holder in J, FX, !, FC; BE (binary encoded draw) is unknown.
TEST(GpglReader, ReadsTheCameo4ProCapture) {
  const std::vector<DeviceCommand> cmds = parse(
      "TG9|J1|FX15,1|TJ0|!10,1|FC0,1,1|FE0,1|FF1,0,1|FF1,1,1|FX15,1|TJ3|"
      "FC18,1,1|M301,356|BE2|L0|\\0,0|M0,0|J0|~\x15"
      "");
  EXPECT_EQ(cmds[1].op, DeviceOp::select_tool);
  EXPECT_EQ(cmds[2].params, (std::vector<double>{15, 1}));
  EXPECT_EQ(cmds[13].name, "BE");
  EXPECT_EQ(cmds[13].op, DeviceOp::unknown);
  EXPECT_EQ(cmds.back().name, "ESC 0x15") << "the tool-setup query";
  EXPECT_EQ(cmds.back().op, DeviceOp::unknown_control);
}

TEST(GpglReader, DeviceControlBypassesACommandSplitAcrossWrites) {
  GpglReader r;
  std::vector<DeviceCommand> out;
  r.feed(gp("D100,2"), out);
  EXPECT_TRUE(out.empty()) << "D waits for its ETX";
  EXPECT_EQ(r.pending(), 6u);
  r.feed(gp("00,~"), out);
  EXPECT_TRUE(r.in_device_control());
  EXPECT_EQ(r.feed_to_control(gp("`300,400|"), out), 1u) << "stops after the device control";
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].op, DeviceOp::query_state);
  EXPECT_TRUE(out[0].device_control);
  EXPECT_EQ(r.pending(), 9u) << "the ESC ENQ is not in the buffer";
  r.feed(gp("300,400|"), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].op, DeviceOp::knife_down);
  EXPECT_EQ(out[1].params, (std::vector<double>{100, 200, 300, 400})) << "the query taken out, the command whole";
  EXPECT_EQ(out[1].length, 17u);
  EXPECT_EQ(r.pending(), 0u);
  // ESC NUL takes one more byte (Silhouette Studio's key presses).
  r.feed(std::string("\x1b\0", 2), out);
  EXPECT_TRUE(r.in_device_control());
  r.feed(gp("\x01"), out);
  EXPECT_EQ(out.back().name, "ESC 0x00");
  EXPECT_EQ(out.back().length, 3u);
}

TEST(GpglReader, MalformedParametersAreFlaggedNotFatal) {
  const std::vector<DeviceCommand> cmds = parse("FXten|M10,,20|D1,2|Mx|\x1b");
  ASSERT_EQ(cmds.size(), 5u);
  EXPECT_TRUE(cmds[0].malformed) << "FXten";
  EXPECT_TRUE(cmds[1].malformed) << "an empty parameter between commas";
  EXPECT_FALSE(cmds[2].malformed);
  EXPECT_TRUE(cmds[3].malformed) << "Mx";
  EXPECT_TRUE(cmds[4].device_control && cmds[4].malformed) << "a lone ESC at the end";
}

TEST(GpglReader, SeparatorsCountInTheBufferAndDiscardDropsThePending) {
  GpglReader r;
  std::vector<DeviceCommand> out;
  r.feed(gp("\r\n  M1,2|M3"), out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].offset, 4u);
  EXPECT_EQ(out[0].buffer_bytes, 9u) << "the blank lines before it were stored too";
  EXPECT_EQ(r.pending(), 2u);
  r.discard_pending();
  EXPECT_EQ(r.pending(), 0u);
  r.feed(gp("M5,6|"), out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].params, (std::vector<double>{5, 6})) << "nothing of the dropped M3 is left";
}

DeviceProfile cameo() {
  return load_profile(std::string(POPCUT_SOURCE_DIR) + "/configs/devices/silhouette-cameo4.toml");
}

std::string replies(SimCutter& c, double wait_s = 0.01) {
  std::string s;
  std::uint8_t buf[64];
  for (;;) {
    const IoResult r = c.reply(buf, sizeof buf, wait_s);
    if (r.bytes == 0) break;
    s.append(reinterpret_cast<const char*>(buf), r.bytes);
  }
  for (char& ch : s) ch = ch == '\x03' ? '|' : ch;
  return s;
}

void send(SimCutter& c, const std::string& text) {
  const std::string bytes = gp(text);
  ASSERT_EQ(c.receive(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), 1).bytes, bytes.size());
}

// ESC ENQ is answered at once with the GP-GL state; FG and TB71 once executed, each ending in ETX.
TEST(GpglSim, AnswersStatusVersionAndCalibrationInGpgl) {
  SimCutter c(cameo());
  send(c, "~^~`");
  EXPECT_EQ(replies(c), "0|") << "ready: nothing buffered, not moving";
  send(c, "J1|!1,1|M0,0|D4000,0,4000,4000|~`");
  EXPECT_EQ(replies(c, 0), "1|") << "moving: a 200 mm cut at 1 cm/s is under way";
  ASSERT_TRUE(c.run_to_end());
  send(c, "~`");
  EXPECT_EQ(replies(c), "0|");
  send(c, "FG|TB71|");
  ASSERT_TRUE(c.run_to_end());
  EXPECT_EQ(replies(c), "POPCUT-SIM V1.00|    0,    0|");
  ASSERT_EQ(c.strokes().size(), 1u);
  EXPECT_EQ(c.strokes()[0].points_pu, (PlotterPath{{0, 0}, {4000, 0}, {4000, 4000}}));
  EXPECT_EQ(c.strokes()[0].pen, 1);
  EXPECT_TRUE(c.report().unknown.empty());
}

TEST(GpglSim, TrayEmptyAndPausedHaltTheCutAndSaySo) {
  SimCutter c(cameo());
  c.set_media_loaded(false);
  send(c, "~^J1|M0,0|D100,0|~`");
  EXPECT_EQ(replies(c), "2|") << "no media";
  EXPECT_FALSE(c.run_to_end()) << "nothing runs without media";
  EXPECT_TRUE(c.strokes().empty());
  c.set_media_loaded(true);
  c.set_paused(true);
  send(c, "~`");
  EXPECT_EQ(replies(c), "3|") << "paused at the panel";
  c.set_paused(false);
  ASSERT_TRUE(c.run_to_end());
  EXPECT_EQ(c.strokes().size(), 1u) << "and it cuts once resumed";
}

// Per-holder force and speed (FXn,t / !n,t) apply when that holder is selected; H goes home.
TEST(GpglSim, HoldersKeepTheirOwnForceAndSpeed) {
  SimCutter c(cameo());
  send(c, "~^J1|FX10,1|!5,1|FX20,2|!3,2|M0,0|D10,0|J2|M0,10|D10,10|H|");
  ASSERT_TRUE(c.run_to_end());
  ASSERT_EQ(c.strokes().size(), 2u);
  EXPECT_EQ(c.strokes()[0].pen, 1);
  EXPECT_EQ(c.strokes()[0].force, 10);
  EXPECT_EQ(c.strokes()[0].speed_cm_s, 5);
  EXPECT_EQ(c.strokes()[1].pen, 2);
  EXPECT_EQ(c.strokes()[1].force, 20);
  EXPECT_EQ(c.strokes()[1].speed_cm_s, 3);
  EXPECT_FALSE(c.knife_down());
}

// ESC EOT drops what is buffered, like a reset, and unknown commands are reported, not fatal.
TEST(GpglSim, InitialiseDropsTheBufferAndUnknownsAreReported) {
  SimCutter c(cameo());
  send(c, "SO0|M0,0|D5,5,7|");
  ASSERT_TRUE(c.run_to_end());
  ASSERT_EQ(c.report().unknown.size(), 1u);
  EXPECT_EQ(c.report().unknown[0].command, "SO");
  ASSERT_EQ(c.report().errors.size(), 1u);
  EXPECT_EQ(c.report().errors[0].message, "odd number of coordinates");
  SimCutter slow(cameo());
  send(slow, "J1|!1,1|M0,0|D4000,0|D0,0|D4000,0|");
  send(slow, "~^");
  ASSERT_TRUE(slow.run_to_end());
  EXPECT_GT(slow.report().discarded_bytes, 0u);
  EXPECT_LE(slow.strokes().size(), 1u) << "the queued strokes are gone";
}

}  // namespace
}  // namespace popcut::drivers
