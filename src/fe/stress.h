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
// Complex displacements (harmonic amplitudes, DESIGN.md) give complex stress amplitudes: the
// map is real-linear, so real and imaginary parts are processed separately.
#pragma once

#include <complex>
#include <span>

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

}  // namespace stickslip
