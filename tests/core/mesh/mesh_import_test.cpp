// Tests of mesh import: readers, depth sampling, morphology, eq. 7 filling, windows, thin tops, bad input.
#include "popcut/mesh/mesh_import.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "popcut/error.h"
#include "popcut/io/voxel_json.h"
#include "popcut/design/thin_tops.h"
#include "popcut/io/model_io.h"
#include "popcut/mesh/silhouette_faces.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "test_meshes.h"

namespace popcut {
namespace {

using testing::write_temp;

bool pops_up(const VoxelModel& m) { return check_popup(make_pattern(m)).pops_up(); }

ImportOptions small(int resolution) {
  ImportOptions o;
  o.resolution = resolution;
  return o;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.location() + ": " + e.message();
  }
  return "no error";
}

// Thin top faces partly dropped: a slice's top left out while a slice next to it, with a step at
// the same height over overlapping depths (the same face), keeps its top. Must be 0.
int partly_dropped_faces(const VoxelModel& m) {
  int partial = 0;
  for (int x = 0; x + 1 < m.width; ++x) {
    for (int y = 0; y < m.depth; ++y) {
      const int z = m.h(x, y);
      if (z == 0) continue;
      if (m.h(x + 1, y) == z && m.is_top_dropped(x, z) != m.is_top_dropped(x + 1, z)) ++partial;
    }
  }
  return partial;
}

TEST(MeshRead, EveryFormatGivesTheSameCard) {
  const TriangleSoup house = testing::house_mesh();
  const std::vector<std::pair<std::string, std::string>> files = {{"house.obj", testing::to_obj(house)},
                                                                  {"house.off", testing::to_off(house)},
                                                                  {"house.ply", testing::to_ply(house)},
                                                                  {"house.stl", testing::to_stl_ascii(house)},
                                                                  {"house-binary.STL", testing::to_stl_binary(house)}};
  const VoxelModel reference = import_mesh(house, small(40), "house").model;
  for (const auto& [name, text] : files) {
    const std::string path = write_temp(name, text);
    const TriangleSoup read = read_mesh(path);
    EXPECT_EQ(read.triangles.size(), house.triangles.size()) << name << ": every triangle is read";
    EXPECT_EQ(import_mesh(read, small(40), path).model, reference) << name << ": the same card as the mesh in memory";
  }
}

TEST(MeshImport, HouseHasAGableAPorchAndPopsUp) {
  const ImportResult r = import_mesh(testing::house_mesh(), small(40), "house");
  const VoxelModel& m = r.model;
  ASSERT_FALSE(find_violation(m)) << "the staircase rule holds";
  EXPECT_TRUE(pops_up(m)) << "the imported house pops up";
  EXPECT_EQ(m.width, 40) << "resolution is the number of voxels across";
  EXPECT_EQ(m.height, 34) << "40 mesh units across in 40 voxels: 34 units high is 34 voxels";
  EXPECT_EQ(m.voxel_mm, 3.0) << "default card width 120 mm over 40 voxels";
  EXPECT_GT(m.h(20, 0), m.h(2, 0) + 10) << "the ridge in the middle stands well above the eaves";
  EXPECT_NEAR(m.h(20, 0), 34, 1) << "the ridge reaches the top";
  // Kept depth: the front half of 39 units (30 house + 9 porch) is 19.5 units ≈ 20 voxels;
  // the porch (9 deep) stands in front of the house's front wall in the middle slices only.
  EXPECT_EQ(m.depth, 20) << "front half of the depth";
  int front_mid = 0, front_side = 0;
  for (int y = 0; y < m.depth; ++y) {
    front_mid += m.h(20, y) > 0;
    front_side += m.h(2, y) > 0;
  }
  EXPECT_EQ(front_mid - front_side, 9) << "the porch adds 9 voxels of depth in the middle";
}

TEST(MeshImport, ArchOpeningBecomesWindows) {
  ImportOptions o = small(40);
  o.structuring_element = 1;
  const ImportResult r = import_mesh(testing::arch_mesh(), o, "arch");
  EXPECT_GT(r.stats.cells_filled, 0) << "the opening under the arch is filled by eq. 7";
  EXPECT_GT(r.stats.windows_added, 0) << "and opened again as windows where the card stands";
  EXPECT_TRUE(pops_up(r.model)) << "with its windows the arch pops up";
  // Mid-opening, low rows: the opening is see-through, so those rows are windows.
  EXPECT_TRUE(r.model.is_window(20, 3)) << "the middle of the opening is a window";
  EXPECT_FALSE(r.model.is_window(2, 3)) << "the pier is solid";
}

TEST(MeshImport, ArchSillsLineUp) {
  // An opening taller than the card is deep keeps one solid row per slice under its windows; at
  // the same height in every slice, those rows' sills make one face, not one per slice (the
  // paper's top-down order gave 8 and 18 sills held from one side on examples/meshes/arch.off).
  const TriangleSoup arch = testing::arch_mesh(40, 30, 40, 16);
  for (int across : {40, 80}) {
    const ImportResult r = import_mesh(arch, small(across), "arch");
    const PopupReport report = check_popup(make_pattern(r.model));
    ASSERT_TRUE(report.pops_up()) << across << " across";
    EXPECT_GT(r.stats.windows_added, 0) << across << " across: the opening is open";
    EXPECT_LE(report.flaps.size(), 2u) << across << " across: the sills line up into few faces held from one side";
  }
}

TEST(MeshImport, TowerStepsBackTierByTier) {
  const ImportResult r = import_mesh(testing::tower_mesh(), small(40), "tower");
  const VoxelModel& m = r.model;
  EXPECT_TRUE(pops_up(m)) << "the tower pops up";
  int steps = 0;
  for (int y = 1; y < m.depth; ++y) steps += m.h(20, y) != m.h(20, y - 1);
  EXPECT_GE(steps, 3) << "the middle slice steps down towards the front once per tier";
}

TEST(MeshImport, AxesChooseTheView) {
  // The house turned so +Y is up and +Z faces the viewer gives the same card.
  TriangleSoup turned = testing::house_mesh();
  for (auto& p : turned.points) p = {p[0], p[2], -p[1]};
  ImportOptions o = small(30);
  o.up = Axis::py;
  o.front = Axis::pz;
  EXPECT_EQ(import_mesh(turned, o, "turned").model, import_mesh(testing::house_mesh(), small(30), "house").model)
      << "--up +y --front +z reads a Y-up model";
}

TEST(MeshImport, RandomMeshesAlwaysGiveACardThatPopsUp) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 30);
  const Axis axes[] = {Axis::px, Axis::nx, Axis::py, Axis::ny, Axis::pz, Axis::nz};
  int windows = 0;
  for (int trial = 0; trial < 60; ++trial) {
    TriangleSoup s;
    const int boxes = 1 + static_cast<int>(rng() % 6);
    for (int b = 0; b < boxes; ++b) {
      const double x = u(rng), y = u(rng), z = u(rng);
      testing::add_box(s, x, y, z, x + 1 + u(rng) / 2, y + 1 + u(rng) / 2, z + 1 + u(rng) / 2);
    }
    ImportOptions o;
    o.resolution = 8 + static_cast<int>(rng() % 40);
    o.up = axes[rng() % 6];
    do o.front = axes[rng() % 6];
    while (static_cast<int>(o.front) / 2 == static_cast<int>(o.up) / 2);
    o.keep_depth = 0.2 + 0.2 * static_cast<int>(rng() % 5);
    o.structuring_element = 1 + 2 * static_cast<int>(rng() % 3);
    o.thin_top_voxels = static_cast<int>(rng() % 3);
    try {
      const ImportResult r = import_mesh(s, o, "random");
      ASSERT_FALSE(find_violation(r.model)) << "trial " << trial << ": the staircase rule holds";
      ASSERT_TRUE(pops_up(r.model)) << "trial " << trial << ": every import pops up";
      EXPECT_EQ(partly_dropped_faces(r.model), 0) << "trial " << trial << ": thin tops go as whole faces";
      windows += r.stats.windows_added;
    } catch (const Error& e) {
      // Only a documented refusal: nothing left after smoothing.
      EXPECT_NE(e.message().find("no voxel is left"), std::string::npos) << "trial " << trial << ": " << e.message();
    }
  }
  EXPECT_GT(windows, 0) << "overhanging boxes give windows somewhere";
}

