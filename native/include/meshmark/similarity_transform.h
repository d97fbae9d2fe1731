// meshmark: similarity transforms (rotation, uniform scaling, translation) - "distortionless"
// attacks of thesis sections 1.5.2 and 6.3.2.
#pragma once
#include "meshmark/mesh.h"
#include "meshmark/rng.h"
#include <Eigen/Core>

namespace meshmark {

// v' = s R v + t for every row v of V.
MatrixX3dR similarity_transform(const Eigen::Ref<const MatrixX3dR>& V, const Eigen::Matrix3d& R, double s,
                                const Eigen::Vector3d& t);

// Rotation by angle_deg degrees about axis (right-hand rule). MeshError for a zero or non-finite axis.
Eigen::Matrix3d axis_angle_rotation(const Eigen::Vector3d& axis, double angle_deg);

// Uniformly distributed rotation (Haar measure on SO(3)), Shoemake's quaternion method:
// u0, u1, u2 = 3 x rng.uniform01(); q = (sqrt(1-u0) sin 2pi u1, sqrt(1-u0) cos 2pi u1,
// sqrt(u0) sin 2pi u2, sqrt(u0) cos 2pi u2) as (x, y, z, w).
Eigen::Matrix3d random_rotation(Rng& rng);

}  // namespace meshmark
