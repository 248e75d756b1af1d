// Linear elastic stresses from nodal displacements (Voigt order of material.h:
// s_xx, s_yy, s_zz, s_xy, s_xz, s_yz; Pa).
//
//   integration points: s_g = D B_g u_e  at the stiffness-rule points of element.h (order there);
//                       for C3D8I B_g includes the condensed incompatible modes.
//   nodes of an element: polynomial extrapolation of the integration-point values,
//                       s_nodes = E s_points, E (nen x ngp) from the basis that interpolates the
//                       points exactly: 2x2x2 -> {1, xi, eta, zeta, xi eta, eta zeta, zeta xi,
//                       xi eta zeta}; 3x3x3 -> triquadratic Lagrange; tetrahedron 4 points ->
//                       linear; 1 point -> constant.
//   mesh nodes:         unweighted average over the listed elements that contain the node
//                       (nodes in no listed element get 0).
// u_e is the element's displacement vector (DOF 3a + d); u the global one (DOF 3 node + d).
// Complex displacements (harmonic amplitudes, docs/conventions.md) give complex stress amplitudes:
// the map is real-linear, so real and imaginary parts are processed separately.
#pragma once

#include <complex>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fe/assembly.h"
#include "fe/material.h"
#include "mesh/mesh.h"

namespace stickslip {

using StressMatrix = Eigen::Matrix<double, 6, Eigen::Dynamic>;
using ComplexStressMatrix = Eigen::Matrix<std::complex<double>, 6, Eigen::Dynamic>;

// 6 x ngp.
StressMatrix element_stress_at_integration_points(ElementType type, const Eigen::Matrix3Xd& X,
                                                  const IsotropicMaterial& material,
                                                  const Eigen::VectorXd& ue);
ComplexStressMatrix element_stress_at_integration_points(ElementType type,
                                                         const Eigen::Matrix3Xd& X,
                                                         const IsotropicMaterial& material,
                                                         const Eigen::VectorXcd& ue);

// nen x ngp extrapolation matrix E of the header comment.
Eigen::MatrixXd stress_extrapolation_matrix(ElementType type);

// 6 x nen.
StressMatrix element_stress_at_nodes(ElementType type, const Eigen::Matrix3Xd& X,
                                     const IsotropicMaterial& material, const Eigen::VectorXd& ue);
ComplexStressMatrix element_stress_at_nodes(ElementType type, const Eigen::Matrix3Xd& X,
                                            const IsotropicMaterial& material,
                                            const Eigen::VectorXcd& ue);

// 6 x num_nodes, averaged. The element formulation follows options.hex8 (as in assembly).
// Empty `elements` = all elements of the mesh. u has size 3 num_nodes (else InvalidInput).
StressMatrix nodal_stress(const Mesh& mesh, const IsotropicMaterial& material,
                          const AssemblyOptions& options, const Eigen::VectorXd& u,
                          std::span<const int> elements = {});
ComplexStressMatrix nodal_stress(const Mesh& mesh, const IsotropicMaterial& material,
                                 const AssemblyOptions& options, const Eigen::VectorXcd& u,
                                 std::span<const int> elements = {});

// The map u -> nodal_stress(u) as a sparse operator, built once: S = G u, S of size 6 num_nodes
// (row 6 n + i = component i at node n, i.e. a StressMatrix's storage), u of size 3 num_nodes.
// G is stored as 6 x 3 blocks (node n, neighbour node m) for every pair of nodes sharing one of
// the listed elements: 27 blocks per interior node of a hexahedral mesh, 144 bytes each (at
// 318k nodes: 1.2 GB). Applying G costs one pass over the blocks for all columns at once
// (e.g. real and imaginary parts of every harmonic), with no per-element work; the result equals
// nodal_stress's to round-off. Same options, elements and InvalidInput rules as nodal_stress.
class NodalStressOperator {
 public:
  NodalStressOperator(const Mesh& mesh, const IsotropicMaterial& material,
                      const AssemblyOptions& options, std::span<const int> elements = {});
  // U: 3 num_nodes x m real; returns 6 num_nodes x m. num_threads: 0 = one per hardware thread.
  Eigen::MatrixXd apply(const Eigen::MatrixXd& U, int num_threads = 0) const;
  // Complex amplitudes: column j of x (3 num_nodes x nh) -> element j (6 x num_nodes), real and
  // imaginary parts in the same pass.
  std::vector<ComplexStressMatrix> apply(const Eigen::MatrixXcd& x, int num_threads = 0) const;
  int num_nodes() const { return static_cast<int>(row_offsets_.size()) - 1; }
  Eigen::Index num_blocks() const { return static_cast<Eigen::Index>(block_nodes_.size()); }

 private:
  std::vector<Eigen::Index> row_offsets_;  // num_nodes + 1, into block_nodes_
  std::vector<int> block_nodes_;           // neighbour node of each block (sorted per row)
  std::vector<double> blocks_;             // 18 per block, 6 x 3 column-major
};

}  // namespace stickslip
