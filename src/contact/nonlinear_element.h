// One interface for every nonlinear element that joins two nodes (A, B) or a node and the ground.
//
// An element sees only its LOCAL relative displacement u = R (x_A − x_B) (m components; for the
// 3D friction contact rows (t1, t2, n), so u_n = w is the normal approach) and returns the LOCAL
// force f that the element exerts on B; the force on B in global axes is +Rᵀ f, on A −Rᵀ f
// (docs/conventions.md). SI units: u in m, f in N.
//
// march(): the element law marched over ONE period sampled at N equally spaced instants
// (column j of u = u(t_j); the sample after N−1 is sample 0 of the next period). Elements with
// memory (friction) return the periodic steady state: the cycle whose state at the end of the
// period equals the state at its start (the hysteresis cycle repeats). They start from the
// virgin state (zero force history at u = 0) and march; a cycle that has not repeated after two
// periods may be closed by solving the periodicity condition for the start state directly
// (FrictionContact3D: Newton on τ at the period start). The returned f is the closed cycle.
//
// Exact derivatives: du_dp ((m·N) x p) holds ∂u_d(t_j)/∂p_q in row j·m + d, for any p parameters
// (e.g. the harmonic coefficients of u). df_dp (same layout) receives ∂f_d(t_j)/∂p_q, propagated
// through the whole march (stick, slip, lift-off branches) and across the period wrap: the
// derivative of the last period's start state is the derivative of the previous period's end
// state, or, for a start state found from the periodicity condition τ_s = P(τ_s, p), its
// implicit derivative (I − ∂P/∂τ_s)⁻¹ ∂P/∂p. Pass nullptr for both to skip derivatives.
#pragma once

#include <memory>
#include <string>

#include <Eigen/Core>

namespace stickslip {

// Per element, per converged cycle.
struct CycleStatistics {
  // Fractions of the N samples. Friction elements: stick / slip / separation (N = 0).
  // Unilateral springs: stick = closed, separation = open. Cubic spring: stick = 1.
  double stick_fraction = 0.0;
  double slip_fraction = 0.0;
  double separation_fraction = 0.0;
  // ∮ f_t · du_t over the cycle (tangential components; trapezoidal rule on the samples), J.
  // Energy taken out of the structure by the element; 0 for elastic elements.
  double dissipated_energy = 0.0;
  int periods = 0;  // periods of the march (a stuck cycle: 2, the second known to repeat the
                    // first without being marched; memoryless elements: 1)
  bool converged = true;  // cycle repeated within MarchOptions.tolerance
  // Set by the event AFT (hbm/aft.h) when it did not apply to this cycle and the sampled AFT
  // gave it instead (a 3D contact whose tangential motion is not collinear).
  bool aft_fallback = false;
};

struct MarchOptions {
  // Cycle closure: max_j |state_end − state_start| <= tolerance · (force scale of the cycle).
  double tolerance = 1e-12;
  int max_periods = 200;
};
void validate(const MarchOptions& options);

class NonlinearElement {
 public:
  virtual ~NonlinearElement() = default;
  virtual int dimension() const = 0;     // m: rows of u and f
  virtual std::string name() const = 0;  // e.g. "friction_contact_3d"
  // u: m x N. f: resized to m x N. du_dp and df_dp both null or both set.
  virtual CycleStatistics march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp,
                                Eigen::MatrixXd& f, Eigen::MatrixXd* df_dp) const = 0;
};

using ElementPtr = std::shared_ptr<const NonlinearElement>;

}  // namespace stickslip
