// A solid spinning at a constant speed Ω (rad/s) about a fixed axis, seen in the frame that turns
// with it (docs/rotation.md). With a the unit axis direction, p a point on it and
// r⊥(x) = (I − aaᵀ)(x − p) the position's part normal to the axis, the equations of small motion
// about the spinning state are
//
//   M ü + (K + Ω² K_σ1 − Ω² S) u = Ω² f_c1 + f(t),   f_c1 = M r⊥(nodes),
//
// (the Coriolis term 2Ω M_× u̇ is neglected, as CalculiX's *FREQUENCY does):
//   centrifugal load     f_c = Ω² f_c1, the body force ρ Ω² r⊥ integrated with the element shape
//                        functions. r⊥ is affine in x and every element is isoparametric
//                        (x = Σ N_b x_b exactly), so ρ r⊥(x) = Σ_b N_b ρ r⊥(x_b) and
//                        ∫ N_a ρ r⊥ dV = Σ_b M_ab r⊥(x_b): the consistent nodal force is exactly
//                        the mass matrix times the nodal r⊥ (for every element type, with the
//                        mass rule the matrix was built with), point masses included.
//   stress stiffening    K_σ (geometric stiffness of a prestress σ, Voigt order of material.h):
//                        K_σ(3a+d, 3b+d) = ∫ ∇N_aᵀ σ ∇N_b dV, the same for each direction d,
//                        integrated with the element's stiffness rule (element.h), σ the stress
//                        at those points (stress.h: D B u). The prestress of the centrifugal load
//                        is linear in Ω², so K_σ = Ω² K_σ1 with K_σ1 that of the solution at
//                        Ω = 1 rad/s.
//   spin softening       S = ∫ ρ Nᵀ (I − aaᵀ) N dV: the centrifugal force's change with the
//                        displacement (Ω² (I − aaᵀ) u per unit mass). The consistent mass is
//                        m_ab I₃ per node pair (element.h), so S(3a+d, 3b+e) = m_ab (I − aaᵀ)_de
//                        with m_ab = M(3a, 3b): built from the assembled mass.
// All matrices are 3 num_nodes square, global DOF 3 node + direction, full symmetric storage.
#pragma once

#include <span>

#include <Eigen/Core>

#include "core/types.h"
#include "fe/assembly.h"
#include "fe/material.h"
#include "mesh/mesh.h"

namespace stickslip {

struct RotationAxis {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();       // m, any point of the axis
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // non-zero; normalised where used
};
// Throws InvalidInput when the direction is zero or a component is not finite.
void validate(const RotationAxis& axis);

// Ω in rad/s of a speed in revolutions per minute.
double rpm_to_rad_per_s(double rpm);

// r⊥ at every node of the mesh, 3 num_nodes (DOF 3 node + d).
Eigen::VectorXd radial_positions(const Mesh& mesh, const RotationAxis& axis);

// f_c1 = M r⊥: the centrifugal nodal forces per unit Ω² (N s²), M the assembled consistent mass
// of the mesh (3 num_nodes square; InvalidInput otherwise).
Eigen::VectorXd centrifugal_force_per_speed_squared(const SparseMatrix& M, const Mesh& mesh,
                                                    const RotationAxis& axis);

// S of the header (kg), from the assembled mass M of the mesh: same size and 3 x 3 block pattern.
SparseMatrix spin_softening_matrix(const SparseMatrix& M, const RotationAxis& axis);

// K_σ of the header (N/m) for the prestress of the static displacement u (3 num_nodes, m) over
// the listed elements (empty: every element); the element formulation follows options.hex8 as in
// assemble_stiffness_mass. InvalidInput for a size mismatch or an element index out of range.
SparseMatrix geometric_stiffness(const Mesh& mesh, const IsotropicMaterial& material,
                                 const AssemblyOptions& options, const Eigen::VectorXd& u,
                                 std::span<const int> elements = {});

}  // namespace stickslip
