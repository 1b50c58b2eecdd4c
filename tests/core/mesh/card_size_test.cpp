// Tests of sizing an imported card in mm: --height-mm, --fit-mm (a box or a device's media), their conflicts and media
// warnings.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "popcut/error.h"
#include "popcut/mesh/import_request.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "test_meshes.h"

namespace popcut {
namespace {

using Values = std::vector<std::pair<std::string, std::string>>;

// A tall, narrow tower (1 wide : 5 high), the shape that gives a sheet far taller than wide.
TriangleSoup tall_tower() {
  TriangleSoup s;
  testing::add_box(s, 0, 0, 0, 20, 10, 100);
  testing::add_box(s, 4, -4, 0, 16, 0, 60);
  return s;
}

struct Card {
  double width_mm, flat_mm, closed_mm, back_mm;
  Pattern pattern;
};

Card card_of(const Values& values, const std::vector<NamedMedia>& media = {}) {
  const ImportRequest r = parse_import_options(values, "tower.obj", media);
  const ImportResult imported = import_mesh(tall_tower(), r.options, "tower.obj");
  const Pattern p = make_pattern(imported.model, "tower.obj");
  EXPECT_TRUE(check_popup(p).pops_up()) << "the sized card still pops up";
  const Rect& s = p.sheet;
  return {s.max.x_mm - s.min.x_mm, s.max.v_mm - s.min.v_mm, std::max(s.max.v_mm, -s.min.v_mm), s.max.v_mm, p};
}

std::string error_of(const Values& values, const std::vector<NamedMedia>& media = {}) {
  try {
    const ImportRequest r = parse_import_options(values, "tower.obj", media);
    import_mesh(tall_tower(), r.options, "tower.obj");
  } catch (const Error& e) {
    return e.location() + ": " + e.message();
  }
  return "no error";
}

TEST(CardSize, HeightMmIsTheStandingCardsHeight) {
  const Card plain = card_of({{"resolution", "20"}});
  EXPECT_NEAR(plain.width_mm, 120.0 * 24 / 20, 1e-9) << "by default 120 mm across the model, plus the sides";
  EXPECT_GT(plain.flat_mm, 4 * plain.width_mm) << "a tall mesh makes a sheet far taller than wide: " << plain.flat_mm;
  const Card c = card_of({{"resolution", "20"}, {"height-mm", "80"}});
  EXPECT_NEAR(c.back_mm, 80, 1e-3) << "the back board (standing height) is 80 mm";
  EXPECT_LE(c.back_mm, 80) << "never over";
  EXPECT_NEAR(c.closed_mm, 80, 1e-3) << "and so is the closed card";
  EXPECT_NEAR(c.width_mm / c.flat_mm, plain.width_mm / plain.flat_mm, 1e-9) << "only the scale changes";
}

TEST(CardSize, FitMmHoldsTheClosedCardInTheBox) {
  for (const char* box : {"100x60", "100×60", "100 X 60", " 100 x 60 "}) {
    const Card c = card_of({{"resolution", "20"}, {"fit-mm", box}});
    EXPECT_LE(c.width_mm, 100) << box;
    EXPECT_LE(c.closed_mm, 60) << box << ": the folded card's outline fits";
    EXPECT_NEAR(c.closed_mm, 60, 1e-3) << box << ": as large as the box lets it (height binds for a tall tower)";
  }
  const Card wide = card_of({{"resolution", "20"}, {"fit-mm", "30x1000"}});
  EXPECT_NEAR(wide.width_mm, 30, 1e-3) << "the width binds in a narrow box";
  EXPECT_LE(wide.width_mm, 30);
}

TEST(CardSize, FitMmOnADeviceHoldsTheFlatSheetInItsMedia) {
  const std::vector<NamedMedia> media = {{"cutter", 300, 200}};
  const Card c = card_of({{"resolution", "20"}, {"fit-mm", "cutter"}}, media);
  EXPECT_LE(c.flat_mm, 200) << "the whole flat sheet is what the device cuts";
  EXPECT_NEAR(c.flat_mm, 200, 1e-3) << "and it is as large as the media allow";
  EXPECT_LE(c.width_mm, 300);
}

TEST(CardSize, SizesAreExclusiveAndChecked) {
  EXPECT_EQ(error_of({{"width-mm", "100"}, {"height-mm", "50"}}),
            "--height-mm: give one of --width-mm, --voxel-mm, --height-mm and --fit-mm (each sets the card's size), "
            "not both --width-mm and --height-mm");
  EXPECT_NE(error_of({{"voxel-mm", "1"}, {"fit-mm", "100x50"}}).find("--fit-mm: give one of"), std::string::npos);
  EXPECT_NE(error_of({{"height-mm", "100"}, {"fit-mm", "100x50"}}).find("not both --height-mm and --fit-mm"),
            std::string::npos);
  EXPECT_EQ(error_of({{"height-mm", "0"}}), "--height-mm: the card's height must be a positive number of mm, not 0");
  EXPECT_EQ(error_of({{"height-mm", "tall"}}), "--height-mm: 'tall' is not a number");
  EXPECT_EQ(error_of({{"fit-mm", "100x-5"}}),
            "--fit-mm: the box must be a positive number of mm each way, not 100 x -5");
  EXPECT_EQ(error_of({{"fit-mm", "100x"}}, {{"sim", 599, 999}, {"roll", 500, 20000}}),
            "--fit-mm: '100x' is neither WxH in mm (e.g. 148x105, or 148×105) nor a device (sim, roll)");
  EXPECT_NE(error_of({{"fit-mm", "a4"}}).find("nor a device (none is configured)"), std::string::npos);
  EXPECT_NE(
      error_of({{"resolution", "20"}, {"height-mm", "0.05"}}).find("--height-mm: a card 0.05 mm high needs voxels of"),
      std::string::npos)
      << "a size the voxels cannot take names the option";
}

TEST(CardSize, MediaWarningsNameTheDeviceAndBothSizes) {
  const Rect sheet{{0, -303}, {126, 303}};
  const std::vector<std::string> w = media_warnings(sheet, {{"flatbed", 600, 1000}, {"narrow", 50000, 584}});
  ASSERT_EQ(w.size(), 1u) << "only the device the sheet does not fit";
  EXPECT_EQ(w[0],
            "the sheet (126 x 606 mm) does not fit narrow (at most 50000 x 584 mm): use --fit-mm narrow or a smaller "
            "--height-mm");
  EXPECT_TRUE(media_warnings(sheet, {{"flatbed", 600, 1000}}).empty());
}

// Debian's CGAL data (libcgal-demo) has a standing man and a beam: meshes far taller than wide.
TEST(CardSize, CgalsTallMeshes) {
  const char* cgal = "/usr/share/doc/libcgal-dev/data.tar.gz";
  if (!std::filesystem::exists(cgal)) GTEST_SKIP() << "libcgal-demo is not installed (" << cgal << ")";
  const std::filesystem::path dir = std::filesystem::path(testing::write_temp("cgal-tall/.keep", "")).parent_path();
  const std::string cmd =
      std::string("tar -xzf ") + cgal + " -C " + dir.string() + " data/meshes/man.off data/meshes/beam.off";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  for (const char* name : {"man.off", "beam.off"}) {
    const std::string path = (dir / "data/meshes" / name).string();
    const MeshImport plain = import_mesh_file(path, parse_import_options({}, name), name);
    const double plain_h = plain.pattern.sheet.max.v_mm - plain.pattern.sheet.min.v_mm;
    EXPECT_GT(plain_h, 500) << name << ": at the default 120 mm across the sheet is huge";
    EXPECT_FALSE(media_warnings(plain.pattern.sheet, {{"a4", 210, 297}}).empty()) << name << ": and is warned of";
    const MeshImport sized = import_mesh_file(path, parse_import_options({{"height-mm", "120"}}, name), name);
    const Rect& s = sized.pattern.sheet;
    EXPECT_NEAR(s.max.v_mm, 120, 1e-3) << name << ": the card stands 120 mm high";
    EXPECT_LE(s.max.v_mm - s.min.v_mm, 240) << name << ": on a sheet at most twice that";
    const MeshImport a4 =
        import_mesh_file(path, parse_import_options({{"fit-mm", "a4"}}, name, {{"a4", 210, 297}}), name);
    EXPECT_TRUE(media_warnings(a4.pattern.sheet, {{"a4", 210, 297}}).empty())
        << name << ": fitted to A4, nothing to warn of";
  }
}

}  // namespace
}  // namespace popcut
