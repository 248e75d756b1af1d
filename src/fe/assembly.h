// Assembly of the global stiffness K (N/m) and consistent mass M (kg) of a linear elastic solid
// mesh: K = sum_e A_e^T K_e A_e, M = sum_e A_e^T M_e A_e (element kernels: fe/element.h).
//
// Sizes: both are 3 num_nodes x 3 num_nodes, global DOF 3*node + direction (core/types.h), and
// are stored with BOTH triangles (full symmetric storage), compressed, column-major. The sparsity
// pattern is the node adjacency of the assembled elements in 3x3 blocks (explicit zeros may be
// stored); a node that belongs to no assembled element has empty rows and columns.
#pragma once

#include <span>

#include "core/types.h"
#include "fe/element.h"
#include "fe/material.h"
#include "mesh/mesh.h"

namespace stickslip {

struct AssemblyOptions {
  enum class Hex8Formulation {
    kAsMesh,        // honour C3D8 vs C3D8I as the mesh says
    kFull,          // every 8-node hexahedron as C3D8 (full 2x2x2 integration)
    kIncompatible,  // every 8-node hexahedron as C3D8I (incompatible modes)
  };
  Hex8Formulation hex8 = Hex8Formulation::kAsMesh;
  // Rule for the consistent mass (fe/element.h); kStiffnessRule reproduces CalculiX's matrices.
  MassIntegration mass_integration = MassIntegration::kExact;
  // Threads for the element loop (element colouring, race-free); 1 = serial, 0 = one per
  // hardware thread. Results equal the serial ones up to the order of summation.
  int num_threads = 0;
};

// Throws InvalidInput naming the field, its value and the rule it broke.
void validate(const AssemblyOptions& options);

// The element type actually integrated for a mesh element of type `type` under `options`.
ElementType effective_element_type(ElementType type, const AssemblyOptions& options);

// Assembles every element of the mesh, then its discrete springs and point masses
// (add_discrete_springs_masses). Either output pointer may be null (not assembled).
// Throws InvalidInput for an invalid material or options, or an element with a non-positive
// Jacobian (naming the element id).
void assemble_stiffness_mass(const Mesh& mesh, const IsotropicMaterial& material,
                             const AssemblyOptions& options, SparseMatrix* K, SparseMatrix* M);

// Assembles only the listed element indices (e.g. one body of a multi-body mesh); the matrices
// are still 3 num_nodes square. Indices must be in range and must not repeat. Springs and point
// masses are not added (they belong to no element list).
void assemble_stiffness_mass(const Mesh& mesh, std::span<const int> elements,
                             const IsotropicMaterial& material, const AssemblyOptions& options,
                             SparseMatrix* K, SparseMatrix* M);

// Adds Mesh::springs to K (k g gᵀ, g = [d_a; −d_b] on the DOFs of nodes a, b; the pattern grows
// where needed) and Mesh::point_masses to M (m on the three translations). Null: skipped.
void add_discrete_springs_masses(const Mesh& mesh, SparseMatrix* K, SparseMatrix* M);

}  // namespace stickslip
