// HP-GL encoder: exact bytes per dialect, placement and refusal, relative moves from rounded absolutes.
#include <gtest/gtest.h>

#include <cmath>

#include "popcut/error.h"
#include "popcut/hpgl/hpgl.h"

namespace popcut {
namespace {

StrokePlan small_plan() {
  StrokePlan p;
  p.sheet = {{-10, -5}, {10, 5}};
  p.strokes = {{PlanKind::valley, {{-5, 0}, {5, 0}}}, {PlanKind::cut, {{0.02, 1}, {0.04, 2}, {0.07, 3}}}};
  return p;
}

std::array<ToolSetting, 4> tools() {
  std::array<ToolSetting, 4> t{};
  t[index_of(PlanKind::valley)] = {2, 40, 10};
  t[index_of(PlanKind::cut)] = {1, 120, 15};
  return t;
}

HpglDialect area(HpglDialect d) {
  d.area_max_x_pu = 40 * 600;
  d.area_max_y_pu = 40 * 600;
  return d;
}

TEST(Hpgl, SeparateAbsoluteGolden) {
  const std::string got = encode_hpgl(small_plan(), area({}), tools());
  // Sheet min corner (-10, -5) lands at (0, 0); 10.02 mm = 400.8 units rounds to 401.
  EXPECT_EQ(got, "IN;SP2;VS10;FS40;PU;PA200,200;PD;PA600,200;SP1;VS15;FS120;PU;PA401,240;PD;PA402,280,403,320;PU;SP0;")
      << "generic dialect, byte for byte";
}

// Per-pass settings: the encoder re-sends force and speed where a pass's differ, nothing else.
TEST(Hpgl, EachPassIsCutWithItsOwnForceAndSpeed) {
  StrokePlan p;
  p.sheet = {{-10, -5}, {10, 5}};
  p.strokes = {{PlanKind::cut, {{-5, 0}, {5, 0}}, false, 0},
               {PlanKind::cut, {{5, 0}, {-5, 0}}, false, 1},
               {PlanKind::cut, {{-5, 2}, {5, 2}}, false, 0},
               {PlanKind::cut, {{5, 2}, {-5, 2}}, false, 1}};
  std::array<ToolSetting, 4> t{};
  t[index_of(PlanKind::cut)] = {1, 120, 15, {60, 140}, {10, 5}};
  EXPECT_EQ(encode_hpgl(p, area({}), t),
            "IN;SP1;VS10;FS60;PU;PA200,200;PD;PA600,200;VS5;FS140;PU;PA600,200;PD;PA200,200;"
            "VS10;FS60;PU;PA200,280;PD;PA600,280;VS5;FS140;PU;PA600,280;PD;PA200,280;PU;SP0;")
      << "light first pass, full second, for every stroke; the knife lifts to take the new force";
  t[index_of(PlanKind::cut)] = {1, 120, 15, {60, 140}, {}};
  const std::string force_only = encode_hpgl(p, area({}), t);
  EXPECT_EQ(force_only.find("VS", force_only.find("VS15") + 1), std::string::npos)
      << "the speed is sent once: " << force_only;
  // tool_for_stroke: a pass past the lists' end takes the kind's own values.
  const Stroke third{PlanKind::cut, {}, false, 2};
  EXPECT_EQ(tool_for_stroke(t, third), (ToolSetting{1, 120, 15}));
  EXPECT_EQ(tool_for_stroke(t, p.strokes[1]), (ToolSetting{1, 140, 15}));
}

// The cutter-language seam: HP-GL behind JobEncoder writes encode_job's bytes and offsets.
TEST(Hpgl, TheEncoderBehindTheSeamIsEncodeJob) {
  HpglDialect d = area({});
  d.move_style = MoveStyle::inline_xy;
  const HpglEncoder hpgl(d);
  const JobEncoder& encoder = hpgl;
  EXPECT_EQ(encoder.language(), CutterLanguage::hpgl);
  for (std::size_t from : {1u, 2u}) {
    const EncodedJob via = encoder.encode(small_plan(), tools(), from);
    const EncodedJob direct = encode_job(small_plan(), d, tools(), from);
    EXPECT_EQ(via.bytes, direct.bytes) << from;
    EXPECT_EQ(via.stroke_end, direct.stroke_end) << from;
    EXPECT_EQ(via.stroke_cut_start, direct.stroke_cut_start) << from;
    EXPECT_EQ(via.command_end, direct.command_end) << from;
    EXPECT_EQ(via.first_stroke, from);
  }
  EXPECT_NE(encoder.encode(small_plan(), tools(), 1).bytes, encode_hpgl(small_plan(), area({}), tools()))
      << "bound to its dialect";
  EXPECT_THROW(encoder.encode(small_plan(), tools(), 3), Error) << "past the last stroke";
  EXPECT_EQ(kCutterLanguageNames.name(CutterLanguage::hpgl), "hpgl");
}

TEST(Hpgl, InlineRelativeGoldenDerivesDeltasFromRoundedAbsolutes) {
  HpglDialect d = area({});
  d.move_style = MoveStyle::inline_xy;
  d.coords = CoordMode::relative;
  d.force = ForceStyle::roland;
  d.newline = true;
  const std::string got = encode_hpgl(small_plan(), d, tools());
  EXPECT_EQ(got,
            "IN;PR;\nSP2;\nVS10;\n!FS40;\nPA;\nPU200,200;\nPR;\nPD400,0;\nSP1;\nVS15;\n!FS120;\nPU-199,40;\nPD1,40,1,"
            "40;\nPU;SP0;")
      << "inline relative, Roland force, newline padding";
}

TEST(Hpgl, RelativeNeverDrifts) {
  // 1000 steps of 0.0101 mm: rounding each delta would drift by 0.0001 mm per step.
  StrokePlan p;
  p.sheet = {{0, 0}, {100, 100}};
  Stroke s{PlanKind::cut, {}};
  for (int i = 0; i <= 1000; ++i) s.points.push_back({i * 0.0101, 1});
  p.strokes = {s};
  HpglDialect d = area({});
  d.coords = CoordMode::relative;
  const auto abs = plan_in_plotter_units(p, d);
  ASSERT_EQ(abs.size(), 1u);
  EXPECT_EQ(abs[0].back()[0], std::llround(1000 * 0.0101 * 40)) << "the last point is the rounded absolute";
  // Sum the relative PD deltas from the text.
  const std::string job = encode_hpgl(p, d, tools());
  long sum_x = 0;
  std::size_t at = job.find("PD;PR");
  ASSERT_NE(at, std::string::npos) << job.substr(0, 200);
  const std::string first_abs = "PA0,40;";
  ASSERT_NE(job.find(first_abs), std::string::npos) << "first move is absolute: " << job.substr(0, 80);
  while ((at = job.find("PR", at)) != std::string::npos) {
    at += 2;
    const std::size_t end = job.find(';', at);
    std::string body = job.substr(at, end - at);
    std::size_t k = 0;
    bool x = true;
    while (k < body.size()) {
      const std::size_t c = body.find(',', k);
      const std::string num = body.substr(k, c == std::string::npos ? std::string::npos : c - k);
      if (x) sum_x += std::stol(num);
      x = !x;
      k = c == std::string::npos ? body.size() : c + 1;
    }
  }
  EXPECT_EQ(sum_x, abs[0].back()[0]) << "relative deltas add up exactly to the rounded absolute end";
}

TEST(Hpgl, FlipAndSwapStayInsideTheArea) {
  HpglDialect d = area({});
  d.swap_axes = true;
  d.flip_x = true;
  const StrokePlan p = small_plan();
  const Placement pl = place_sheet(p.sheet, d);
  const auto corner = to_plotter(p.sheet.max, p.sheet, pl, d);
  EXPECT_EQ(corner[0], d.area_max_x_pu - 400) << "swapped: plotter x runs along v (10 mm), flipped from the max edge";
  EXPECT_EQ(corner[1], 800) << "plotter y runs along x (20 mm)";
  for (const auto& path : plan_in_plotter_units(p, d)) {
    for (const auto& q : path) {
      EXPECT_TRUE(q[0] >= d.area_min_x_pu && q[0] <= d.area_max_x_pu && q[1] >= d.area_min_y_pu &&
                  q[1] <= d.area_max_y_pu)
          << "point " << q[0] << "," << q[1] << " inside the usable area";
    }
  }
}

TEST(Hpgl, RefusesASheetLargerThanTheArea) {
  HpglDialect d;
  d.area_max_x_pu = 40 * 15;  // 15 mm: the 20 mm sheet does not fit
  d.area_max_y_pu = 40 * 600;
  try {
    encode_hpgl(small_plan(), d, tools());
    FAIL() << "a sheet wider than the usable area must be refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input) << "bad input, not a crash";
    EXPECT_NE(e.message().find("does not fit"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("20.0 x 10.0 mm"), std::string::npos) << "names the sheet size: " << e.message();
  }
}

TEST(Hpgl, LongStrokesAreSplitIntoCommandsOfBoundedLength) {
  StrokePlan p;
  p.sheet = {{0, 0}, {100, 100}};
  Stroke s{PlanKind::cut, {}};
  for (int i = 0; i < 10; ++i) s.points.push_back({double(i), double(i % 2)});
  p.strokes = {s};
  HpglDialect d = area({});
  d.max_pairs_per_command = 4;
  const std::string job = encode_hpgl(p, d, tools());
  EXPECT_NE(job.find("PD;PA40,40,80,0,120,40,160,0;PA200,40,240,0,280,40,320,0;PA360,40;"), std::string::npos)
      << "9 pairs in commands of at most 4: " << job;
}

TEST(Hpgl, StrokesBelowResolutionAreReportedNotCounted) {
  StrokePlan p = small_plan();
  p.home = p.sheet.min;
  p.strokes.insert(p.strokes.begin() + 1, {PlanKind::cut, {{1, 1}, {1.004, 1}}});  // 0.16 units long
  for (const Stroke& s : p.strokes) {
    KindStats& k = p.kinds[index_of(s.kind)];
    ++k.strokes, ++k.pen_lifts, k.cut_mm += path_length_mm(s.points);
  }
  const HpglDialect d = area({});
  const StrokePlan sent = drop_below_resolution(p, d);
  const KindStats& cut = sent.kinds[index_of(PlanKind::cut)];
  EXPECT_EQ(cut.strokes_below_resolution, 1) << "the 0.004 mm stroke rounds to one point";
  EXPECT_EQ(cut.strokes, 1) << "only the stroke that is sent counts";
  EXPECT_EQ(cut.pen_lifts, 1) << "and only its lift";
  EXPECT_NEAR(cut.cut_mm, path_length_mm(p.strokes[2].points), 1e-12) << "cut length without the dropped stroke";
  EXPECT_EQ(sent.total().strokes_below_resolution, 1) << "the total reports it too";
  EXPECT_EQ(sent.kinds[index_of(PlanKind::valley)].strokes, 1) << "other kinds untouched";
  EXPECT_NEAR(sent.total().travel_mm, travel_mm({p.strokes[0].points, p.strokes[2].points}, p.home), 1e-12)
      << "travel goes straight to the next stroke that is sent";
  EXPECT_EQ(encode_hpgl(sent, d, tools()), encode_hpgl(p, d, tools())) << "the same bytes either way";
  std::size_t pen_downs = 0;
  for (std::size_t at = 0; (at = encode_hpgl(sent, d, tools()).find("PD", at)) != std::string::npos; ++at) ++pen_downs;
  EXPECT_EQ(pen_downs, static_cast<std::size_t>(sent.total().strokes)) << "one PD per stroke counted";
}

}  // namespace
}  // namespace popcut
