// OBJ reading: vertices and the four face-corner forms, negative indices, skipped lines; refusals
// with the line number; a written mesh reads back.
#include "registration/obj_mesh.h"

#include <stdexcept>

#include <gtest/gtest.h>

#include "util/temporary_directory_testing.h"

namespace mocap {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    ParseObj(text, "m.obj");
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(ObjMesh, ReadsVerticesAndEveryCornerForm) {
  const ObjMesh mesh = ParseObj(
      "# a quad and a triangle\r\nmtllib x.mtl\no face\nv 0 0 0\nv 1.5 0 0 1.0\nv 1 1 0\nv 0 1e1 -2\n"
      "vt 0 0\nvn 0 0 1\ns off\nf 1/1/1 2/1/1 3//1 4\n\tf -1 -2 -3\nusemtl skin\n",
      "m.obj");
  ASSERT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(mesh.vertices[1], Eigen::Vector3d(1.5, 0, 0));
  EXPECT_EQ(mesh.vertices[3], Eigen::Vector3d(0, 10, -2));
  ASSERT_EQ(mesh.faces.size(), 2u);
  EXPECT_EQ(mesh.faces[0], (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(mesh.faces[1], (std::vector<int>{3, 2, 1}));
}

TEST(ObjMesh, RefusalsNameTheLine) {
  EXPECT_EQ(ErrorOf("v 0 0\n"), "m.obj: line 1: missing vertex coordinate");
  EXPECT_EQ(ErrorOf("v 0 0 0\nv 0 nan 0\n"), "m.obj: line 2: vertex coordinate 'nan' is not a finite number");
  EXPECT_EQ(ErrorOf("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"), "m.obj: line 4: face corner '4' names vertex 4 of 3 read so far");
  EXPECT_EQ(ErrorOf("v 0 0 0\nf 1 1\n"), "m.obj: line 2: a face needs at least 3 corners, this one has 2");
  EXPECT_EQ(ErrorOf("v 0 0 0\nf 0 1 1\n"), "m.obj: line 2: face corner '0' names vertex 0 of 1 read so far");
  EXPECT_EQ(ErrorOf("v 0 0 0\nf a 1 1\n"), "m.obj: line 2: face corner 'a' does not start with a vertex index");
  EXPECT_EQ(ErrorOf("# nothing\n"), "m.obj: no vertices ('v x y z' lines)");
  std::string many = "v 0 0 0\nf";
  for (int i = 0; i < 65; ++i) many += " 1";
  EXPECT_NE(ErrorOf(many).find("more than 64 corners"), std::string::npos);
}

TEST(ObjMesh, WriteThenRead) {
  const testing::TemporaryDirectory dir("obj_mesh");
  ObjMesh mesh;
  mesh.vertices = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.25, 0, 0), Eigen::Vector3d(0, 1, 0.5)};
  mesh.faces = {{0, 1, 2}};
  const std::vector<Eigen::Vector3d> moved = {Eigen::Vector3d(5, 0, 0), Eigen::Vector3d(6.25, 0, 0), Eigen::Vector3d(5, 1, 0.5)};
  WriteObj(mesh, dir.File("m.obj"), &moved);
  const ObjMesh back = ReadObj(dir.File("m.obj"));
  EXPECT_EQ(back.vertices, moved);
  EXPECT_EQ(back.faces, mesh.faces);
  EXPECT_THROW(ReadObj(dir.File("missing.obj")), std::runtime_error);
  const std::vector<Eigen::Vector3d> two(2);
  EXPECT_THROW(WriteObj(mesh, dir.File("n.obj"), &two), std::invalid_argument);
}

}  // namespace
}  // namespace mocap
