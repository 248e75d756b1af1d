// The rotation of a case (`rotation`, io/case_file.h; docs/rotation.md) on its mesh bodies: the
// library's terms (fe/rotation.h) put where the model is built.
//
//   stiffness  before a body is reduced, its full stiffness becomes K(Ω) = K + Ω² (K_σ1 − S) by
//              the flags stress_stiffening (K_σ1) and spin_softening (S), so that every reduction
//              (Craig–Bampton, per nodal diameter of a sector) and every modal analysis of the
//              body is that of the spinning body at the case's speed. The prestress of K_σ1 is the
//              body's own linear static solution under its centrifugal load per unit Ω² with its
//              clamps, supports and equations (a cyclic sector: its nodal-diameter-0 problem, the
//              whole disk spinning): the contact forces do not enter it. A body that its own
//              constraints do not hold (a free damper, held by its contacts only) has no such
//              solution: it gets no stress stiffening, with a warning.
//   load       the centrifugal load Ω² M r⊥ on the reduced DOFs, a static (harmonic-0) load:
//              Tᵀ f with the Craig–Bampton basis T when the body has it; otherwise (a cyclic
//              sector, whose reductions keep no basis) its static condensation on the masters,
//              f_b − K_bi K_ii⁻¹ f_i (the masters' rows of Tᵀ f exactly), and 0 on the modal
//              coordinates. The reduced stiffness is block-diagonal between masters and modal
//              coordinates (craig_bampton.h), so the static response of the masters — the contact
//              displacements, hence the computed preload — is the same either way, and exact.
// Problems throw InvalidInput at the case key they come from (the rotation block).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "fe/cyclic.h"
#include "fe/dof_map.h"
#include "fe/material.h"
#include "fe/rotation.h"
#include "io/case_file.h"
#include "mesh/mesh.h"
#include "model/case_model.h"

namespace stickslip {

// rotation.axis, or the cyclic body's axis when the case gives none; InvalidInput at `rotation`
// when the case has no rotation.
RotationAxis case_rotation_axis(const CaseDefinition& definition);
// Ω, rad/s, of rotation.speed_rpm (0 without rotation).
double case_rotation_speed(const CaseDefinition& definition);

// A cyclic sector's boundary (resolve_case_bodies): its (low, high) node pairs, clamped full
// DOFs and symmetry; the static problems of the sector are its nodal-diameter-0 problems.
struct SectorBoundary {
  std::vector<std::pair<int, int>> pairs;
  std::vector<int> clamped_dofs;
  CyclicSymmetry symmetry;
};

// Adds Ω² (K_σ1 − S) (by the flags; nothing without rotation or at Ω = 0) to the full stiffness K
// of mesh body `name` (mesh, material, its constraints, M its full mass, both 3 num_nodes square).
// `sector`: non-null for a cyclic body.
void add_rotation_stiffness(const CaseDefinition& definition, const std::string& name,
                            const Mesh& mesh, const IsotropicMaterial& material,
                            const DofMap& constraints, const SectorBoundary* sector,
                            const SparseMatrix& M, SparseMatrix& K);

// The centrifugal load of body `body` on its reduced DOFs (size body.reduced.size(), N), as in the
// header. Needs body.K and body.M (InvalidInput at `rotation` when a stage command did not load
// them). `sector`: non-null for a cyclic body.
Eigen::VectorXd reduced_centrifugal_load(const CaseDefinition& definition, const PreparedBody& body,
                                         const SectorBoundary* sector);

}  // namespace stickslip
