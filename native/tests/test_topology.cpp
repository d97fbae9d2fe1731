// C++ unit tests of the mesh model: hand-computed answers on tiny meshes.
#include "meshmark/boundary.h"
#include "meshmark/connected_components.h"
#include "meshmark/error.h"
#include "meshmark/manifold.h"
#include "meshmark/mesh_info.h"
#include "meshmark/triangulate.h"
#include "meshmark/unique_edges.h"
#include "meshmark/validate.h"
#include "meshmark/vertex_adjacency.h"
#include "meshmark/weld_vertices.h"

#include <gtest/gtest.h>

using namespace meshmark;

namespace {
// A unit square split into two triangles, plus an isolated (unreferenced) vertex 4.
MatrixX3dR square_V() {
  MatrixX3dR V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 5, 5, 5;
  return V;
}
Polygons square_P() {
  MatrixX3iR T(2, 3);
  T << 0, 1, 2, 0, 2, 3;
  return Polygons::from_triangles(T);
}
// A closed tetrahedron.
Polygons tetra_P() {
  MatrixX3iR T(4, 3);
  T << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  return Polygons::from_triangles(T);
}
}  // namespace

TEST(UniqueEdges, SquareHasFiveEdgesFourOnBoundary) {
  const EdgeList E = unique_edges(5, square_P());
  ASSERT_EQ(E.E.rows(), 5);
  // sorted lexicographically: (0,1) (0,2) (0,3) (1,2) (2,3)
  EXPECT_EQ(E.E(0, 0), 0); EXPECT_EQ(E.E(0, 1), 1);
  EXPECT_EQ(E.E(1, 1), 2); EXPECT_EQ(E.face_count[1], 2);  // the diagonal is interior
  EXPECT_EQ(boundary_edges(E).size(), 4);
  EXPECT_EQ(boundary_vertices(5, E).size(), 4);
}

TEST(UniqueEdges, QuadKeepsItsFourSides) {
  Polygons P;
  P.indices.resize(4);
  P.indices << 0, 1, 2, 3;
  P.offsets.resize(2);
  P.offsets << 0, 4;
  const EdgeList E = unique_edges(4, P);
  EXPECT_EQ(E.E.rows(), 4);  // no diagonal
}

TEST(Adjacency, CsrIsSortedAndSymmetric) {
  const EdgeList E = unique_edges(5, square_P());
  const Adjacency A = vertex_adjacency(5, E.E);
  ASSERT_EQ(A.ptr.size(), 6);
  EXPECT_EQ(A.ptr[1] - A.ptr[0], 3);  // vertex 0: 1,2,3
  EXPECT_EQ(A.nbr[A.ptr[0]], 1);
  EXPECT_EQ(A.nbr[A.ptr[0] + 2], 3);
  EXPECT_EQ(A.ptr[5] - A.ptr[4], 0);  // isolated vertex
  EXPECT_EQ(valence(5, E.E)[2], 3);
}

TEST(Components, UnreferencedVertexIsLabelledMinusOne) {
  const EdgeList E = unique_edges(5, square_P());
  const Components C = connected_components(5, E.E);
  EXPECT_EQ(C.count, 1);
  EXPECT_EQ(C.label[4], -1);
  EXPECT_EQ(C.label[0], 0);
}

TEST(Manifold, BowtieVertexIsNonManifold) {
  MatrixX3iR T(2, 3);
  T << 0, 1, 2, 0, 3, 4;  // two triangles sharing only vertex 0
  const Polygons P = Polygons::from_triangles(T);
  const ManifoldReport R = manifold_report(5, P, unique_edges(5, P));
  EXPECT_EQ(R.non_manifold_edges, 0);
  EXPECT_EQ(R.non_manifold_vertices, 1);
}

TEST(Manifold, ThreeFacesOnAnEdge) {
  MatrixX3iR T(3, 3);
  T << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const Polygons P = Polygons::from_triangles(T);
  const ManifoldReport R = manifold_report(5, P, unique_edges(5, P));
  EXPECT_EQ(R.non_manifold_edges, 1);
  EXPECT_FALSE(R.manifold());
}

TEST(MeshInfo, TetrahedronIsClosedGenusZero) {
  MatrixX3dR V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  const MeshInfo I = mesh_info(V, tetra_P());
  EXPECT_EQ(I.n_edges, 6);
  EXPECT_TRUE(I.closed);
  EXPECT_TRUE(I.manifold);
  EXPECT_EQ(I.euler_characteristic, 2);
  EXPECT_NEAR(I.mean_edge_length, (3 * 1.0 + 3 * std::sqrt(2.0)) / 6, 1e-12);
  EXPECT_NEAR(I.surface_area, 1.5 + std::sqrt(3.0) / 2, 1e-12);
}

