// meshmark: one level of 1-to-4 subdivision of a triangle mesh (midpoint or Loop).
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/unique_edges.h"

namespace meshmark {

struct SubdividedMesh {
  MatrixX3dR V;  // original n vertices (same ids; moved by Loop) then one vertex per unique edge
  MatrixX3iR T;  // 4 t triangles: face f -> rows 4f..4f+3: (a,m0,m2), (b,m1,m0), (c,m2,m1), (m0,m1,m2)
                 // with m0 = (a,b), m1 = (b,c), m2 = (c,a); edge e gets vertex n + e (unique_edges order)
};

// Midpoint (linear) subdivision: original vertices kept, edge points at the edge midpoints.
SubdividedMesh midpoint_subdivide(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

// Loop subdivision (Loop 1987; the masks of CGAL's Loop_mask_3):
//  * edge with two triangles: 3/8 (a + b) + 1/8 (c + d); other edges: (a + b) / 2;
//  * vertex with only two-triangle edges, valence k: (1 - k beta) v + beta sum(neighbours),
//    beta = (5/8 - (3/8 + 1/4 cos(2 pi / k))^2) / k;
//  * vertex on exactly two boundary edges: 3/4 v + 1/8 (p + q); other vertices (non-manifold
//    edges, corners) do not move.
SubdividedMesh loop_subdivide(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Ref<const MatrixX3iR>& T);

}  // namespace meshmark
