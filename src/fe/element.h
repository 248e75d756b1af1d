// Element kernels for linear elastic 3D solids: stiffness, consistent mass, strain operators.
//
// Element DOF order: 3*a + d for local node a (CalculiX/Abaqus node order, see mesh/mesh.h) and
// direction d (x, y, z). X is the 3 x nen matrix of node coordinates (m); nen =
// nodes_per_element(type). Kernels see coordinates and a material, never a mesh.
//
//   K_e = integral of B^T D B dV  (N/m),   M_e = integral of rho N^T N dV  (kg)
//
// Integration (natural coordinates: hexahedra [-1,1]^3; tetrahedra xi, eta, zeta >= 0,
// xi + eta + zeta <= 1 with N1 = 1 - xi - eta - zeta, N2 = xi, N3 = eta, N4 = zeta; wedges
// (xi, eta) in that triangle, L = (1 - xi - eta, xi, eta), zeta in [-1, 1], nodes 1-3 at
// zeta = -1 and 4-6 at +1, C3D15's mid-edge nodes 7-9 on 1-2, 2-3, 3-1, 10-12 on 4-5, 5-6,
// 6-4, 13-15 on 1-4, 2-5, 3-6):
//   type     stiffness rule            exact mass rule (MassIntegration::kExact)
//   C3D8     2x2x2 Gauss               2x2x2 Gauss
//   C3D8I    2x2x2 Gauss + 9 incompatible modes, condensed       2x2x2 Gauss
//   C3D8B    2x2x2 Gauss, volumetric strain = its element mean   2x2x2 Gauss
//   C3D20    3x3x3 Gauss               3x3x3 Gauss
//   C3D20R   2x2x2 Gauss               3x3x3 Gauss
//   C3D4     1 point                   4-point (degree 2)
//   C3D10    4-point (degree 2)        64-point collapsed Gauss (degree 5)
//   C3D6     2 points: triangle centroid x 2 Gauss in zeta     7-point triangle (deg. 5) x 3
//   C3D15    9 points: 3 triangle points (1/6, 1/6), (2/3, 1/6), (1/6, 2/3) x 3 Gauss
//                                      7-point triangle (deg. 5) x 4 Gauss
//   C3D5     2x2x2 Gauss               3x3x3 Gauss
//   C3D13    3x3x3 Gauss               4x4x4 Gauss
//   C3D8R    1 point + hourglass stiffness (below)               2x2x2 Gauss
// MassIntegration::kStiffnessRule integrates the mass with the stiffness rule, as CalculiX does
// (identical for C3D8, C3D8I, C3D8B, C3D20, C3D13; rank-deficient for C3D20R, C3D4, C3D6 and
// C3D8R).
// The wedge rules are CalculiX 2.20's (its frequencies of wedge meshes reproduced to 1e-11,
// tests/validation/calculix_modal_test.cpp). C3D6's two points on the centroid leave one spurious
// zero-energy mode on a single free element, constrained in a mesh.
// Hexahedron Gauss points are ordered xi fastest, then eta, then zeta.
//
// C3D5 (5-node pyramid) is the 8-node brick with its top face collapsed onto the apex, as ANSYS
// defines SOLID185's pyramid (M = N = O = P) and as a C3D8 with nodes 5-8 equal is in CalculiX:
// base nodes 1-4 at zeta = -1 in the brick's order (their right-hand normal points to the apex),
// apex 5 at natural coordinates (0, 0, 1); N_a = (1 ± xi)(1 ± eta)(1 - zeta)/8 on the base,
// N_5 = (1 + zeta)/2. Linear on each triangular face (conforming with C3D4 and C3D6 triangles),
// bilinear on the base (conforming with C3D8 faces); det J = 0 at the apex, which no integration
// point reaches. Exact mass rule 3x3x3, so the mass is ρV exactly for a planar base.
//
// C3D13 (13-node pyramid) is the 20-node brick with its top face collapsed onto the apex, as
// CalculiX computes a C3D20 whose nodes 5-8 and 13-16 are one node and as ANSYS stores SOLID186's
// pyramid shape (M = N = O = P = U = V = W = X): base corners 1-4 and apex 5 as C3D5's, mid-edge
// nodes 6-9 on the base edges 1-2, 2-3, 3-4, 4-1 (the brick's 9-12) and 10-13 on the lateral
// edges 1-5, 2-5, 3-5, 4-5 (the brick's 17-20, natural coordinates (±1, ±1, 0)); VTK's
// quadratic pyramid order. Each function is the sum of the brick functions it stands for, so
// K and M are exactly those of the collapsed C3D20 under the same rule. Quadratic on the base
// (conforming with C3D20 faces); on a triangular face the trace is the collapsed 8-node
// serendipity quadrilateral, not the 6-node triangle of a C3D10 face (the two agree at the six
// nodes and along the edges, not inside: the pair is not conforming, as in CalculiX and ANSYS
// meshes that mix them). Linear fields are reproduced exactly; of the quadratic ones (axis z
// from the base to the apex of a right pyramid) z², xz, yz and xy are, x² and y² are not (the
// collapsed map is not affine: x² needs ξ²ζ², outside the brick's space).
//
// C3D8R (CalculiX 2.20's reduced-integration brick, after Flanagan and Belytschko 1981): the
// uniform-strain part V B̄ᵀ D B̄, B̄ the strain operator of the mean gradients
// b̄_ja = (1/V) ∫ ∂N_a/∂x_j dV, plus CalculiX's hourglass stiffness on each direction alike,
//   K_hg(3a+d, 3b+d) = c Σ_k γ_ka γ_kb,  c = 0.0005 E Σ_ja (∂V/∂x_ja)² / V  (N/m),
// γ_k = h_k − Σ_j b̄_j (x_jᵀ h_k) for the four hourglass base vectors h_k = ηζ, ξζ, ξη, ξηζ at the
// nodes (x_j: the nodes' coordinates in direction j): orthogonal to every linear field, so rigid
// motions and linear fields cost no hourglass energy. ccx 2.20 subtracts the z term only
// (γ_k = h_k − b̄_z (zᵀ h_k)): identical on parallelepipeds (x_jᵀ h_k = 0 there), but on a
// distorted brick its hourglass stiffness resists rigid rotations (‖K r‖ = 6e-3 ‖K‖ on the
// distorted brick of tests/validation/c3d8r_calculix_test.cpp), which stickslip does not copy.
// The factor 0.0005 is CalculiX's, fixed. Strains and stresses: B̄, at the centre. Exact mass:
// the C3D8 consistent mass; MassIntegration::kStiffnessRule: CalculiX's one-point mass,
// M_e(3a+d, 3b+d) = ρV/64 for every a, b (V exact).
//
// C3D8I (Wilson-Taylor incompatible modes): displacement u = sum N_a u_a + sum_k P_k alpha_k with
// P = (1 - xi^2, 1 - eta^2, 1 - zeta^2) times three internal 3-vectors alpha. Following Taylor,
// Beresford and Wilson (1976), the physical derivatives of P use the Jacobian J0 at the element
// centre and are scaled by det J0 / det J, so that integral(grad P dV) = 0 and the element passes
// the patch test. The 9 internal DOFs are condensed statically:
//   K_e = K_uu - K_ua K_aa^-1 K_au,   alpha = -K_aa^-1 K_au u_e.
// The C3D8I mass is the C3D8 consistent mass (the incompatible modes carry no mass). For linear
// elasticity this is also ANSYS SOLID185 with KEYOPT(2)=3 (9 enhanced strain modes, Simo and
// Rifai), which the CDB reader maps to C3D8I.
// CalculiX 2.20's C3D8I uses J0 but omits the det J0 / det J factor: identical on
// parallelepipeds, different (and failing the patch test) on distorted bricks.
//
// C3D8B (B-bar, ANSYS SOLID185 with KEYOPT(2)=0, its "selective reduced integration"): the
// volumetric strain at each integration point is replaced by the element's mean volumetric strain
// (mean dilatation, Hughes 1980): B̄ = B + (1/3) m (b̄ - b)ᵀ with m = [1 1 1 0 0 0]ᵀ, b = mᵀB
// the divergence row at the point and b̄ its volume average over the element. Then
//   K_e = Σ_g w det J B̄ᵀ D B̄ = (fully integrated deviatoric part) + κ V b̄ b̄ᵀ,  κ = λ + 2μ/3,
// free of volumetric locking as ν → 1/2 (shear locking in bending stays, as in C3D8). Mass and
// strain operators at the 8 Gauss points (B̄) as above. CalculiX has no such element.
//
// A non-positive Jacobian determinant at an integration point throws InvalidInput.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "fe/material.h"
#include "mesh/mesh.h"