TEST(DepthSampling, ZBufferAndRayCastingAgree) {
  for (const TriangleSoup& mesh :
       {testing::house_mesh(), testing::arch_mesh(), testing::tower_mesh(), testing::city_mesh(4, 3)}) {
    const TriangleSoup card = to_card_frame(mesh, Axis::pz, Axis::ny, "");
    const ImportGrid g = plan_grid(card, small(64), "");
    const std::vector<int> a = depth_cells(sample_depth_zbuffer(card, g), g);
    const std::vector<int> b = depth_cells(sample_depth_raycast(card, g), g);
    int differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
    EXPECT_LE(differ * 500, static_cast<int>(a.size()))
        << differ << " of " << a.size() << " cells differ between the two samplers";
  }
}

// A brute-force binary erosion/dilation of one yz slice, to check the profile shortcut.
std::vector<int> brute_open_close(std::vector<int> p, int depth, int side) {
  const int h = static_cast<int>(p.size()), r = side / 2;
  using Image = std::vector<std::vector<char>>;
  const auto image = [&](const std::vector<int>& q) {
    Image im(static_cast<std::size_t>(h), std::vector<char>(static_cast<std::size_t>(depth)));
    for (int z = 0; z < h; ++z)
      for (int y = 0; y < depth; ++y)
        im[static_cast<std::size_t>(z)][static_cast<std::size_t>(y)] = y < q[static_cast<std::size_t>(z)];
    return im;
  };
  const auto op = [&](const Image& in, bool erode) {
    Image out = in;
    for (int z = 0; z < h; ++z)
      for (int y = 0; y < depth; ++y) {
        bool v = erode;
        for (int dz = -r; dz <= r; ++dz)
          for (int dy = -r; dy <= r; ++dy) {
            const int zz = z + dz, yy = y + dy;
            if (zz < 0 || zz >= h || yy < 0 || yy >= depth) continue;  // outside: neutral
            const bool c = in[static_cast<std::size_t>(zz)][static_cast<std::size_t>(yy)];
            v = erode ? (v && c) : (v || c);
          }
        out[static_cast<std::size_t>(z)][static_cast<std::size_t>(y)] = v;
      }
    return out;
  };
  Image im = op(op(op(op(image(p), true), false), false), true);
  for (int z = 0; z < h; ++z) {
    int n = 0;
    while (n < depth && im[static_cast<std::size_t>(z)][static_cast<std::size_t>(n)]) ++n;
    for (int y = n; y < depth; ++y)
      EXPECT_FALSE(im[static_cast<std::size_t>(z)][static_cast<std::size_t>(y)]) << "the result is a profile";
    p[static_cast<std::size_t>(z)] = n;
  }
  return p;
}

