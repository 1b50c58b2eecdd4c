// popcut.voxel.v1 reader: the documented example, every class of bad input, and fuzzing.
#include "popcut/io/voxel_json.h"

#include <gtest/gtest.h>

#include <random>

#include "popcut/error.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
namespace {

const char* kIssueExample = R"({"format": "popcut.voxel.v1", "voxel_mm": 2.0,
 "heights": [[3, 3, 1], [4, 2], []],
 "windows": [[1, 0], [1, 1]],
 "sheet": {"back": 12, "floor": 12, "side": 2}})";

TEST(VoxelJson, ReadsTheDocumentedExample) {
  const VoxelModel m = parse_voxel_model(kIssueExample, "example.json");
  EXPECT_EQ(m.width, 3) << "three columns";
  EXPECT_EQ(m.depth, 3) << "longest column list";
  EXPECT_EQ(m.height, 4) << "tallest column";
  EXPECT_EQ(m.h(1, 0), 4) << "heights[1][0]";
  EXPECT_EQ(m.h(1, 2), 0) << "missing entries are 0";
  EXPECT_TRUE(m.is_window(1, 0) && m.is_window(1, 1)) << "both windows";
  EXPECT_EQ(m.window_count(), 2) << "and no others";
  EXPECT_EQ(m.sheet.back, 12) << "sheet.back";
  const Pattern p = make_pattern(m);
  // x in mm = (voxel x + side) × voxel_mm; v in mm = (z − y) × voxel_mm.
  EXPECT_EQ(p.sheet, (Rect{{0, -24}, {14, 24}})) << "sheet from (3 + 2·2) columns × 2 mm and 12 voxels per half";
}

TEST(VoxelJson, WriterRoundTrips) {
  VoxelModel m = parse_voxel_model(kIssueExample, "example.json");
  m.name = "house \"A\"";
  EXPECT_EQ(parse_voxel_model(to_voxel_json(m), "rt.json"), m) << "every field survives write + read";
}

struct BadCase {
  const char* name;
  const char* text;
  const char* location;  // expected Error::location()
  const char* fragment;  // expected somewhere in the message
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

class BadVoxelInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadVoxelInput, IsRejectedWithAPreciseMessage) {
  const BadCase& c = GetParam();
  try {
    parse_voxel_model(c.text, "bad.json");
    FAIL() << c.name << ": should be rejected";
  } catch (const Error& e) {
    EXPECT_EQ(e.source(), "bad.json") << c.name << ": the file is named: " << e.what();
    EXPECT_EQ(e.location(), c.location) << c.name << ": the field or position is named: " << e.what();
    EXPECT_NE(e.message().find(c.fragment), std::string::npos)
        << c.name << ": message says what is wrong: " << e.what();
  }
}

