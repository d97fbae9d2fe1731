// C++ tests of mesh I/O: round trips and errors (the Python suite covers every format in depth).
#include "meshmark/error.h"
#include "meshmark/read_mesh.h"
#include "meshmark/write_mesh.h"

#include <gtest/gtest.h>
#include <cstdio>
#include <fstream>

using namespace meshmark;

namespace {
std::string tmp(const std::string& name) { return ::testing::TempDir() + "meshmark_" + name; }
}

TEST(IO, DoublePlyRoundTripIsExact) {
  MatrixX3dR V(4, 3);
  V << 0.1, 0.2, 0.3, 1.0 / 3, 2.0 / 7, 1e-17, -5.5, 7.25, 1e10, 0, 1, 2;
  MatrixX3iR T(2, 3);
  T << 0, 1, 2, 0, 2, 3;
  const Polygons P = Polygons::from_triangles(T);
  for (const char* ext : {"ply", "obj", "off"}) {
    const std::string path = tmp(std::string("rt.") + ext);
    write_mesh(path, V, P);
    const MeshFile f = read_mesh(path);
    EXPECT_EQ(f.V, V) << ext;
    EXPECT_EQ(f.P.indices, P.indices) << ext;
    std::remove(path.c_str());
  }
}

TEST(IO, MissingAndUnknownFilesGiveMeshError) {
  EXPECT_THROW(read_mesh("/nonexistent/file.obj"), MeshError);
  const std::string path = tmp("x.xyz");
  std::ofstream(path) << "hello";
  try {
    read_mesh(path);
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported format"), std::string::npos);
  }
}

TEST(IO, SharedBunnyCounts) {
  const MeshFile f = read_mesh(std::string(MESHMARK_SHARED_MESHES) + "/classic/bunny.obj");
  EXPECT_EQ(f.V.rows(), 35947);
  EXPECT_EQ(f.P.n_faces(), 69451);
}
