// Every mesh reader refuses face corners that name no vertex (out of range, negative, overflowing) and truncated files,
// naming the line or record.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "popcut/error.h"
#include "popcut/mesh/mesh_import.h"
#include "test_meshes.h"

namespace popcut {
namespace {

using testing::write_temp;

// The error read_mesh gives for this file, as "location: message", or "read" when it reads.
std::string read_error(const std::string& name, const std::string& bytes) {
  try {
    read_mesh(write_temp(name, bytes));
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input) << name << ": bad input, exit 2";
    return e.location() + ": " + e.message();
  }
  return "read";
}

// A tetrahedron (four faces) with depth towards the viewer, then one more face line.
const std::string kObj = "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 2 4\nf 1 3 4\nf 2 3 4\nf 1 2 3\n";
const std::string kOff = "OFF\n4 5 0\n0 0 0\n10 0 0\n0 10 0\n0 0 10\n3 0 1 3\n3 0 2 3\n3 1 2 3\n3 0 1 2\n";
const std::string kPly =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\n"
    "property list uchar int vertex_indices\nend_header\n0 0 0\n10 0 0\n0 10 0\n0 0 10\n3 0 1 3\n";

std::string le32(std::uint32_t v) {
  std::string s(4, '\0');
  for (int k = 0; k < 4; ++k) s[static_cast<std::size_t>(k)] = static_cast<char>((v >> (8 * k)) & 0xff);
  return s;
}
std::string be32(std::uint32_t v) {
  std::string s(4, '\0');
  for (int k = 0; k < 4; ++k) s[static_cast<std::size_t>(k)] = static_cast<char>((v >> (8 * (3 - k))) & 0xff);
  return s;
}
std::uint32_t bits(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, 4);
  return u;
}

TEST(MeshIndex, ObjCornersMustNameAVertex) {
  // CGAL read each corner as an int and ended the face at the first it could not read, so
  // these faces lost a corner and were dropped as "zero area", exit 0.
  EXPECT_EQ(read_error("big.obj", kObj + "f 1 2 4294967300\n"),
            "line 9: face refers to vertex 4294967300, but the file has only 4 vertices: expected 1 to 4 or -1 to -4 "
            "counting back");
  EXPECT_EQ(read_error("int.obj", kObj + "f 1 2 2147483648\n"),
            "line 9: face refers to vertex 2147483648, but the file has only 4 vertices: expected 1 to 4 or -1 to -4 "
            "counting back");
  EXPECT_EQ(read_error("huge.obj", kObj + "f 1 2 99999999999999999999999\n"),
            "line 9: corner 3 '99999999999999999999999': '99999999999999999999999' is far larger than any vertex "
            "index: expected a "
            "vertex index, 1 to 4 or -1 to -4 counting back");
  EXPECT_EQ(
      read_error("word.obj", kObj + "f 1 2 abc\n"),
      "line 9: corner 3 'abc': 'abc' is not a whole number: expected a vertex index, 1 to 4 or -1 to -4 counting back");
  EXPECT_EQ(read_error("zero.obj", kObj + "f 1 2 0\n"),
            "line 9: corner 3: vertex 0 does not exist: OBJ counts vertices from 1");
  EXPECT_EQ(
      read_error("next.obj", kObj + "f 1 2 5/1/1\n"),
      "line 9: face refers to vertex 5, but the file has only 4 vertices: expected 1 to 4 or -1 to -4 counting back");
  // Relative corners count back from the face's own line.
  EXPECT_EQ(read_error("back.obj", "v 0 0 0\nv 10 0 0\nf -1 -2 -3\nv 0 0 10\n"),
            "line 3: face refers to vertex -3 (counting back), but only 2 are defined before it: expected 1 to 3 or -1 "
            "to -2 counting back");
  EXPECT_EQ(read_error("back-ok.obj", kObj + "f -1 -2 -3\n"), "read") << "-1 is the last vertex so far";
  EXPECT_EQ(read_mesh(write_temp("tabs.obj", kObj + "f 1\t3\t2\n")).triangles.size(), 5u)
      << "tab-separated corners are read, not dropped";
  EXPECT_EQ(read_mesh(write_temp("forward.obj", "f 1 2 4\nv 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\n")).triangles.size(),
            1u)
      << "a face may come before its vertices, as CGAL and most readers allow";
}

