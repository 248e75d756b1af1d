#include "fe/loads.h"

#include <string>

#include "core/errors.h"
#include "core/types.h"

namespace stickslip {

void add_nodal_forces(std::span<const NodalForce> forces, Eigen::VectorXd& f) {
  if (f.size() % kDofsPerNode != 0) {
    throw InvalidInput("nodal forces: vector size " + std::to_string(f.size()) +
                       " is not a multiple of 3");
  }
  const int num_nodes = static_cast<int>(f.size() / kDofsPerNode);
  for (size_t i = 0; i < forces.size(); ++i) {
    const NodalForce& nf = forces[i];
    if (nf.node < 0 || nf.node >= num_nodes) {
      throw InvalidInput("nodal forces[" + std::to_string(i) + "]: node index " +
                         std::to_string(nf.node) + " out of range [0, " +
                         std::to_string(num_nodes) + ")");
    }
    f.segment<3>(dof_of(nf.node, 0)) += nf.force;
  }
}

Eigen::VectorXd nodal_force_vector(int num_nodes, std::span<const NodalForce> forces) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(kDofsPerNode * static_cast<Eigen::Index>(num_nodes));
  add_nodal_forces(forces, f);
  return f;
}

}  // namespace stickslip