TEST(Morphology, ProfileShortcutEqualsBinaryOpeningAndClosing) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 300; ++trial) {
    ImportGrid g;
    g.width = 1;
    g.height = 1 + static_cast<int>(rng() % 14);
    g.depth = 1 + static_cast<int>(rng() % 10);
    std::vector<int> p(static_cast<std::size_t>(g.height));
    for (int& v : p) v = static_cast<int>(rng() % static_cast<unsigned>(g.depth + 1));
    const int side = 1 + 2 * static_cast<int>(rng() % 3);
    std::vector<int> fast = p;
    open_close(fast, g, side);
    EXPECT_EQ(fast, brute_open_close(p, g.depth, side)) << "trial " << trial << ", square " << side;
  }
}

TEST(Morphology, RemovesABumpAndFillsADent) {
  ImportGrid g;
  g.width = 1;
  g.height = 9;
  g.depth = 10;
  std::vector<int> bump = {5, 5, 5, 5, 8, 5, 5, 5, 5};
  open_close(bump, g, 3);
  EXPECT_EQ(bump, std::vector<int>(9, 5)) << "a one-row bump goes";
  std::vector<int> dent = {5, 5, 5, 5, 2, 5, 5, 5, 5};
  open_close(dent, g, 3);
  EXPECT_EQ(dent, std::vector<int>(9, 5)) << "a one-row dent fills";
  std::vector<int> wide = {5, 5, 8, 8, 8, 8, 5, 5, 5};
  const std::vector<int> before = wide;
  open_close(wide, g, 3);
  EXPECT_EQ(wide, before) << "a feature as wide as the square stays";
}

TEST(ThinTops, GableRoofDropsNarrowTopsAndKeepsTheRidge) {
  ImportOptions o = small(40);
  o.thin_top_voxels = 1;
  const ImportResult r = import_mesh(testing::house_mesh(), o, "house");
  EXPECT_GT(r.stats.tops_dropped, 10) << "the roof's one-slice-wide steps go (the two-slice steps hold the front)";
  EXPECT_TRUE(pops_up(r.model)) << "the card still pops up";
  const Pattern with = make_pattern(r.model);
  const Pattern without = make_pattern(import_mesh(testing::house_mesh(), small(40), "house").model);
  EXPECT_LT(with.faces.size(), without.faces.size()) << "fewer faces to cut and fold";
  // Round trip through popcut.voxel.v1.
  EXPECT_EQ(parse_voxel_model(to_voxel_json(r.model), "rt"), r.model) << "dropped_tops survive the file";
}