TEST(MeshIndex, OffCornersMustNameAVertex) {
  // CGAL's reader failed on these, and the error named neither line nor face.
  for (const char* corner : {"4", "7", "-1", "4294967298", "1.5", "x"}) {
    EXPECT_EQ(read_error("corner.off", kOff + "3 0 1 " + corner + "\n"),
              std::string("line 11 (face 5): corner 3 is vertex '") + corner +
                  "', but the file has 4 vertices: expected 0 to 3")
        << corner;
  }
  const std::string binary = "OFF BINARY\n" + be32(3) + be32(1) + be32(0) + be32(0) + be32(0) + be32(0) +
                             be32(bits(10)) + be32(0) + be32(0) + be32(0) + be32(0) + be32(bits(10));
  EXPECT_EQ(read_error("ok-bin.off", binary + be32(3) + be32(0) + be32(1) + be32(2) + be32(0)), "read");
  EXPECT_EQ(read_error("bad-bin.off", binary + be32(3) + be32(0) + be32(1) + be32(0xfffffffeu) + be32(0)),
            "face 1: corner 3 is vertex -2, but the file has 3 vertices: expected 0 to 2");
  EXPECT_EQ(read_error("far-bin.off", binary + be32(3) + be32(0) + be32(3) + be32(1) + be32(0)),
            "face 1: corner 2 is vertex 3, but the file has 3 vertices: expected 0 to 2");
}

TEST(MeshIndex, PlyCornersMustNameAVertex) {
  EXPECT_EQ(read_error("ok.ply", kPly + "3 0 1 2\n"), "read");
  EXPECT_EQ(read_error("far.ply", kPly + "3 0 1 4\n"),
            "face 2: corner 3 is vertex '4', but the file has 4 vertices: expected 0 to 3");
  EXPECT_EQ(read_error("neg.ply", kPly + "3 0 -1 2\n"),
            "face 2: corner 2 is vertex '-1', but the file has 4 vertices: expected 0 to 3");
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string vertices =
      le32(0) + le32(0) + le32(0) + le32(bits(10)) + le32(0) + le32(0) + le32(0) + le32(bits(10)) + le32(bits(10));
  EXPECT_EQ(read_error("ok-bin.ply", header + vertices + std::string(1, '\3') + le32(0) + le32(1) + le32(2)), "read");
  EXPECT_EQ(read_error("big-bin.ply", header + vertices + std::string(1, '\3') + le32(0) + le32(1) + le32(0x80000000u)),
            "face 1: corner 3 is vertex -2147483648, but the file has 3 vertices: expected 0 to 2");
  std::string unsigned_header = header;
  unsigned_header.replace(unsigned_header.find("uchar int"), 9, "uchar uint");
  EXPECT_EQ(read_error("ubig-bin.ply",
                       unsigned_header + vertices + std::string(1, '\3') + le32(0) + le32(1) + le32(4294967295u)),
            "face 1: corner 3 is vertex 4294967295, but the file has 3 vertices: expected 0 to 2");
}

TEST(MeshIndex, TruncatedAsciiStlNamesTheLine) {
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 10\nendloop\nendfacet\n";
  const std::string whole = "solid t\n" + facet + "endsolid t\n";
  EXPECT_EQ(read_error("ok.stl", whole), "read");
  EXPECT_EQ(read_error("cut.stl", "solid t\n" + facet + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0\n"),
            "line 12: 'vertex' has 2 of its 3 numbers on its line: expected x y z");
  EXPECT_EQ(read_error("open.stl", "solid t\n" + facet + "facet normal 0 0 1\nouter loop\nvertex 0 0 0\n"),
            "line 11: the file ends inside the facet that begins on line 9: expected 3 'vertex x y z' and 'endfacet' "
            "(truncated?)");
  EXPECT_EQ(read_error("noend.stl", "solid t\n" + facet), "line 8: the file ends before 'endsolid' (truncated?)");
  EXPECT_EQ(
      read_error("quad.stl",
                 "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n"),
      "line 7: the facet from line 2 has 2 vertices: only triangles (3 'vertex x y z') can be read");
}

TEST(MeshIndex, HugeCountsAreRefusedBeforeAllocating) {
  EXPECT_NE(read_error("count.off", "OFF\n3000000000 1 0\n0 0 0\n").find("declares 3000000000 vertices"),
            std::string::npos);
  EXPECT_NE(read_error("count.ply",
                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                       "element face 4000000000\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n")
                .find("4000000000 faces"),
            std::string::npos);
}

}  // namespace
}  // namespace popcut