#define HEAD R"("format": "popcut.voxel.v1", "voxel_mm": 1, )"
INSTANTIATE_TEST_SUITE_P(
    Cases, BadVoxelInput,
    ::testing::Values(
        BadCase{"empty", "", "line 1, column 1", "malformed JSON"},
        BadCase{"truncated", "{\"format\": \"popcut.voxel.v1\",\n \"voxel_mm\": 1,\n \"heights\": [[1, 2",
                "line 3, column 19", "malformed JSON"},
        BadCase{"not an object", "[1, 2]", "document", "expected an object"},
        BadCase{"wrong format", R"({"format": "popcut.faces.v1", "voxel_mm": 1, "heights": [[1]]})", "format",
                "expected \"popcut.voxel.v1\""},
        BadCase{"other format with other fields", R"({"format": "popcut.faces.v1", "faces": []})", "format",
                "got \"popcut.faces.v1\""},
        BadCase{"missing format", R"({"voxel_mm": 1, "heights": [[1]]})", "format", "is missing"},
        BadCase{"unknown field", "{" HEAD R"("heights": [[1]], "colour": "red"})", "colour", "unknown field"},
        BadCase{"duplicate key", "{" HEAD R"("heights": [[1]], "heights": [[2]]})", "", "duplicate key \"heights\""},
        BadCase{"negative height", "{" HEAD R"("heights": [[1, 2], [-3]]})", "heights[1][0]", "got -3"},
        BadCase{"fractional height", "{" HEAD R"("heights": [[1.5]]})", "heights[0][0]", "whole number"},
        BadCase{"string height", "{" HEAD R"("heights": [["2"]]})", "heights[0][0]", "got a string"},
        BadCase{"huge height", "{" HEAD R"("heights": [[99999999999999999999]]})", "heights[0][0]", "4096"},
        BadCase{"staircase", "{" HEAD R"("heights": [[3, 3], [2, 4]]})", "heights[1][1]", "staircase"},
        BadCase{"window outside", "{" HEAD R"("heights": [[3]], "windows": [[1, 0]]})", "windows[0]",
                "outside the grid"},
        BadCase{"window not a pair", "{" HEAD R"("heights": [[3]], "windows": [[0]]})", "windows[0]",
                "expected [x, z]"},
        BadCase{"window repeated", "{" HEAD R"("heights": [[3]], "windows": [[0, 1], [0, 1]]})", "windows[1]",
                "repeats"},
        BadCase{"window above column", "{" HEAD R"("heights": [[3], [1]], "windows": [[1, 2]]})", "windows",
                "no front face"},
        BadCase{"sheet too small", "{" HEAD R"("heights": [[3, 3]], "sheet": {"floor": 4}})", "sheet.floor",
                "at least 5 voxels"},
        BadCase{"sheet unknown key", "{" HEAD R"("heights": [[3]], "sheet": {"top": 4}})", "sheet.top",
                "unknown field"},
        BadCase{"sheet negative side", "{" HEAD R"("heights": [[3]], "sheet": {"side": -1}})", "sheet.side", "from 0"},
        BadCase{"number overflow", R"({"format": "popcut.voxel.v1", "voxel_mm": 1e400, "heights": [[1]]})",
                "line 1, column 43", "overflow"},
        BadCase{"voxel_mm zero", R"({"format": "popcut.voxel.v1", "voxel_mm": 0, "heights": [[1]]})", "voxel_mm",
                "from 0.01"},
        BadCase{"voxel_mm string", R"({"format": "popcut.voxel.v1", "voxel_mm": "2", "heights": [[1]]})", "voxel_mm",
                "got a string"},
        BadCase{"no columns", "{" HEAD R"("heights": []})", "heights", "at least one column"},
        BadCase{"heights and voxels", "{" HEAD R"("heights": [[1]], "voxels": [[0,0,0]]})", "heights", "exactly one"},
        BadCase{"voxel gap", "{" HEAD R"("voxels": [[0,0,0],[0,0,2]]})", "voxels", "empty under a filled voxel"},
        BadCase{"voxel repeated", "{" HEAD R"("voxels": [[0,0,0],[0,0,0]]})", "voxels[1]", "repeats voxels[0]"},
        BadCase{"grid too small", "{" HEAD R"("heights": [[3]], "grid": {"width": 1, "depth": 1, "height": 2}})",
                "grid", "needs at least"},
        BadCase{"grid too wide", "{" HEAD R"("heights": [[0]], "grid": {"width": 5000, "depth": 1, "height": 1}})",
                "grid.width", "4096"},
        BadCase{"deep nesting",
                "[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]]]"
                "]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]",
                "", "nested deeper"},
        BadCase{"bad utf8", "{\"format\": \"popcut.voxel.v1\xff\"}", "line 1, column 28", "malformed JSON"}),
    [](const ::testing::TestParamInfo<BadCase>& param) {
      std::string n = param.param.name;
      for (char& ch : n) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
      return n;
    });
#undef HEAD

TEST(VoxelJson, TooManyColumns) {
  std::string text = R"({"format": "popcut.voxel.v1", "voxel_mm": 1, "heights": [)";
  for (int x = 0; x < 4097; ++x) text += x ? ",[]" : "[]";
  try {
    parse_voxel_model(text + "]}", "wide.json");
    FAIL() << "4097 columns is over the documented limit";
  } catch (const Error& e) {
    EXPECT_EQ(e.location(), "heights") << e.what();
    EXPECT_NE(e.message().find("limit is 4096"), std::string::npos) << e.what();
  }
}