TEST(ThinTops, TallestOfARunStaysAsTheSupport) {
  // Paper Fig. 14 (a): slices d, c, b, a rising one voxel each, every top one slice wide, one
  // front wall across them. Lowest first, d, c and b go; a must stay to hold the wall up.
  VoxelModel m = VoxelModel::empty(4, 2, 8, 1.0);
  for (int x = 0; x < 4; ++x) {
    for (int y = 0; y < 2; ++y) m.h_at(x, y) = 5 + x;
  }
  const ThinTops r = drop_thin_tops(m, 1);
  EXPECT_EQ(r.dropped, 3) << "three thin tops go";
  EXPECT_EQ(r.kept, 1) << "one stays";
  EXPECT_FALSE(m.is_top_dropped(3, 8)) << "the tallest is the one kept";
  EXPECT_TRUE(m.is_top_dropped(0, 5) && m.is_top_dropped(1, 6) && m.is_top_dropped(2, 7))
      << "the lower three are dropped";
  EXPECT_TRUE(pops_up(m)) << "and the card pops up";
  VoxelModel wide = VoxelModel::empty(4, 2, 8, 1.0);
  for (int x = 0; x < 4; ++x) wide.h_at(x, 0) = wide.h_at(x, 1) = 5 + x / 2;
  EXPECT_EQ(drop_thin_tops(wide, 1).dropped, 0) << "tops two slices wide are above the threshold of one";
}

TEST(ThinTops, AWideThinFaceGoesAsAWhole) {
  // Fig. 14 (a) with every step two slices wide and a threshold of two: the three lower faces go
  // whole; the tallest must stay to hold the front wall, and stays whole (slice by slice its left
  // slice could go, the right one holding the wall, which leaves a face half dropped).
  VoxelModel m = VoxelModel::empty(8, 2, 10, 1.0);
  for (int x = 0; x < 8; ++x) m.h_at(x, 0) = m.h_at(x, 1) = 5 + x / 2;
  const ThinTops r = drop_thin_tops(m, 2);
  EXPECT_EQ(r.dropped, 3) << "three faces go";
  EXPECT_EQ(r.kept, 1) << "the tallest face stays";
  EXPECT_FALSE(m.is_top_dropped(6, 8) || m.is_top_dropped(7, 8)) << "no slice of the kept face is dropped";
  for (int x = 0; x < 6; ++x) EXPECT_TRUE(m.is_top_dropped(x, 5 + x / 2)) << "slice " << x << " of a dropped face";
  EXPECT_EQ(partly_dropped_faces(m), 0) << "faces go whole";
  EXPECT_TRUE(pops_up(m)) << "and the card pops up";
}

TEST(ThinTops, MeshWithAWideThinRoof) {
  // A stepped roof of four terraces rising to the right, each 2 voxels wide and as deep as the
  // card: every roof face is 2 slices wide, under a threshold of 2.
  TriangleSoup s;
  for (int k = 0; k < 4; ++k) testing::add_box(s, 2.0 * k, 0, 0, 2.0 * k + 2, 3, 5.0 + k);
  ImportOptions o = small(8);
  o.keep_depth = 1;
  o.structuring_element = 1;
  o.thin_top_voxels = 2;
  const ImportResult r = import_mesh(s, o, "roof");
  EXPECT_EQ(r.stats.tops_dropped, 3) << "the three lower terraces go";
  EXPECT_EQ(r.stats.tops_kept, 1) << "the top terrace holds the front wall";
  EXPECT_EQ(partly_dropped_faces(r.model), 0) << "and each terrace goes or stays whole, across its two slices";
  EXPECT_TRUE(pops_up(r.model)) << "the card pops up";
}

TEST(ThinTops, DroppedTopLiesOnTheWallBehind) {
  // One slice, a 3-high column 2 deep in front of the back wall: dropping its top puts the
  // top's two cells (v = 1, 2) on the back wall, which then reaches down to v = 1.
  VoxelModel m = VoxelModel::empty(1, 2, 3, 1.0);
  m.h_at(0, 0) = 3;
  m.h_at(0, 1) = 3;
  m.sheet.side = 0;
  m.set_top_dropped(0, 3, true);
  const CellGrid g = make_cell_grid(m);
  const int floor = g.sheet.floor;
  EXPECT_EQ(g.at(0, floor + 1), CellGrid::pack(FaceKind::vertical, 0)) << "v = 1 is back wall";
  EXPECT_EQ(g.at(0, floor + 0), CellGrid::pack(FaceKind::vertical, 2)) << "v = 0 is the front wall's top cell";
  EXPECT_FALSE(pops_up(m)) << "alone, the front wall stands on nothing from the back";
}