namespace stickslip {

enum class MassIntegration {
  kExact,          // the exact rule of the table above (default)
  kStiffnessRule,  // CalculiX's choice: the stiffness rule
};

// K_e, 3nen x 3nen, symmetric. K is resized if needed (no allocation when already sized).
void element_stiffness(ElementType type, const Eigen::Matrix3Xd& X,
                       const IsotropicMaterial& material, Eigen::MatrixXd& K);

// Consistent M_e, 3nen x 3nen, symmetric; M_e(3a+d, 3b+e) = 0 for d != e.
void element_mass(ElementType type, const Eigen::Matrix3Xd& X, double density, Eigen::MatrixXd& M,
                  MassIntegration rule = MassIntegration::kExact);

// Volume (m^3) integrated with the exact mass rule of the table above.
double element_volume(ElementType type, const Eigen::Matrix3Xd& X);

// Why the element's geometry cannot be integrated, or "" when it can: a coordinate that is not
// finite, or det J <= 0 at a point of its stiffness or mass rules (the kernels above would throw
// there), described as flat (|det J| <= kFlatElementTolerance |J_1| |J_2| |J_3| everywhere, J_i
// the rows of J: independent of size and aspect ratio), inverted
// (det J < 0 everywhere: nodes in mirrored order) or distorted (det J changes sign: a misplaced
// mid-side node or corner). For the mesh readers, which add the file and the element's line.
std::string element_shape_problem(ElementType type, const Eigen::Matrix3Xd& X);
// Relative |det J| below which an element counts as flat rather than inverted or distorted.
inline constexpr double kFlatElementTolerance = 1e-12;

// --- Reference element ---

// Natural coordinates of the nodes, 3 x nen.
Eigen::Matrix3Xd natural_node_coordinates(ElementType type);
// Natural coordinates (3 x ngp) and weights of the stiffness rule of the table above.
Eigen::Matrix3Xd integration_points(ElementType type);
Eigen::VectorXd integration_weights(ElementType type);
// Shape functions N (nen) and their natural derivatives dN (3 x nen, row i = d/dxi_i) at xi.
void shape_functions(ElementType type, const Eigen::Vector3d& xi, Eigen::VectorXd& N,
                     Eigen::Matrix3Xd& dN);

// Strain operators at the stiffness-rule integration points: B[g] (6 x 3nen) maps the element's
// nodal displacements to the Voigt strain (material.h's order, engineering shears) at point g.
// For C3D8I the condensed incompatible modes are included (B = B_u - B_a K_aa^-1 K_au), so the
// material is needed; for the other types it is unused.
void element_strain_operators(ElementType type, const Eigen::Matrix3Xd& X,
                              const IsotropicMaterial& material, std::vector<Eigen::MatrixXd>& B);

}  // namespace stickslip
