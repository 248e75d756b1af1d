// The linear model of an assembly whose contacts are stuck: every body's elements assembled into
// one K and M, each contact pair joined by a linear spring (kt in both tangential directions, kn
// along the normal, in the pair's frame), clamped node sets eliminated. Used for the modal study
// of the reference case and as the "infinite friction" linear reference.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/material.h"
#include "mesh/mesh.h"

namespace stickslip {

struct StuckContact {
  std::vector<std::pair<int, int>> pairs;  // node indices (A on body 1, B on body 2)
  Eigen::Vector3d normal;                  // out of A into B
  double k_t = 0.0;                        // N/m per pair, both tangential directions
  double k_n = 0.0;                        // N/m per pair
};

struct StuckAssembly {
  SparseMatrix K, M;  // free DOFs only (DofMap below)
  DofMap dofs;
};

StuckAssembly assemble_stuck(const Mesh& mesh, const IsotropicMaterial& material,
                             const AssemblyOptions& options,
                             const std::vector<StuckContact>& contacts,
                             const std::vector<std::string>& clamp_sets);

}  // namespace stickslip
