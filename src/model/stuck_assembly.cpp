#include "model/stuck_assembly.h"

#include "core/errors.h"
#include "core/frame.h"
#include "fe/springs.h"

namespace stickslip {

StuckAssembly assemble_stuck(const Mesh& mesh, const IsotropicMaterial& material,
                             const AssemblyOptions& options,
                             const std::vector<StuckContact>& contacts,
                             const std::vector<std::string>& clamp_sets) {
  SparseMatrix K, M;
  assemble_stiffness_mass(mesh, material, options, &K, &M);
  std::vector<NodePairSpring> springs;
  for (const StuckContact& c : contacts) {
    const Eigen::Matrix3d frame = frame_from_normal(c.normal);
    for (const auto& [a, b] : c.pairs) {
      springs.push_back(
          {.node_a = a, .node_b = b, .frame = frame, .k_t1 = c.k_t, .k_t2 = c.k_t, .k_n = c.k_n});
    }
  }
  add_springs(springs, K);
  std::vector<int> clamped;
  for (const std::string& name : clamp_sets) {
    const auto it = mesh.node_sets.find(name);
    if (it == mesh.node_sets.end()) throw InvalidInput("clamp: no node set named " + name);
    clamped.insert(clamped.end(), it->second.begin(), it->second.end());
  }
  StuckAssembly out;
  out.dofs = DofMap::from_nodes(mesh.num_nodes(), clamped);
  out.K = out.dofs.restrict(K);
  out.M = out.dofs.restrict(M);
  return out;
}

}  // namespace stickslip