// Binary records for the crafted files below, in the byte order the format asks for.
std::string bytes_of(const std::vector<std::uint32_t>& words, bool big_endian) {
  std::string out;
  for (std::uint32_t w : words) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>(w >> (8 * (big_endian ? 3 - k : k))));
  }
  return out;
}
std::uint32_t float_bits(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, 4);
  return u;
}

// A list or face count the rest of the file cannot hold is refused, naming the record, before
// CGAL's reader resizes a vector to it (0xffffffff ints took all the memory there is).
TEST(MeshRead, ListCountsAreBoundedByTheFile) {
  const std::string ply_header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uint int vertex_indices\nend_header\n";
  const std::string vertices =
      bytes_of({0, float_bits(-1), 0, float_bits(1), 0, 0, 0, float_bits(-1), float_bits(1)}, false);
  const std::string face = bytes_of({3, 0, 1, 2}, false);
  // The well-formed file reads; each corruption below is one count.
  EXPECT_EQ(read_mesh(write_temp("ok.ply", ply_header + vertices + face + face)).triangles.size(), 2u)
      << "the good binary PLY reads";
  EXPECT_EQ(error_of([&] {
              read_mesh(write_temp("big.ply", ply_header + vertices + face + bytes_of({0xffffffffu, 0, 1, 2}, false)));
            }),
            "face 2: list 'vertex_indices' says 4294967295 entries, but only 12 bytes (3 entries) are left in the "
            "file: the file is "
            "truncated or corrupt")
      << "a uint count of 0xffffffff";
  std::string signed_header = ply_header;
  signed_header.replace(signed_header.find("list uint"), 9, "list int");
  EXPECT_NE(
      error_of([&] {
        read_mesh(write_temp("neg.ply", signed_header + vertices + bytes_of({0x80000000u, 0, 1, 2}, false) + face));
      }).find("face 1: list 'vertex_indices' says -2147483648 entries"),
      std::string::npos)
      << "a negative int count";
  EXPECT_NE(error_of([&] {
              read_mesh(write_temp("cut.ply", ply_header + vertices + face + face.substr(0, 10)));
            }).find("face 2: "),
            std::string::npos)
      << "a face cut short";
  std::string big_endian = ply_header;
  big_endian.replace(big_endian.find("little"), 6, "big");
  EXPECT_NE(
      error_of([&] {
        read_mesh(write_temp("be.ply", big_endian + std::string(36, '\0') + bytes_of({3, 0, 1, 2, 0x01000000u}, true)));
      }).find("face 2: list 'vertex_indices' says 16777216 entries"),
      std::string::npos)
      << "big-endian counts are read big-endian";
  const std::string ascii_ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 0 1\n";
  EXPECT_EQ(error_of([&] { read_mesh(write_temp("big-ascii.ply", ascii_ply + "4294967295 0 1 2\n")); }),
            "face 1: list 'vertex_indices' says '4294967295' entries, but only 3 numbers are left in the file: "
            "expected a whole "
            "number of entries that follow")
      << "a text PLY count";
  // OFF: CGAL sizes a face by its first number, whatever the line holds.
  const std::string off = "OFF\n# comment\n3 1 0\n\n0 0 0\n1 0 0  # x\n0 0 1\n";
  EXPECT_EQ(error_of([&] { read_mesh(write_temp("big.off", off + "1e18 0 1 2\n")); }),
            "line 8 (face 1): says '1e18' corners, but the line has 3 more numbers: expected the corner count, then "
            "that many "
            "vertex indices")
      << "a text OFF face count";
  EXPECT_NE(error_of([&] {
              read_mesh(write_temp("neg.off", off + "-1 0 1 2\n"));
            }).find("line 8 (face 1): says '-1' corners"),
            std::string::npos)
      << "a negative OFF face count";
  EXPECT_EQ(read_mesh(write_temp("ok.off", off + "3 0 1 2 255 0 0\n")).triangles.size(), 1u)
      << "comments, blank lines and a face colour are fine";
  const std::string binary_off =
      "OFF BINARY\n" + bytes_of({3, 1, 0}, true) + bytes_of({0, 0, 0, float_bits(1), 0, 0, 0, 0, float_bits(1)}, true);
  EXPECT_EQ(read_mesh(write_temp("ok-bin.off", binary_off + bytes_of({3, 0, 1, 2, 0}, true))).points.size(), 3u)
      << "the good binary OFF reads";
  EXPECT_EQ(
      error_of([&] {
        read_mesh(write_temp("big-bin.off", binary_off + bytes_of({0x7fffffffu, 0, 1, 2, 0}, true)));
      }),
      "face 1: says 2147483647 corners, but only 4 numbers are left in the file: the file is truncated or corrupt")
      << "a binary OFF face count";
  // Coordinates that are finite but whose extent overflows.
  EXPECT_NE(error_of([] {
              const TriangleSoup s = read_mesh(write_temp("huge.obj", "v 1e308 0 0\nv -1e308 0 0\nv 0 1 1\nf 1 2 3\n"));
              import_mesh(s, small(10), "huge.obj");
            }).find("x extent (card axes) overflows a double"),
            std::string::npos)
      << "huge coordinates";
}

