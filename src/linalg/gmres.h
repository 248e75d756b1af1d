// Restarted GMRES with right preconditioning for a real n x n system A x = b given only as
// products (Saad, "Iterative Methods for Sparse Linear Systems", alg. 9.5):
//   solve A P⁻¹ y = b by GMRES(restart), x = P⁻¹ y; the monitored residual is the true one,
//   ||b − A x||₂, and the solver stops when it is <= tolerance · ||b||₂.
// apply(v) returns A v, precondition(v) returns P⁻¹ v (both size n).
#pragma once

#include <functional>

#include <Eigen/Core>

namespace stickslip {

struct GmresOptions {
  double tolerance = 1e-10;   // relative to ||b||
  int restart = 100;          // Krylov dimension per cycle, >= 1
  int max_iterations = 1000;  // products with A in all cycles
};

struct GmresSummary {
  bool converged = false;
  int iterations = 0;            // products with A (without the residual checks at restarts)
  double relative_residual = 0;  // ||b − A x|| / ||b|| at return
};

using LinearOperator = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// x is overwritten (the start is x = 0). b = 0 gives x = 0, converged.
GmresSummary gmres(const LinearOperator& apply, const LinearOperator& precondition,
                   const Eigen::VectorXd& b, Eigen::VectorXd& x, const GmresOptions& options);

}  // namespace stickslip
