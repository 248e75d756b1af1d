// Concentrated nodal forces (N, global axes) and the global force vector they make:
//   f(3*node + d) = sum of force(d) over the NodalForce entries of that node (repeats add up).
#pragma once

#include <span>

#include <Eigen/Core>

namespace stickslip {

struct NodalForce {
  int node = 0;  // node index (not id)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

// Vector of size 3 num_nodes; InvalidInput if a node index is out of range.
Eigen::VectorXd nodal_force_vector(int num_nodes, std::span<const NodalForce> forces);
// Adds the forces into an existing vector f (size 3 num_nodes).
void add_nodal_forces(std::span<const NodalForce> forces, Eigen::VectorXd& f);

}  // namespace stickslip
