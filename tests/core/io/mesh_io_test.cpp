// OBJ and glTF output: counts, both sides, orientation, and a glTF document a loader accepts.
#include "popcut/io/mesh_io.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "popcut/io/voxel_json.h"
#include "popcut/pattern/voxel_pattern.h"

namespace popcut {
namespace {

CardMesh box_mesh(double angle) {
  return fold_card(
      make_pattern(parse_voxel_model(
          R"({"format": "popcut.voxel.v1", "voxel_mm": 10, "heights": [[2, 2]], "sheet": {"side": 1}})", "b.json")),
      angle);
}

TEST(MeshIo, ObjHasBothSides) {
  const CardMesh m = box_mesh(90);
  std::ostringstream out;
  write_obj(out, m, "card.mtl");
  const std::string obj = out.str();
  std::size_t faces = 0, normals = 0;
  for (std::size_t at = obj.find("\nf "); at != std::string::npos; at = obj.find("\nf ", at + 1)) ++faces;
  for (std::size_t at = obj.find("\nvn "); at != std::string::npos; at = obj.find("\nvn ", at + 1)) ++normals;
  EXPECT_EQ(faces, 2 * m.triangles.size()) << "each triangle once per side";
  EXPECT_EQ(normals, 2 * m.triangles.size()) << "a normal per triangle per side";
  EXPECT_NE(obj.find("mtllib card.mtl"), std::string::npos) << "names its material file";
  EXPECT_NE(obj.find("usemtl front"), std::string::npos) << "front material";
  EXPECT_NE(obj.find("usemtl back"), std::string::npos) << "back material";
  std::ostringstream mtl;
  write_mtl(mtl);
  EXPECT_NE(mtl.str().find("newmtl back"), std::string::npos) << "the MTL defines both";
}

TEST(MeshIo, GltfIsAValidDocument) {
  const CardMesh m = box_mesh(60);
  std::ostringstream out;
  write_gltf(out, m);
  const auto doc = nlohmann::json::parse(out.str());
  EXPECT_EQ(doc["asset"]["version"], "2.0") << "glTF 2.0";
  ASSERT_EQ(doc["meshes"][0]["primitives"].size(), 2u) << "front and back primitives";
  EXPECT_EQ(doc["materials"].size(), 2u) << "two materials";
  const std::string uri = doc["buffers"][0]["uri"];
  const std::string prefix = "data:application/octet-stream;base64,";
  ASSERT_EQ(uri.rfind(prefix, 0), 0u) << "embedded buffer";
  const std::size_t b64 = uri.size() - prefix.size();
  const std::size_t bytes = doc["buffers"][0]["byteLength"];
  EXPECT_EQ(b64, (bytes + 2) / 3 * 4) << "base64 length matches byteLength";
  EXPECT_EQ(bytes, 2 * 2 * m.triangles.size() * 3 * 12) << "positions and normals, both sides";
  for (const auto& a : doc["accessors"]) {
    if (a.contains("min")) {
      for (std::size_t k = 0; k < 3; ++k)
        EXPECT_LE(a["min"][k].get<double>(), a["max"][k].get<double>()) << "POSITION bounds";
    }
  }
  // Y is up: at 90° the tallest point is the back wall's top, 0 < y.
  const auto& pos = doc["accessors"][0];
  EXPECT_GT(pos["max"][1].get<double>(), 0) << "the card stands up along +Y";
}

TEST(MeshIo, FrontFacesTheViewerAt90) {
  // The back wall's printed side faces the viewer (+Z in the Y-up frame).
  const CardMesh m = box_mesh(90);
  int toward = 0, away = 0;
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    const Point3 a = m.vertices[t[0]];
    if (m.face_kind[static_cast<std::size_t>(m.triangle_face[i])] != FaceKind::vertical) continue;
    // Card y is toward the viewer; a VFace's front normal is +y, i.e. +Z after the frame swap.
    const Point3 b = m.vertices[t[1]], c = m.vertices[t[2]];
    // Z component of (b'-a')×(c'-a') with P' = (x, z, y): the Y-up frame's toward-the-viewer axis.
    const double nz = (b.x_mm - a.x_mm) * (c.z_mm - a.z_mm) - (b.z_mm - a.z_mm) * (c.x_mm - a.x_mm);
    (nz > 0 ? toward : away)++;
  }
  EXPECT_GT(toward, 0) << "VFace triangles exist";
  EXPECT_EQ(away, 0) << "every VFace's printed side faces the viewer";
}

}  // namespace
}  // namespace popcut