TEST(MeshRead, BadFilesGiveClearErrors) {
  EXPECT_NE(error_of([] { read_mesh(write_temp("empty.obj", "")); }).find("empty"), std::string::npos);
  EXPECT_NE(error_of([] { read_mesh(write_temp("model.xyz", "v 0 0 0")); }).find("unknown mesh format '.xyz'"),
            std::string::npos);
  EXPECT_NE(error_of([] { read_mesh("/nonexistent/house.obj"); }).find("no such file"), std::string::npos);
  EXPECT_NE(error_of([] {
              read_mesh(write_temp("trunc.off", "OFF\n8 12 0\n0 0 0\n1 0 0\n"));
            }).find("8 vertices and 12 faces"),
            std::string::npos);
  // Counts no file of that size could hold are refused before CGAL's reader reserves them (a
  // billion vertices from 34 bytes took all memory before).
  EXPECT_NE(error_of([] {
              read_mesh(write_temp("huge.off", "OFF\n1000000000 1000000000 0\n0 0 0\n"));
            }).find("truncated or corrupt"),
            std::string::npos);
  EXPECT_NE(
      error_of([] {
        read_mesh(write_temp("huge.ply",
                             "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"));
      }).find("declares 4000000000 vertices"),
      std::string::npos);
  EXPECT_NE(error_of([] {
              read_mesh(write_temp("short.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n"));
            }).find("not a readable OFF file"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              read_mesh(write_temp("range.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 9\n"));
            }).find("line 4: face refers to vertex 9, but the file has only 3 vertices"),
            std::string::npos);
  EXPECT_NE(
      error_of([] { read_mesh(write_temp("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")); }).find("zero area"),
      std::string::npos);
  TriangleSoup nan_mesh = testing::house_mesh();
  nan_mesh.points[3][1] = std::nan("");
  EXPECT_NE(
      error_of([&] { read_mesh(write_temp("nan.stl", testing::to_stl_binary(nan_mesh))); }).find("not a finite number"),
      std::string::npos);
  // A binary STL cut short of its triangle count.
  const std::string stl = testing::to_stl_binary(testing::house_mesh());
  EXPECT_NE(error_of([&] { read_mesh(write_temp("cut.stl", stl.substr(0, stl.size() - 30))); }).find("truncated"),
            std::string::npos);
  EXPECT_NE(error_of([] { read_mesh(write_temp("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n")); }).find("line 3: 'l'"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              read_mesh(write_temp("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 0 1\nf 1 2 3\n"));
            }).find("line 2: 'nan'"),
            std::string::npos);
}

TEST(MeshRead, NonManifoldAndUnorientedMeshesStillImport) {
  TriangleSoup s = testing::tower_mesh(2);
  // Flip every other triangle and add a fin sharing an edge with three triangles.
  for (std::size_t i = 0; i < s.triangles.size(); i += 2) std::swap(s.triangles[i][1], s.triangles[i][2]);
  s.points.push_back({20, -5, 5});
  s.triangles.push_back({0, 1, static_cast<std::uint32_t>(s.points.size() - 1)});
  const ImportResult r = import_mesh(read_mesh(write_temp("odd.obj", testing::to_obj(s))), small(20), "odd");
  EXPECT_TRUE(pops_up(r.model)) << "only the surface seen from the front matters";
}

