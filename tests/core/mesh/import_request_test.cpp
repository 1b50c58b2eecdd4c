// Tests of popcut import's text options (shared by the CLI and popcutd) and the whole file import.
#include "popcut/mesh/import_request.h"

#include <gtest/gtest.h>

#include "popcut/error.h"
#include "popcut/io/files.h"
#include "popcut/io/voxel_json.h"

namespace popcut {
namespace {

// The error's "location: message" for these option values, or "" when they parse.
std::string option_error(const std::vector<std::pair<std::string, std::string>>& values) {
  try {
    parse_import_options(values, "m.obj");
  } catch (const Error& e) {
    return e.location() + ": " + e.message();
  }
  return "";
}

TEST(ImportOptionText, ReadsEveryOptionByItsFlagName) {
  const ImportRequest r = parse_import_options({{"up", "+y"},
                                                {"front", "x"},
                                                {"resolution", "64"},
                                                {"voxel-mm", "2.5"},
                                                {"keep-depth", "0.75"},
                                                {"smooth", "5"},
                                                {"no-windows", "true"},
                                                {"thin-tops", "2"},
                                                {"depth-method", "raycast"},
                                                {"faces", "true"}},
                                               "m.obj");
  EXPECT_EQ(r.options.up, Axis::py) << "--up";
  EXPECT_EQ(r.options.front, Axis::px) << "--front without a sign is +";
  EXPECT_EQ(r.options.resolution, 64) << "--resolution";
  EXPECT_EQ(r.options.voxel_mm.value_or(0), 2.5) << "--voxel-mm";
  EXPECT_FALSE(r.options.width_mm) << "--width-mm not given";
  EXPECT_EQ(r.options.keep_depth, 0.75) << "--keep-depth";
  EXPECT_EQ(r.options.structuring_element, 5) << "--smooth";
  EXPECT_FALSE(r.options.windows) << "--no-windows";
  EXPECT_EQ(r.options.thin_top_voxels, 2) << "--thin-tops";
  EXPECT_EQ(r.options.depth, DepthMethod::raycast) << "--depth-method";
  EXPECT_TRUE(r.faces) << "--faces";
  const ImportRequest d = parse_import_options({}, "m.obj");
  EXPECT_EQ(d.options.resolution, ImportOptions{}.resolution) << "nothing given: the defaults";
  EXPECT_TRUE(d.options.windows && !d.faces) << "switches default off";
}

TEST(ImportOptionText, RefusesWhatIsNotAnOptionOrNotOfItsKind) {
  EXPECT_EQ(option_error({{"resolution", "4x"}}),
            "--resolution: '4x' is not a whole number: expected 1 to 2048 voxels across")
      << "trailing junk";
  EXPECT_NE(option_error({{"resolution", "99999999999"}}).find("out of range"), std::string::npos)
      << "too big for an int";
  EXPECT_NE(option_error({{"keep-depth", "half"}}).find("--keep-depth: 'half' is not a number"), std::string::npos)
      << "not a number";
  EXPECT_NE(option_error({{"width-mm", "12mm"}}).find("--width-mm: '12mm' is not a number"), std::string::npos)
      << "no units after the number";
  EXPECT_NE(option_error({{"up", "north"}}).find("--up: 'north' is not an axis"), std::string::npos) << "not an axis";
  EXPECT_NE(option_error({{"depth-method", "guess"}}).find("--depth-method: 'guess' is not a method"),
            std::string::npos)
      << "not a method";
  EXPECT_NE(option_error({{"faces", "1"}}).find("--faces: '1' is not a switch value"), std::string::npos)
      << "switches: true or false";
  EXPECT_NE(option_error({{"colour", "red"}}).find("--colour: not an import option"), std::string::npos)
      << "unknown option";
  EXPECT_NE(option_error({{"smooth", "3"}, {"smooth", "5"}}).find("--smooth: given twice"), std::string::npos)
      << "repeated option";
  EXPECT_EQ(option_error({{"smooth", "4"}}), "") << "ranges are import_mesh's to check, not the text parser's";
}

TEST(ImportOptionText, AxesAndDepthMethodsByTheirTableNames) {
  const Axis axes[] = {Axis::px, Axis::nx, Axis::py, Axis::ny, Axis::pz, Axis::nz};
  for (Axis a : axes) {
    EXPECT_EQ(parse_axis(to_string(a)), a) << to_string(a) << " reads back";
  }
  EXPECT_EQ(parse_axis("z"), Axis::pz) << "no sign is +";
  EXPECT_FALSE(parse_axis("-") || parse_axis("+") || parse_axis("") || parse_axis("++x") || parse_axis("X"))
      << "only the six names";
  EXPECT_EQ(option_error({{"up", "north"}}), "--up: 'north' is not an axis: use +x, -x, +y, -y, +z or -z");
  EXPECT_EQ(option_error({{"depth-method", "guess"}}),
            "--depth-method: 'guess' is not a method: use zbuffer or raycast");
  EXPECT_EQ(parse_import_options({{"depth-method", "zbuffer"}}, "m.obj").options.depth, DepthMethod::zbuffer);
}

TEST(ImportMeshFile, NamesTheSourceAndHoldsTheTriangleAndCellBudgets) {
  const std::string house = std::string(POPCUT_SOURCE_DIR) + "/examples/meshes/house.obj";
  ImportRequest r = parse_import_options({{"resolution", "40"}, {"thin-tops", "1"}}, "house.obj");
  const MeshImport m = import_mesh_file(house, r, "house.obj");
  EXPECT_EQ(
      parse_voxel_model(m.model_json, "imported"),
      parse_voxel_model(read_text_file(std::string(POPCUT_SOURCE_DIR) + "/examples/meshes/house.json"), "shipped"))
      << "the same card as examples/meshes/house.json (made by popcut import with these options)";
  EXPECT_FALSE(m.pattern.faces.empty()) << "the pattern comes with it";
  try {
    import_mesh_file(house, r, "upload.obj", 3);
    ADD_FAILURE() << "three triangles at most: refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::limit) << "a limit error";
    EXPECT_EQ(e.source(), "upload.obj") << "named by the caller's name for the file, not its path";
  }
  r.options.max_cells = 1000;
  try {
    import_mesh_file(house, r, "upload.obj");
    ADD_FAILURE() << "more cells than max_cells: refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::limit) << "a limit error: " << e.what();
    EXPECT_EQ(e.location(), "--resolution") << "naming the option to lower: " << e.what();
  }
}

}  // namespace
}  // namespace popcut
