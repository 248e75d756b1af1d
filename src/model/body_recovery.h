// The full-model recovery of one body given by a mesh (docs/conventions.md, "Full-model recovery"),
// computed and returned, never written: the body is loaded at a solved frequency point with the
// excitation, the static and preload loads and the harmonic contact forces the nonlinear solve
// found (recovery_loads.h), and solved as a linear harmonic problem on its full model with the
// case's recovery.method (direct: sparse complex factorisation; modal: full-body modes + static
// residual correction; expansion: x = T q through the Craig–Bampton basis). A body its clamps and
// supports do not hold gets, at harmonic 0, the rigid motion that fits the reduced response at its
// master DOFs (recovery/harmonic_response.h, add_rigid_motion).
//
// A spinning body (`rotation`, docs/rotation.md): its full K already holds Ω² (K_σ1 − S) (the
// reduction's), and its harmonic-0 load is the centrifugal body force Ω² M r⊥ on every node, in
// place of the condensed one the reduced model carried at its masters (model/rotation_case.h:
// Tᵀ f_c's master rows, or f_b − K_bi K_ii⁻¹ f_i): the recovered harmonic 0 is then the static
// state of the spinning body under its centrifugal load and the contact forces, and its stresses
// the mean stresses.
//
// A cyclic sector under engine-order excitation (PreparedModel::wave) is recovered on its sector
// with the cyclic constraint of each harmonic's nodal diameter (recovery/cyclic_recovery.h;
// recovery.method: direct only): sector 0's fields, the reactions and the nodal stresses of its
// boundary nodes as in the whole annulus solved as one body; the annulus from them is
// recovery/cyclic_recovery.h's annulus_*.
//
// The command line writes what this returns (cli/recovery_stage.h: recovery_check.csv,
// reactions.csv, recovered_nodes.csv, .vtu files); a program using the library takes the arrays.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "fe/stress.h"
#include "hbm/frequency_response.h"
#include "io/case_file.h"
#include "model/case_model.h"
#include "recovery/cyclic_recovery.h"
#include "recovery/harmonic_response.h"

namespace stickslip {

// One body at one frequency point; every matrix has one column per harmonic of the response
// (FrequencyResponse::harmonics), rows in the body's full DOF numbering (3 node + direction).
struct RecoveredPoint {
  Eigen::MatrixXcd loads;         // F: the recovery loads (global axes)
  Eigen::MatrixXcd displacement;  // x: the full-model response (constrained rows 0)
  // Harmonics the solver could not solve (singular dynamic stiffness: undamped, exactly at a
  // natural frequency) are NaN in `displacement` and named here; the others are valid.
  RecoverySummary summary;
  // Against the reduced nonlinear response at the body's master DOFs (compare_responses, the
  // reduced one the reference), per harmonic; reduced_max: the largest reduced amplitude there.
  ResponseDifference check;
  std::vector<double> reduced_max;
  // The forces the clamps and supports exert on the body, R_k = D_k x_k − F_k with
  // D_k = K − (kΩ)²M + i kΩ (αM + βK): row 3 i + d for node held_nodes()[i], direction d.
  Eigen::MatrixXcd reactions;
};

struct BodyRecoveryOptions {
  bool stresses = false;  // build the nodal stress operator (stresses() needs it)
};

class BodyRecovery {
 public:
  // model.bodies[body] must come from a mesh, with full K and M (and T for recovery.method:
  // expansion). Throws InvalidInput naming the case key when it has none of them (a reduction
  // given without them) or when the full model's solver cannot be set up (recovery.method).
  BodyRecovery(const CaseDefinition& definition, const PreparedModel& model, int body,
               BodyRecoveryOptions options = {});
  ~BodyRecovery();
  BodyRecovery(const BodyRecovery&) = delete;
  BodyRecovery& operator=(const BodyRecovery&) = delete;

  // `point` must be converged and carry master and pairs[q].force_global (a solved response);
  // harmonics: the response's.
  RecoveredPoint recover(const FrequencyPoint& point, const std::vector<int>& harmonics) const;

  // Nodal stresses of a recovered displacement (one 6 x num_nodes matrix per column of x; tensor
  // components xx, yy, zz, xy, xz, yz). Needs options.stresses. A cyclic sector needs the
  // harmonic of each column (its boundary nodes average across the boundary with their phase).
  std::vector<ComplexStressMatrix> stresses(const Eigen::MatrixXcd& displacement,
                                            std::span<const int> harmonics = {}) const;

  // Node indices (into the body's mesh) with a clamped, supported or equation-dependent DOF.
  const std::vector<int>& held_nodes() const { return held_nodes_; }
  const PreparedBody& body() const { return body_; }
  // The cyclic sector's recovery (null for an ordinary body).
  const CyclicSectorRecovery* cyclic() const { return cyclic_.get(); }

 private:
  const PreparedModel& model_;
  const PreparedBody& body_;
  RecoveryMethod method_;
  RayleighDamping damping_;
  std::unique_ptr<HarmonicSolver> solver_;     // null for expansion
  Eigen::MatrixXd rigid_;                      // rigid modes nothing holds (num_dofs x r)
  std::vector<int> full_dofs_, reduced_dofs_;  // the master DOFs: full and assembled-reduced
  std::vector<int> held_nodes_;
  std::optional<NodalStressOperator> stress_operator_;
  std::unique_ptr<CyclicSectorRecovery> cyclic_;
  std::vector<int> elements_at_node_;  // cyclic: elements holding each node
  // Rotation: added to the harmonic-0 loads, Ω² M r⊥ minus the condensed centrifugal load the
  // master rows carry (empty without rotation).
  Eigen::VectorXd rotation_load_;
};

}  // namespace stickslip
