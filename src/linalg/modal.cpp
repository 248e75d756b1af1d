#include "linalg/modal.h"

#include <Spectra/SymEigsSolver.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numeric>
#include <string>
#include <vector>

#include "core/errors.h"
#include "linalg/blas_threads.h"
#include "linalg/sparse_cholesky.h"

namespace stickslip {

namespace {

// Shift-invert in symmetric form. With K − σM = G Gᵀ (sparse Cholesky, G = Pᵀ L), the pencil
// K φ = λ M φ becomes the standard symmetric problem
//   C y = ν y,   C = G⁻¹ M G⁻ᵀ,   ν = 1 / (λ − σ),   φ = G⁻ᵀ y,
// whose largest ν are the λ closest to σ from above (all of them when σ is below the spectrum).
// Unlike the M-inner-product Lanczos of Spectra's generalised solver, this needs one M product
// per step instead of several, and the same two triangular solves.
class SymmetricShiftInvertOp {
 public:
  using Scalar = double;
  SymmetricShiftInvertOp(const SparseCholesky& factor, const SparseMatrix& M)
      : factor_(factor), M_(M), t_(M.rows()), u_(M.rows()) {}
  Eigen::Index rows() const { return M_.rows(); }
  Eigen::Index cols() const { return M_.cols(); }
  void perform_op(const double* x_in, double* y_out) const {
    factor_.solve_upper(x_in, t_.data());
    u_.noalias() = M_ * t_;
    factor_.solve_lower(u_.data(), y_out);
  }

 private:
  const SparseCholesky& factor_;
  const SparseMatrix& M_;
  mutable Eigen::VectorXd t_, u_;
};

std::string to_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", v);
  return buffer;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The component that fixes a mode's sign: the first one whose magnitude is within
// kSignTieTolerance of the largest. Symmetric structures have modes with mirror components of
// equal magnitude and opposite sign; without the tolerance round-off would pick either.
constexpr double kSignTieTolerance = 1e-4;
Eigen::Index sign_component(const Eigen::Ref<const Eigen::VectorXd>& phi) {
  const double threshold = (1.0 - kSignTieTolerance) * phi.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < phi.size(); ++i) {
    if (std::abs(phi(i)) >= threshold) return i;
  }
  return 0;
}

}  // namespace

void validate(const ModalOptions& options) {
  require(options.num_modes >= 1, "ModalOptions::num_modes", std::to_string(options.num_modes),
          "num_modes >= 1");
  require(std::isfinite(options.shift), "ModalOptions::shift", to_text(options.shift),
          "shift must be finite");
  require(options.subspace_size == 0 || options.subspace_size > options.num_modes,
          "ModalOptions::subspace_size", std::to_string(options.subspace_size),
          "subspace_size == 0 (automatic) or subspace_size > num_modes (" +
              std::to_string(options.num_modes) + ")");
  require(options.tolerance > 0.0 && options.tolerance < 1.0, "ModalOptions::tolerance",
          to_text(options.tolerance), "0 < tolerance < 1");
  require(options.max_iterations >= 1, "ModalOptions::max_iterations",
          std::to_string(options.max_iterations), "max_iterations >= 1");
}

Eigen::VectorXd ModalResult::frequencies_hz() const {
  return eigenvalues.unaryExpr(
      [](double w2) { return std::sqrt(std::max(w2, 0.0)) / (2.0 * kPi); });
}