TEST(VoxelJson, LargestColumnGetsACappedDefaultSheet) {
  // y + h + 1 reaches 4095 + 4096 + 1 = 8192, the sheet limit: the default margin must not push
  // the sheet past it and then blame a field the user never wrote.
  std::string text = R"({"format": "popcut.voxel.v1", "voxel_mm": 1, "heights": [[)";
  for (int y = 0; y < 4096; ++y) text += y ? ",4096" : "4096";
  const VoxelModel m = parse_voxel_model(text + "]]}", "deep.json");
  EXPECT_EQ(resolve_sheet(m, "deep.json").back, kMaxSheetVoxels) << "the default is capped at the limit";
}

// Truncations and random mutations of a valid file must fail cleanly or parse: never crash or hang.
TEST(VoxelJson, FuzzedInputNeverCrashes) {
  const std::string good = to_voxel_json(parse_voxel_model(kIssueExample, "example.json"));
  int rejected = 0, accepted = 0;
  const auto attempt = [&](const std::string& text) {
    try {
      const VoxelModel m = parse_voxel_model(text, "fuzz.json");
      make_pattern(m);
      ++accepted;
    } catch (const Error& e) {
      EXPECT_NE(e.code(), ErrorCode::internal) << "fuzzed input is the user's error, never a bug: " << e.what();
      ++rejected;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "only popcut::Error may escape the reader, got: " << e.what() << "\ninput: " << text;
    }
  };
  for (std::size_t n = 0; n < good.size(); ++n) attempt(good.substr(0, n));
  std::mt19937_64 rng(3);
  for (int i = 0; i < 3000; ++i) {
    std::string t = good;
    for (int k = 0, edits = 1 + static_cast<int>(rng() % 4); k < edits; ++k) {
      const std::size_t at = rng() % t.size();
      switch (rng() % 3) {
        case 0: t[at] = static_cast<char>(rng() % 256); break;
        case 1: t.erase(at, 1); break;
        default: t.insert(at, 1, "0123456789[]{},:-.\"e"[rng() % 20]); break;
      }
    }
    attempt(t);
  }
  for (int i = 0; i < 500; ++i) {
    std::string t(rng() % 200, '\0');
    for (char& ch : t) ch = static_cast<char>(rng() % 256);
    attempt(t);
  }
  EXPECT_GT(rejected, 0) << "mutations must be caught";
  EXPECT_GT(accepted, 0) << "some mutations (e.g. a changed digit) are still valid models";
}

TEST(VoxelJson, DroppedTopsReadWriteAndAreChecked) {
  const VoxelModel m = parse_voxel_model(
      R"({"format": "popcut.voxel.v1", "voxel_mm": 1, "heights": [[3, 3], [2]], "dropped_tops": [[1, 2]]})",
      "tops.json");
  EXPECT_TRUE(m.is_top_dropped(1, 2)) << "the top of slice 1 at z = 2 is dropped";
  EXPECT_EQ(parse_voxel_model(to_voxel_json(m), "rt"), m) << "round trip";
  try {
    parse_voxel_model(
        R"({"format": "popcut.voxel.v1", "voxel_mm": 1, "heights": [[3, 3], [2]], "dropped_tops": [[0, 2]]})",
        "t.json");
    ADD_FAILURE() << "slice 0 has no top at z = 2";
  } catch (const Error& e) {
    EXPECT_EQ(e.location(), "dropped_tops") << e.message();
    EXPECT_NE(e.message().find("no column exactly 2 high"), std::string::npos) << e.message();
  }
  EXPECT_THROW(
      parse_voxel_model(R"({"format": "popcut.voxel.v1", "voxel_mm": 1, "heights": [[3]], "dropped_tops": [[0, 0]]})",
                        "t.json"),
      Error)
      << "z starts at 1 (a top face sits on a column)";
}

}  // namespace
}  // namespace popcut