TEST(Triangulate, ConvexPentagonIsFanFromCornerZero) {
  MatrixX3dR V(5, 3);
  for (int i = 0; i < 5; ++i) V.row(i) << std::cos(2 * M_PI * i / 5), std::sin(2 * M_PI * i / 5), 0;
  Polygons P;
  P.indices.resize(5);
  P.indices << 0, 1, 2, 3, 4;
  P.offsets.resize(2);
  P.offsets << 0, 5;
  const Triangulation T = triangulate(V, P);
  ASSERT_EQ(T.T.rows(), 3);
  EXPECT_EQ(T.T(0, 0), 0); EXPECT_EQ(T.T(0, 1), 1); EXPECT_EQ(T.T(0, 2), 2);
  EXPECT_EQ(T.T(2, 0), 0); EXPECT_EQ(T.T(2, 1), 3); EXPECT_EQ(T.T(2, 2), 4);
}

TEST(Triangulate, ConcaveQuadUsesTheInsideDiagonal) {
  // Dart: corner 2 is reflex, so the 0-2 diagonal is inside and 1-3 is outside.
  MatrixX3dR V(4, 3);
  V << 0, 0, 0, 2, -1, 0, 0.5, 0, 0, 2, 1, 0;
  Polygons P;
  P.indices.resize(4);
  P.indices << 1, 2, 3, 0;  // start at a convex corner whose 0-2 diagonal (1-3) lies outside
  P.offsets.resize(2);
  P.offsets << 0, 4;
  const Triangulation T = triangulate(V, P);
  ASSERT_EQ(T.T.rows(), 2);
  // Both triangles must use the diagonal 0-2 (vertex ids 0 and 2), never 1-3.
  for (int t = 0; t < 2; ++t) {
    const bool has0 = (T.T.row(t).array() == 0).any(), has2 = (T.T.row(t).array() == 2).any();
    EXPECT_TRUE(has0 && has2);
  }
}

TEST(Validate, MessagesNameTheCulprit) {
  MatrixX3dR V = square_V();
  Polygons P = square_P();
  P.indices[4] = 9;
  try {
    validate_mesh(V, P);
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("face 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("vertex 9"), std::string::npos) << e.what();
  }
  V(3, 1) = std::nan("");
  EXPECT_THROW(validate_vertices(V), MeshError);
}

namespace {
PolygonsView view(const Polygons& P) { return PolygonsView{P.indices.data(), P.n_corners(), P.offsets.data(), P.n_faces()}; }
}  // namespace

TEST(WeldVertices, SplitSquareWeldsBackAndKeepsFirstOccurrenceOrder) {
  // the square's two triangles stored apart (non-indexed), -0.0 for one zero, plus a collapsed face
  MatrixX3dR V(7, 3);
  V << 0, 0, 0, 1, 0, 0, 1, 1, 0, -0.0, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 0;
  Polygons P;
  P.indices.resize(9);
  P.indices << 0, 1, 2, 3, 4, 5, 1, 6, 2;  // the last face welds to (1, 1, 2): dropped
  P.offsets.resize(4);
  P.offsets << 0, 3, 6, 9;
  const Welded W = weld_vertices(V, view(P));
  ASSERT_EQ(W.first.size(), 4);
  EXPECT_EQ(W.first[0], 0); EXPECT_EQ(W.first[1], 1); EXPECT_EQ(W.first[2], 2); EXPECT_EQ(W.first[3], 5);
  const int expect_map[7] = {0, 1, 2, 0, 2, 3, 1};
  for (int i = 0; i < 7; ++i) EXPECT_EQ(W.map[i], expect_map[i]) << i;
  ASSERT_EQ(W.offsets.size(), 3);
  ASSERT_EQ(W.indices.size(), 6);
  const int expect_idx[6] = {0, 1, 2, 0, 2, 3};
  for (int c = 0; c < 6; ++c) EXPECT_EQ(W.indices[c], expect_idx[c]) << c;
  EXPECT_EQ(W.face[0], 0); EXPECT_EQ(W.face[1], 1);
}

TEST(WeldVertices, QuadLosingACornerBecomesATriangle) {
  MatrixX3dR V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  Polygons P;
  P.indices.resize(5);
  P.indices << 0, 1, 2, 3, 4;  // a pentagon with corners 1 and 2 coincident -> quad (0, 1, 2, 3) welded
  P.offsets.resize(2);
  P.offsets << 0, 5;
  const Welded W = weld_vertices(V, view(P));
  ASSERT_EQ(W.indices.size(), 4);
  EXPECT_EQ(W.indices[0], 0); EXPECT_EQ(W.indices[1], 1); EXPECT_EQ(W.indices[2], 2); EXPECT_EQ(W.indices[3], 3);
}

TEST(WeldVertices, NothingToMergeLeavesTheFacesToTheCaller) {
  const Welded W = weld_vertices(square_V(), view(square_P()));
  ASSERT_EQ(W.first.size(), 5);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(W.map[i], i);
  EXPECT_EQ(W.indices.size(), 0);
  EXPECT_EQ(W.offsets.size(), 0);
}
