// Local frames for contact pairs and springs: a 3x3 rotation R whose rows are (t1, t2, n), unit
// and orthonormal, right-handed (t1 x t2 = n). Local components of a global vector v: R v.
#pragma once

#include <Eigen/Core>

namespace stickslip {

// The frame with normal n (normalised here; must be non-zero, else InvalidInput). Without a hint,
// t1 is the global axis least aligned with n, made orthogonal to n (ties: lowest axis index), so
// n = +x gives t1 = +y, t2 = +z and n = +z gives t1 = +x, t2 = +y. With a hint, t1 is the hint
// made orthogonal to n (InvalidInput if the hint is parallel to n). t2 = n x t1.
Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& normal);
Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& normal, const Eigen::Vector3d& t1_hint);

}  // namespace stickslip
