// Helpers for the validation tests (tests/validation): meshes of a box generated here (not by
// io/ or Gmsh, so the tests stay independent of the code they check), a CalculiX deck writer, a
// ccx runner and parsers of its eigenvalue output, and the clamped modal problem.
//
// Box meshes: [0, a] x [0, b] x [0, c] (m) with nx x ny x nz hexahedral cells, node ids 1.., the
// node set FIX = nodes at x = 0. Hexahedra use CalculiX's node order; tetrahedra come from the
// Kuhn split of every cell into 6 tetrahedra around its (0,0,0)-(1,1,1) diagonal (conforming);
// 10-node tetrahedra and 20-node hexahedra get mid-edge nodes.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "linalg/modal.h"
#include "mesh/mesh.h"

namespace stickslip::validation {

struct BoxOptions {
  double a = 0.25, b = 0.05, c = 0.03;  // extents along x, y, z, m
  int nx = 8, ny = 2, nz = 2;           // cells
  ElementType type = ElementType::kC3D8;
  // Smooth distortion of the grid (m per m of extent), making Jacobians vary inside elements:
  // y += d b sin(π x / a) (2z/c − 1),  z += d c sin(π y / b) (x / a). 0 = straight box.
  double distortion = 0.0;
};
Mesh make_box_mesh(const BoxOptions& options);

struct Steel {
  double youngs_modulus = 2.0e11;  // Pa
  double poisson_ratio = 0.3;
  double density = 7800.0;  // kg/m^3
};

// A complete *FREQUENCY deck: the mesh (all elements in ELSET EALL), the material, *BOUNDARY
// on the node set FIX (all three directions), `num_modes` eigenpairs, STORAGE=YES (the .eig file
// with the eigenvalues in double precision). `extra` is inserted before *STEP (springs, ...).
std::string calculix_frequency_deck(const Mesh& mesh, const Steel& steel, int num_modes,
                                    const std::string& extra = "");
// The same model with *FREQUENCY, SOLVER=MATRIXSTORAGE: ccx writes its stiffness (.sti) and mass
// (.mas) matrices after applying the boundary conditions, and the DOF list (.dof), instead of
// solving.
std::string calculix_matrix_deck(const Mesh& mesh, const Steel& steel,
                                 const std::string& extra = "");

// The same model with a *STATIC step whose body (loads, *NODE PRINT, ...) is `step`; run by
// run_calculix_dat.
std::string calculix_static_deck(const Mesh& mesh, const Steel& steel, const std::string& step,
                                 const std::string& extra = "");

// Path of the ccx executable, or nothing if it is not installed.
std::optional<std::string> find_ccx();

struct CalculixEigenvalues {
  std::vector<double> from_dat;  // ω², (rad/s)², 7 significant digits (the .dat table)
  std::vector<double> from_eig;  // ω², double precision (the .eig file); empty if unreadable
  std::string log;               // ccx's screen output, for failure messages
  // The most precise available: .eig when it is consistent with .dat, else .dat.
  const std::vector<double>& best() const { return from_eig.empty() ? from_dat : from_eig; }
};

// Writes `deck` as <dir>/<job>.inp in a fresh temporary directory, runs ccx there (one thread)
// and parses the eigenvalues. Throws std::runtime_error if ccx fails or prints no eigenvalues.
CalculixEigenvalues run_calculix_frequency(const std::string& deck, const std::string& job);

// Runs ccx on `deck` (as run_calculix_frequency) and returns its .dat file. Throws
// std::runtime_error if ccx fails.
std::string run_calculix_dat(const std::string& deck, const std::string& job);

// CalculiX's matrices from a MATRIXSTORAGE run, symmetric, both triangles stored; row/column i
// is DOF dofs[i] = (node id, direction 0..2). Nodes that ccx generates internally (e.g. the
// incompatible-mode nodes of C3D8I) have ids above the mesh's.
struct CalculixMatrices {
  SparseMatrix K, M;
  std::vector<std::pair<int, int>> dofs;
};
CalculixMatrices run_calculix_matrices(const std::string& deck, const std::string& job);

// Lowest `num_modes` eigenpairs of K, M restricted to the DOFs not in `fixed_nodes` (all three
// directions removed). The full-size mode shapes (zeros at fixed DOFs) are returned.
ModalResult clamped_modes(const SparseMatrix& K, const SparseMatrix& M,
                          const std::vector<int>& fixed_nodes, int num_modes);

// Relative difference |a − b| / |b|.
inline double relative_difference(double a, double b) { return std::abs(a - b) / std::abs(b); }

}  // namespace stickslip::validation
