// Linear springs between node pairs (stuck contact, elastic joints) in a local frame.
//
// Frame R (3x3) has rows t1, t2, n (unit, orthonormal; n points out of body A into body B, as
// for contact in docs/conventions.md). With x_A, x_B the nodal displacements, the spring's relative
// displacement is u = R (x_A - x_B) and its force in local axes k u, k = diag(k_t1, k_t2, k_n)
// (N/m). The force on B is +R^T k u, on A its negative (docs/conventions.md's sign convention). The
// stiffness this adds to K (internal force = K x) is, with S = R^T k R:
//   K_AA += S,  K_BB += S,  K_AB = K_BA -= S.
// node_b = -1 ties node_a to the ground (x_B = 0): only K_AA += S.
#pragma once

#include <span>

#include <Eigen/Core>

#include "core/types.h"

namespace stickslip {

struct NodePairSpring {
  int node_a = 0;                                       // node index
  int node_b = -1;                                      // node index, or -1 = ground
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  // rows t1, t2, n
  double k_t1 = 0.0, k_t2 = 0.0, k_n = 0.0;             // N/m, >= 0
};

// 6x6 stiffness of one spring in the DOF order [x_A (3), x_B (3)].
Eigen::Matrix<double, 6, 6> spring_stiffness(const NodePairSpring& spring);

// Adds the springs to K (square, 3 num_nodes, both triangles stored, as assembled by
// fe/assembly.h); the sparsity pattern grows where A-B coupling is new. Throws InvalidInput
// naming springs[i] for an out-of-range node, a = b, a non-orthonormal frame
// (|R R^T - I| > 1e-9) or a negative stiffness.
void add_springs(std::span<const NodePairSpring> springs, SparseMatrix& K);

}  // namespace stickslip
