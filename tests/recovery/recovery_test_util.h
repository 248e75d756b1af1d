// Test helpers for recovery: a structured hexahedral bar, nodes on a plane, the clamped DofMap,
// steel, and dense references for K, M (independent of the solvers under test).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "fe/assembly.h"
#include "fe/dof_map.h"
#include "fe/material.h"
#include "mesh/mesh.h"

namespace stickslip::testing {

inline const IsotropicMaterial kSteel{
    .youngs_modulus = 2e11, .poisson_ratio = 0.3, .density = 7800};

// nx x ny x nz 8-node hexahedra (CalculiX node order) over origin + [0,Lx]x[0,Ly]x[0,Lz].
// Node ids = index + 1 + id_offset, element ids = index + 1 + id_offset.
Mesh bar_mesh(int nx, int ny, int nz, const Eigen::Vector3d& size, ElementType type,
              const Eigen::Vector3d& origin = Eigen::Vector3d::Zero(), int id_offset = 0);

// Node indices with coordinate `axis` equal to `value` (tolerance 1e-9 m).
std::vector<int> nodes_at(const Mesh& mesh, int axis, double value);

// Dense complex D = K − w² M + i w (alpha M + beta K) restricted to the free DOFs.
Eigen::MatrixXcd dense_dynamic_matrix(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, double w,
                                      double alpha, double beta);

}  // namespace stickslip::testing
