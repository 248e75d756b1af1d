// Full-model recovery of a cyclic sector under engine-order excitation (issue 13, item 5;
// docs/cyclic.md, "Recovery on the sector and the annulus").
//
// Tuned travelling wave (hbm/travelling_wave.h): harmonic k of every field of sector j is sector
// 0's rotated by R^j with the phase e^{i j σ_k}, σ_k = 2π k·EO/N, so harmonic k of sector 0 lives
// in the nodal diameter h' = k·EO mod N: u_high = e^{iσ_k} R u_low. With T_{h'} of
// fe/cyclic.h (for h' > N/2 the conjugate of diameter N − h's, R being real) and u = T u_I,
//
//   T_{h'}ᴴ D_k T_{h'} u_I = T_{h'}ᴴ F_k,   D_k = K − (kΩ)² M + i kΩ (αM + βK),
//
// F_k the loads on sector 0's own nodes (the high boundary carries none: it is the next
// sector's). Solved by a sparse complex LU per harmonic and point (UMFPACK, as DirectRecovery);
// harmonic 0 (diameter 0, real) is factorised once. A sector whose clamps do not hold its rigid
// motion is refused (as in the forced response).
//
// Boundary fields, so that the sector's fields are the ring's (what the whole annulus solved as
// one body gives):
//  - reactions: the residual D_k x − F_k of a low-boundary node gets the high node's, which is the
//    previous sector's share of that node, rotated back with the conjugate phase:
//    r(lo) += e^{−iσ_k} Rᵀ r(hi); high nodes are not the sector's (fold_boundary_residual);
//  - nodal stresses (fe/stress.h averages over the elements holding a node): at a boundary node
//    the average takes the previous sector's elements too, whose share is the high node's
//    rotated back: S(lo) = (c_lo S(lo) + c_hi e^{−iσ_k} Rᵀ S(hi) R) / (c_lo + c_hi), and
//    S(hi) = e^{iσ_k} R S(lo) Rᵀ (c: elements holding the node; average_boundary_stresses).
//
// The annulus: sector j's node n is sector 0's rotated about the axis by R^j; its harmonic k
// vector fields R^j v e^{i j σ_k}, tensors R^j S R^jᵀ e^{i j σ_k}; an envelope over the period
// (von Mises, principal) is sector 0's at the same node (sector j's cycle is sector 0's shifted in
// time and rotated).
#pragma once

#include <complex>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "fe/cyclic.h"
#include "fe/stress.h"
#include "mesh/mesh.h"
#include "recovery/harmonic_response.h"

namespace stickslip {

// σ_k = 2π (k·EO mod N)/N.
double cyclic_harmonic_phase(int harmonic, int engine_order, int sectors);

class CyclicSectorRecovery {
 public:
  // K, M: the sector's full matrices (3 num_nodes square); boundary_pairs: (low, high) node
  // indices (match_cyclic_boundaries); clamped_dofs: full DOFs held at zero; harmonics: those
  // solve() will be asked for (their diameters are set up here). ok() false (message()) when a
  // diameter's static stiffness cannot be factorised (e.g. rigid motion nothing holds).
  CyclicSectorRecovery(const SparseMatrix& K, const SparseMatrix& M,
                       std::vector<std::pair<int, int>> boundary_pairs,
                       std::span<const int> clamped_dofs, const CyclicSymmetry& symmetry,
                       int engine_order, RayleighDamping damping, std::span<const int> harmonics);
  ~CyclicSectorRecovery();
  CyclicSectorRecovery(const CyclicSectorRecovery&) = delete;
  CyclicSectorRecovery& operator=(const CyclicSectorRecovery&) = delete;

  bool ok() const;
  const std::string& message() const;

  // Column j of `loads` (3 num_nodes, sector 0's own nodes) at harmonic harmonics[j]: sector 0's
  // full complex displacement (high boundary included, clamped DOFs 0). A singular D_k (undamped
  // resonance) gives NaN columns, reported in *summary, as HarmonicSolver.
  Eigen::MatrixXcd solve(const Eigen::MatrixXcd& loads, std::span<const int> harmonics,
                         double omega, RecoverySummary* summary = nullptr) const;

  // Reactions: see the header comment. residual: 3 num_nodes x harmonics, in place.
  void fold_boundary_residual(Eigen::MatrixXcd& residual, std::span<const int> harmonics) const;
  // Nodal stresses averaged across the cyclic boundary, in place (one matrix per harmonic).
  // elements_at_node: per node the number of elements holding it.
  void average_boundary_stresses(std::vector<ComplexStressMatrix>& stresses,
                                 std::span<const int> harmonics,
                                 std::span<const int> elements_at_node) const;
  // True for the nodes of the high boundary (the next sector's low nodes).
  bool is_high(int node) const;

  const CyclicSymmetry& symmetry() const { return symmetry_; }
  int engine_order() const { return engine_order_; }

 private:
  struct Diameter;
  const Diameter& diameter_of(int harmonic, bool* conjugate) const;
  CyclicSymmetry symmetry_;
  int engine_order_ = 0;
  RayleighDamping damping_;
  std::vector<std::pair<int, int>> pairs_;
  std::vector<char> high_;
  std::vector<std::unique_ptr<Diameter>> diameters_;  // by nodal diameter 0..N/2 (null: unused)
  std::string message_;
};

// Number of elements holding each node of `mesh`.
std::vector<int> elements_at_nodes(const Mesh& mesh);

// The annulus of N sectors from sector 0's mesh: sector j's nodes rotated by R^j about the axis,
// node ids id + j·stride and element ids id + j·element_stride (strides: the smallest power of
// ten above the largest id), N × num_nodes nodes (the boundary nodes once per sector).
Mesh annulus_mesh(const Mesh& sector, const CyclicSymmetry& symmetry);
// Vector fields (3 num_nodes x harmonics; column j harmonic harmonics[j]) of the annulus:
// 3 N num_nodes x harmonics, sector j's rows R^j v e^{i j σ_k}.
Eigen::MatrixXcd annulus_vectors(const Eigen::MatrixXcd& sector, std::span<const int> harmonics,
                                 const CyclicSymmetry& symmetry, int engine_order);
// Symmetric tensors (Voigt xx, yy, zz, xy, xz, yz; one 6 x num_nodes matrix per harmonic):
// sector j's R^j S R^jᵀ e^{i j σ_k}.
std::vector<ComplexStressMatrix> annulus_tensors(const std::vector<ComplexStressMatrix>& sector,
                                                 std::span<const int> harmonics,
                                                 const CyclicSymmetry& symmetry, int engine_order);
// Invariant nodal values (rows x num_nodes, e.g. envelopes) repeated in every sector.
Eigen::MatrixXd annulus_scalars(const Eigen::MatrixXd& sector, int sectors);

}  // namespace stickslip