TEST(MeshImport, BadOptionsAndDegenerateMeshesAreNamed) {
  const TriangleSoup house = testing::house_mesh();
  const auto with = [&](auto change) {
    ImportOptions o = small(20);
    change(o);
    return error_of([&] { import_mesh(house, o, "house"); });
  };
  EXPECT_NE(with([](ImportOptions& o) { o.resolution = 0; }).find("--resolution"), std::string::npos);
  EXPECT_NE(with([](ImportOptions& o) { o.keep_depth = 0; }).find("--keep-depth"), std::string::npos);
  EXPECT_NE(with([](ImportOptions& o) { o.structuring_element = 4; }).find("--smooth"), std::string::npos);
  EXPECT_NE(with([](ImportOptions& o) { o.front = Axis::nz; }).find("--front: must be perpendicular"),
            std::string::npos);
  EXPECT_NE(with([](ImportOptions& o) {
              o.width_mm = 100;
              o.voxel_mm = 2;
            }).find("not both"),
            std::string::npos);
  EXPECT_NE(with([](ImportOptions& o) { o.voxel_mm = 5000; }).find("--voxel-mm"), std::string::npos);
  EXPECT_NE(with([](ImportOptions& o) { o.resolution = 2000; }).find("--resolution"), std::string::npos)
      << "the sheet's cell limit is named before any work";
  // A plate facing the viewer has no depth; a thin spike is smoothed away entirely.
  TriangleSoup plate;
  testing::add_box(plate, 0, 0, 0, 10, 0, 10);
  EXPECT_NE(error_of([&] { import_mesh(plate, small(10), "plate"); }).find("no depth"), std::string::npos);
  // A plate behind the back wall (the front half is kept) and a slab thinner than a voxel.
  TriangleSoup spike;
  testing::add_box(spike, 0, 9, 0, 10, 10, 10);
  testing::add_box(spike, 0, 0, 5, 10, 10, 5.4);
  EXPECT_NE(error_of([&] { import_mesh(spike, small(20), "spike"); }).find("no voxel is left"), std::string::npos);
}

TEST(SilhouetteFaces, HouseRoofFollowsTheSlopeWithFewerLines) {
  ImportOptions o = small(40);
  o.thin_top_voxels = 2;
  const TriangleSoup house = testing::house_mesh();
  const ImportResult voxels = import_mesh(house, o, "house");
  const SilhouetteFaces f = silhouette_faces(house, o, voxels, "house");
  const SilhouetteComparison& c = f.comparison;
  EXPECT_GT(c.outlines, 0) << "the roof edges are redrawn";
  EXPECT_GT(c.samples, 100) << "along many silhouette samples";
  EXPECT_LT(c.face_mean_mm, c.voxel_mean_mm / 2)
      << "the polyline is at least twice as close to the silhouette as the steps";
  EXPECT_LT(c.face_lines, c.voxel_lines) << "and needs fewer lines";
  const Pattern p = make_pattern(AnyModel(f.model));
  EXPECT_TRUE(check_popup(p).pops_up()) << "the face model pops up";
  EXPECT_EQ(p.faces.size(), make_pattern(voxels.model).faces.size()) << "the same faces, other outlines";
  // Round trip through popcut.faces.v1.
  EXPECT_EQ(make_pattern(parse_model(to_face_json(f.model), "rt")).faces.size(), p.faces.size())
      << "the file reads back";
}

TEST(SilhouetteFaces, ArchOpeningFollowsTheCurve) {
  // The opening's top is a cut between the arch's front face and the window paper below it: it
  // follows the underside of the arch at the front face's depth, not the voxel steps.
  const TriangleSoup arch = testing::arch_mesh();
  const ImportOptions o = small(40);
  const ImportResult voxels = import_mesh(arch, o, "arch");
  const SilhouetteFaces f = silhouette_faces(arch, o, voxels, "arch");
  const SilhouetteComparison& c = f.comparison;
  EXPECT_FALSE(c.fell_back) << "the redrawn model passed its checks";
  EXPECT_GT(c.outlines, 0) << "the opening's outline is redrawn";
  EXPECT_GT(c.samples, 50) << "along many silhouette samples";
  EXPECT_LT(c.face_mean_mm, c.voxel_mean_mm / 2) << "at least twice as close to the arch's underside as the steps";
  EXPECT_TRUE(check_popup(make_pattern(AnyModel(f.model))).pops_up()) << "the face model pops up";
}

// Imports a random mesh and its face model: it pops up and is never further from the silhouette
// than the voxel steps; counts the outlines redrawn and whole-model fallbacks.
void faces_of_random_mesh(const TriangleSoup& s, const ImportOptions& o, int trial, int& redrawn, int& fell_back) {
  ImportResult voxels;
  try {
    voxels = import_mesh(s, o, "random");
  } catch (const Error&) {
    return;  // nothing left after smoothing: tested elsewhere
  }
  const SilhouetteFaces f = silhouette_faces(s, o, voxels, "random");
  EXPECT_TRUE(check_popup(make_pattern(AnyModel(f.model))).pops_up())
      << "trial " << trial << ", " << o.resolution << " across";
  EXPECT_LE(f.comparison.face_mean_mm, f.comparison.voxel_mean_mm + 1e-9)
      << "trial " << trial << ": never further from the silhouette";
  redrawn += f.comparison.outlines;
  fell_back += f.comparison.fell_back;
}