ModalResult solve_modes(const SparseMatrix& K, const SparseMatrix& M, const ModalOptions& options) {
  validate(options);
  const Eigen::Index n = K.rows();
  require(K.rows() == K.cols(), "K", std::to_string(K.rows()) + " x " + std::to_string(K.cols()),
          "K must be square");
  require(M.rows() == n && M.cols() == n, "M",
          std::to_string(M.rows()) + " x " + std::to_string(M.cols()),
          "M must have the size of K (" + std::to_string(n) + ")");
  require(options.num_modes < n, "ModalOptions::num_modes", std::to_string(options.num_modes),
          "num_modes < problem size (" + std::to_string(n) + ")");
  require(options.subspace_size <= n, "ModalOptions::subspace_size",
          std::to_string(options.subspace_size),
          "subspace_size <= problem size (" + std::to_string(n) + ")");

  const int nev = options.num_modes;
  const Eigen::Index ncv = options.subspace_size > 0
                               ? options.subspace_size
                               : std::min<Eigen::Index>(std::max(2 * nev + 1, nev + 20), n);

  ModalResult result;
  ModalSummary& summary = result.summary;

  auto start = std::chrono::steady_clock::now();
  SparseCholesky factor;
  {
    const SparseMatrix A = options.shift == 0.0 ? K : SparseMatrix(K - options.shift * M);
    factor.factorize(A);
  }
  summary.factorization_seconds = seconds_since(start);
  if (!factor.ok()) {
    summary.termination = ModalTermination::kFactorizationFailed;
    summary.message = "factorisation of K - sigma*M failed (sigma = " + to_text(options.shift) +
                      " (rad/s)^2): " + factor.message() +
                      ". K - sigma*M must be positive definite: choose a shift below the lowest "
                      "eigenvalue (a negative shift for free bodies) and check that K is "
                      "positive semi-definite and M positive definite";
    return result;
  }

  start = std::chrono::steady_clock::now();
  SymmetricShiftInvertOp op(factor, M);
  Spectra::SymEigsSolver<SymmetricShiftInvertOp> solver(op, nev, ncv);
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  try {
    const ScopedBlasThreads single_thread(1);  // BLAS-2 solves: threads only hurt (blas_threads.h)
    solver.init();
    solver.compute(Spectra::SortRule::LargestAlge, options.max_iterations, options.tolerance,
                   Spectra::SortRule::LargestAlge);
    const Eigen::VectorXd nu = solver.eigenvalues();
    const Eigen::MatrixXd y = solver.eigenvectors();
    values = (1.0 / nu.array() + options.shift).matrix();
    vectors.resize(n, y.cols());
    for (Eigen::Index j = 0; j < y.cols(); ++j)
      factor.solve_upper(y.col(j).data(), vectors.col(j).data());
  } catch (const std::exception& e) {
    summary.termination = ModalTermination::kNotConverged;
    summary.message = std::string("Lanczos iteration failed: ") + e.what();
    summary.iteration_seconds = seconds_since(start);
    return result;
  }
  summary.iteration_seconds = seconds_since(start);
  summary.iterations = static_cast<int>(solver.num_iterations());
  summary.operations = static_cast<int>(solver.num_operations());
  summary.converged_modes = static_cast<int>(values.size());

  // Ascending ω², mass normalisation, deterministic sign.
  std::vector<int> order(static_cast<size_t>(values.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return values(a) < values(b); });
  result.eigenvalues.resize(values.size());
  result.modes.resize(n, values.size());
  Eigen::VectorXd Mphi(n);
  for (Eigen::Index j = 0; j < values.size(); ++j) {
    const int k = order[static_cast<size_t>(j)];
    result.eigenvalues(j) = values(k);
    auto phi = result.modes.col(j);
    phi = vectors.col(k);
    Mphi.noalias() = M * phi;
    const double mass = phi.dot(Mphi);
    if (mass > 0.0) phi /= std::sqrt(mass);
    if (phi(sign_component(phi)) < 0.0) phi = -phi;
  }

  if (solver.info() == Spectra::CompInfo::Successful && summary.converged_modes == nev) {
    summary.termination = ModalTermination::kConverged;
    summary.message = std::to_string(nev) + " modes converged in " +
                      std::to_string(summary.iterations) + " restarts, " +
                      std::to_string(summary.operations) + " operator applications";
  } else {
    summary.termination = ModalTermination::kNotConverged;
    summary.message = "Lanczos did not converge: " + std::to_string(summary.converged_modes) +
                      " of " + std::to_string(nev) + " modes converged after " +
                      std::to_string(summary.iterations) + " restarts (tolerance " +
                      to_text(options.tolerance) + ", subspace " + std::to_string(ncv) +
                      "); increase max_iterations or subspace_size";
  }
  return result;
}

}  // namespace stickslip