TEST(SilhouetteFaces, RandomArchesAndOverhangsStayValid) {
  // Arches of random size and depth with a block behind or in front: openings and undersides.
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(0, 1);
  int redrawn = 0, fell_back = 0;
  for (int trial = 0; trial < 20; ++trial) {
    TriangleSoup s =
        testing::arch_mesh(30 + 30 * u(rng), 20 + 20 * u(rng), 8 + 20 * u(rng), 6 + static_cast<int>(rng() % 20));
    const double x0 = 40 * u(rng), z0 = 30 * u(rng);
    testing::add_box(s, x0, -10 * u(rng), z0, x0 + 5 + 20 * u(rng), 5 + 10 * u(rng), z0 + 3 + 10 * u(rng));
    ImportOptions o = small(16 + static_cast<int>(rng() % 50));
    o.thin_top_voxels = static_cast<int>(rng() % 3);
    faces_of_random_mesh(s, o, trial, redrawn, fell_back);
  }
  EXPECT_GT(redrawn, 10) << "openings and undersides get redrawn";
  EXPECT_LE(fell_back, 2) << "the whole-model fallback stays rare";
}

TEST(SilhouetteFaces, RandomSlantedMeshesStayValid) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(0, 1);
  int redrawn = 0, fell_back = 0;
  for (int trial = 0; trial < 25; ++trial) {
    TriangleSoup s;
    for (int k = 0; k < 3; ++k) {
      // Gabled and lean-to blocks at random depths: slanted tops seen from the front.
      const double x0 = 30 * u(rng), w = 8 + 20 * u(rng), h = 5 + 20 * u(rng), y0 = 20 * u(rng);
      testing::add_prism(
          s, {{x0, 0}, {x0 + w, 0}, {x0 + w, h * u(rng) + 1}, {x0 + w * u(rng), h + 6}, {x0, h * u(rng) + 1}}, y0,
          y0 + 10 + 20 * u(rng));
    }
    ImportOptions o = small(16 + static_cast<int>(rng() % 40));
    o.thin_top_voxels = 1 + static_cast<int>(rng() % 3);
    faces_of_random_mesh(s, o, trial, redrawn, fell_back);
  }
  EXPECT_GT(redrawn, 10) << "slanted tops get redrawn";
  EXPECT_LE(fell_back, 2) << "the whole-model fallback stays rare";
}

// Files other projects ship, read where their Debian packages are installed: each gives a card
// that pops up or a popcut::Error, never a crash.
void import_tree(const std::filesystem::path& dir, int& cards, int& refused) {
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    // Up to 1 MiB: the larger scanned models (CGAL's armadillo, diplodocus) add a minute under
    // the sanitizers and nothing the smaller ones do not test.
    if (!e.is_regular_file() || e.file_size() > (1u << 20)) continue;
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext != ".obj" && ext != ".stl" && ext != ".off" && ext != ".ply") continue;
    try {
      const ImportResult r = import_mesh(read_mesh(e.path().string()), small(24), e.path().string());
      EXPECT_TRUE(pops_up(r.model)) << e.path();
      ++cards;
    } catch (const Error& err) {
      EXPECT_NE(err.code(), ErrorCode::internal) << e.path() << ": " << err.message();
      ++refused;
    }
  }
}

TEST(MeshRead, InstalledTestModels) {
  int cards = 0, refused = 0, trees = 0;
  for (const char* dir : {"/usr/share/assimp/models", "/usr/share/openscad"}) {
    if (!std::filesystem::is_directory(dir)) continue;
    ++trees;
    import_tree(dir, cards, refused);
  }
  // libcgal-demo ships its data as a tarball: unpack only the meshes, into a temporary folder.
  const char* cgal = "/usr/share/doc/libcgal-dev/data.tar.gz";
  if (std::filesystem::exists(cgal)) {
    const std::filesystem::path dir = std::filesystem::path(write_temp("cgal-data/.keep", "")).parent_path();
    const std::string cmd =
        std::string("tar -xzf ") + cgal + " -C " + dir.string() + " --wildcards 'data/meshes/*.off'";
    if (std::system(cmd.c_str()) == 0) {
      ++trees;
      import_tree(dir, cards, refused);
    }
  }
  if (trees == 0) GTEST_SKIP() << "assimp-testmodels, openscad-testing-data and libcgal-demo are not installed";
  std::printf("installed models: %d cards, %d refused with a clear error\n", cards, refused);
  EXPECT_GT(cards, 10) << "most of the installed models import";
}

}  // namespace
}  // namespace popcut
