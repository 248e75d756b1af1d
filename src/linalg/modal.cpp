#include "linalg/modal.h"

#include <Spectra/SymEigsSolver.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/parallel.h"
#include "linalg/blas.h"
#include "linalg/blas_threads.h"
#include "linalg/sparse_cholesky.h"

namespace stickslip {

namespace {

// C = alpha op(A) op(B) + beta C, column-major, through BLAS.
void blas_gemm(char transa, char transb, Eigen::Index m, Eigen::Index n, Eigen::Index k,
               double alpha, const double* a, Eigen::Index lda, const double* b, Eigen::Index ldb,
               double beta, double* c, Eigen::Index ldc) {
  const int mi = static_cast<int>(m), ni = static_cast<int>(n), ki = static_cast<int>(k);
  const int la = static_cast<int>(lda), lb = static_cast<int>(ldb), lc = static_cast<int>(ldc);
  dgemm_(&transa, &transb, &mi, &ni, &ki, &alpha, a, &la, b, &lb, &beta, c, &lc);
}

// Shift-invert in symmetric form. With K − σM = G Gᵀ (sparse Cholesky, G = Pᵀ L), the pencil
// K φ = λ M φ becomes the standard symmetric problem
//   C y = ν y,   C = G⁻¹ M G⁻ᵀ,   ν = 1 / (λ − σ),   φ = G⁻ᵀ y,
// whose largest ν are the λ closest to σ from above (all of them when σ is below the spectrum).
// Unlike the M-inner-product Lanczos of Spectra's generalised solver, this needs one M product
// per step instead of several, and the same two triangular solves.
// The operator applied is `scale`·C: Spectra's convergence test, |residual| <= tol·max(|ν|,
// eps^(2/3)), is absolute below ν = eps^(2/3) ≈ 3.7e-11, i.e. for every mode above 26 kHz when C
// is not scaled (ν = 1/ω²): such modes were accepted with residuals of the order of ν itself, not
// M-orthogonal (issue 22). Scaled so that the largest ν is about 1, the test is relative.
class SymmetricShiftInvertOp {
 public:
  using Scalar = double;
  SymmetricShiftInvertOp(const SparseCholesky& factor, const SparseMatrix& M, double scale = 1.0)
      : factor_(factor), M_(M), scale_(scale), t_(M.rows()), u_(M.rows()) {}
  Eigen::Index rows() const { return M_.rows(); }
  Eigen::Index cols() const { return M_.cols(); }
  void perform_op(const double* x_in, double* y_out) const {
    factor_.solve_upper(x_in, t_.data());
    u_.noalias() = scale_ * (M_ * t_);
    factor_.solve_lower(u_.data(), y_out);
  }

 private:
  const SparseCholesky& factor_;
  const SparseMatrix& M_;
  double scale_;
  mutable Eigen::VectorXd t_, u_;
};

// A lower estimate of the largest eigenvalue ν_max of C = G⁻¹ M G⁻ᵀ (within a small factor): a
// few power iterations from a seeded random vector. Only its order of magnitude is used.
double largest_nu_estimate(const SparseCholesky& factor, const SparseMatrix& M, int& operations) {
  constexpr int kPowerIterations = 4;
  const SymmetricShiftInvertOp op(factor, M);
  std::mt19937 rng(20261125);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd x(M.rows()), y(M.rows());
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = normal(rng);
  x.normalize();
  double nu = 0.0;
  for (int it = 0; it < kPowerIterations; ++it) {
    op.perform_op(x.data(), y.data());
    ++operations;
    nu = y.norm();
    if (!(nu > 0.0) || !std::isfinite(nu)) return 1.0;
    x = y / nu;
  }
  return nu;
}

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

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Rows of a sparse product per thread at least: a row costs an axpy per nonzero (≈ 80 of them,
// on rows of 8–30 entries), so 1024 rows take ~1 ms, far more than starting a thread (~30 µs).
constexpr std::ptrdiff_t kRowsPerThread = 1024;

// A new Lanczos block whose QR has a diagonal entry at or below 1e-10 of the block's norm is
// (numerically) rank deficient: its columns span an invariant subspace already in the basis, up
// to the ~1e-14 round-off of the preceding Gram–Schmidt, and orthonormalising them would amplify
// that round-off 1e10 times. The block Lanczos then stops (returns nothing usable).
constexpr double kBlockRankDeficient = 1e-10;

// Y = M X for a block X (n x b): one pass over M's rows, each nonzero an axpy on a row of b
// contiguous entries, the rows split over the hardware threads (parallel_for). (Eigen's
// column-major sparse times dense product passes over M once per column.)
Eigen::MatrixXd block_product(const RowSparse& M, const Eigen::MatrixXd& X) {
  const RowMatrix Xr = X;
  RowMatrix Yr(X.rows(), X.cols());
  parallel_for(
      M.rows(), thread_count(),
      [&](std::ptrdiff_t r0, std::ptrdiff_t r1, int) {
        for (Eigen::Index r = r0; r < r1; ++r) {
          auto y = Yr.row(r);
          y.setZero();
          for (RowSparse::InnerIterator it(M, r); it; ++it)
            y.noalias() += it.value() * Xr.row(it.col());
        }
      },
      kRowsPerThread);
  return Yr;
}

// Block Lanczos on C = G⁻¹ M G⁻ᵀ with full reorthogonalisation (classical Gram–Schmidt, twice)
// and no restart. After j steps the basis Q (n x kb) satisfies C Q = Q H + W Eᵀ with
// H = Qᵀ C Q and W the part of the last block's image orthogonal to Q, so the Ritz pair
// (ν, Q s) of H has residual ‖C Q s − ν Q s‖ = ‖W s_last‖ (s_last: the last b entries of s).
// Converged when the nev largest Ritz values all have residual <= tol · max(|ν|, eps^(2/3)),
// Spectra's criterion. Returns false (nothing usable) if the basis would exceed `capacity`
// columns or a block loses rank; on success `nu` holds the nev largest ν descending and `y`
// the Ritz vectors (n x nev, orthonormal).
bool block_lanczos(const SparseCholesky& factor, const SparseMatrix& M, int nev, int b,
                   Eigen::Index capacity, double tol, Eigen::VectorXd& nu, Eigen::MatrixXd& y,
                   int& operations, int& steps) {
  const Eigen::Index n = M.rows();
  const RowSparse M_rows = M;
  Eigen::MatrixXd Q(n, capacity);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(capacity, capacity);
  std::mt19937 rng(20261122);  // fixed seed: reproducible modes
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd W(n, b);
  for (Eigen::Index j = 0; j < b; ++j)
    for (Eigen::Index i = 0; i < n; ++i) W(i, j) = normal(rng);
  // Orthonormal block of W's columns; false if W is (numerically) rank deficient.
  auto orthonormalise = [&](Eigen::Index at, double scale) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(W);
    const Eigen::VectorXd r = qr.matrixQR().diagonal().head(b).cwiseAbs();
    if (r.minCoeff() <= kBlockRankDeficient * scale) return false;
    Q.middleCols(at, b) = qr.householderQ() * Eigen::MatrixXd::Identity(n, b);
    return true;
  };
  if (!orthonormalise(0, W.norm())) return false;
  Eigen::Index k = b;  // basis columns filled
  // Spectra's criterion made scale-free: the eps^(2/3) floor relative to the largest Ritz value
  // (an absolute floor accepts unconverged modes when ν = 1/(ω² − σ) is small, see
  // SymmetricShiftInvertOp).
  const double eps23 = std::pow(std::numeric_limits<double>::epsilon(), 2.0 / 3.0);
  operations = 0;
  steps = 0;
  while (true) {
    // W = C V for the newest block V.
    const Eigen::MatrixXd T = factor.solve_upper(Eigen::MatrixXd(Q.middleCols(k - b, b)));
    const Eigen::MatrixXd U = block_product(M_rows, T);
    W = factor.solve_lower(U);
    operations += b;
    ++steps;
    const double image_norm = W.norm();
    Eigen::MatrixXd coefficients(k, b);
    for (int pass = 0; pass < 2; ++pass) {
      // coefficients = Q_kᵀ W;  W −= Q_k coefficients.
      blas_gemm('T', 'N', k, b, n, 1.0, Q.data(), n, W.data(), n, 0.0, coefficients.data(), k);
      blas_gemm('N', 'N', n, b, k, -1.0, Q.data(), n, coefficients.data(), k, 1.0, W.data(), n);
      H.block(0, k - b, k, b) += coefficients;
    }
    // Column block j holds Qᵀ C V_j for the blocks that existed then: H's upper triangle is
    // complete (the sub-diagonal blocks are filled by symmetry).
    const Eigen::MatrixXd Hk = H.topLeftCorner(k, k).selfadjointView<Eigen::Upper>();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz(Hk);
    if (ritz.info() != Eigen::Success) return false;
    if (k >= nev) {
      // Largest nev Ritz values: the last nev of the ascending list.
      const Eigen::MatrixXd S = ritz.eigenvectors().rightCols(nev);
      const Eigen::VectorXd values = ritz.eigenvalues().tail(nev);
      const Eigen::MatrixXd residual = W * S.bottomRows(b);
      bool converged = true;
      for (int j = 0; j < nev && converged; ++j)
        converged = residual.col(j).norm() <=
                    tol * std::max(std::abs(values(j)), eps23 * std::abs(values(nev - 1)));
      if (converged) {
        nu = values.reverse();
        const Eigen::MatrixXd S_descending = S.rowwise().reverse();
        y.resize(n, nev);
        blas_gemm('N', 'N', n, nev, k, 1.0, Q.data(), n, S_descending.data(), k, 0.0, y.data(), n);
        return true;
      }
    }
    if (k + b > capacity) return false;
    if (!orthonormalise(k, image_norm)) return false;
    k += b;
  }
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
  require(options.block_size >= 0, "ModalOptions::block_size", std::to_string(options.block_size),
          "block_size >= 0 (0 = automatic)");
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

  auto start = std::chrono::steady_clock::now();
  SparseCholesky factor;
  {
    const SparseMatrix A = options.shift == 0.0 ? K : SparseMatrix(K - options.shift * M);
    factor.factorize(A);
  }
  const double factorization_seconds = seconds_since(start);
  if (!factor.ok()) {
    ModalResult result;
    ModalSummary& summary = result.summary;
    summary.factorization_seconds = factorization_seconds;
    summary.termination = ModalTermination::kFactorizationFailed;
    summary.message = "factorisation of K - sigma*M failed (sigma = " + to_text(options.shift) +
                      " (rad/s)^2): " + factor.message() +
                      ". K - sigma*M must be positive definite: choose a shift below the lowest "
                      "eigenvalue (a negative shift for free bodies) and check that K is "
                      "positive semi-definite and M positive definite";
    return result;
  }
  ModalResult result = solve_modes(factor, M, options);
  result.summary.factorization_seconds = factorization_seconds;
  return result;
}

// GCC 12 at -O3 reports a false -Wuse-after-free inside Eigen's aligned_free, inlined here
// (clang has no such warning and would reject the unknown option under -Werror).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuse-after-free"
#endif
ModalResult solve_modes(const SparseCholesky& factor, const SparseMatrix& M,
                        const ModalOptions& options) {
  validate(options);
  require(factor.ok(), "factor", "not factorised",
          "solve_modes needs a successful Cholesky of K - sigma*M");
  const Eigen::Index n = factor.size();
  require(M.rows() == n && M.cols() == n, "M",
          std::to_string(M.rows()) + " x " + std::to_string(M.cols()),
          "M must have the size of the factor (" + std::to_string(n) + ")");
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

  // Automatic block size: single-vector Lanczos for small problems (its solves are cheap), blocks
  // where the factor is large and each single solve streams it from memory.
  constexpr Eigen::Index kBlockMinRows = 20000;
  // 8 vectors per step: fewest vectors in total (box of 202k DOFs, 60 modes: 280 against 375
  // with 15), and with one BLAS thread the least CPU time (docs/performance.md).
  constexpr int kAutomaticBlock = 8;
  const int block =
      options.block_size > 0 ? options.block_size : (n >= kBlockMinRows ? kAutomaticBlock : 1);

  auto start = std::chrono::steady_clock::now();
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;      // φ = G⁻ᵀ y, any scale
  Eigen::MatrixXd coordinates;  // the y of each φ
  bool converged = false;
  std::string method;
  if (block >= 2) {
    const Eigen::Index capacity =
        std::min<Eigen::Index>(std::max<Eigen::Index>(ncv, 8 * nev) + block, n);
    Eigen::VectorXd nu;
    Eigen::MatrixXd y;
    int operations = 0, steps = 0;
    // One BLAS thread: the half solves with a few columns gain little from a second thread, and
    // on a busy machine OpenBLAS's waiting threads spin.
    const ScopedBlasThreads single_thread(1);
    const bool done =
        capacity >= std::max(block, nev) &&
        block_lanczos(factor, M, nev, block, capacity, options.tolerance, nu, y, operations, steps);
    summary.operations += operations;
    if (done) {
      values = (1.0 / nu.array() + options.shift).matrix();
      vectors = factor.solve_upper(y);
      coordinates = y;
      converged = true;
      summary.iterations = steps;
      summary.block_size = block;
      method = "block Lanczos (" + std::to_string(block) + " vectors per step) in " +
               std::to_string(steps) + " steps, ";
    }
  }
  if (!converged) {
    int power_operations = 0;
    const double nu_scale = largest_nu_estimate(factor, M, power_operations);
    summary.operations += power_operations;
    SymmetricShiftInvertOp op(factor, M, 1.0 / nu_scale);
    Spectra::SymEigsSolver<SymmetricShiftInvertOp> solver(op, nev, ncv);
    try {
      const ScopedBlasThreads single_thread(1);  // BLAS-2 solves: threads only hurt
      solver.init();
      solver.compute(Spectra::SortRule::LargestAlge, options.max_iterations, options.tolerance,
                     Spectra::SortRule::LargestAlge);
      const Eigen::VectorXd nu = nu_scale * solver.eigenvalues();
      const Eigen::MatrixXd y = solver.eigenvectors();
      values = (1.0 / nu.array() + options.shift).matrix();
      coordinates = y;
      vectors.resize(n, y.cols());
      for (Eigen::Index j = 0; j < y.cols(); ++j)
        factor.solve_upper(y.col(j).data(), vectors.col(j).data());
    } catch (const std::exception& e) {
      summary.termination = ModalTermination::kNotConverged;
      summary.message = std::string("Lanczos iteration failed: ") + e.what();
      summary.iteration_seconds = seconds_since(start);
      return result;
    }
    summary.iterations = static_cast<int>(solver.num_iterations());
    summary.operations += static_cast<int>(solver.num_operations());
    summary.block_size = 1;
    converged = solver.info() == Spectra::CompInfo::Successful && values.size() == nev;
    method = std::to_string(summary.iterations) + " restarts, ";
  }
  summary.iteration_seconds = seconds_since(start);
  summary.converged_modes = static_cast<int>(values.size());

  // Rayleigh–Ritz in the span of the Ritz vectors: with A = Vᵀ M V and B = Vᵀ(K − σM)V = YᵀY
  // (φ = G⁻ᵀ y), the small problem B s = μ A s (μ = ω² − σ) gives modes that are M-orthonormal
  // and K-orthogonal to round-off whatever the Lanczos residuals were, so that callers that
  // assume ΦᵀMΦ = I and ΦᵀKΦ = diag(ω²) (Craig–Bampton's reduced matrices) hold exactly. Cost:
  // two products of n x m by m x m (BLAS), m = the modes returned.
  const Eigen::Index m = values.size();
  result.eigenvalues.resize(m);
  result.modes.resize(n, m);
  if (m > 0) {
    const Eigen::MatrixXd M_vectors = block_product(RowSparse(M), vectors);
    Eigen::MatrixXd A(m, m), B(m, m);
    blas_gemm('T', 'N', m, m, n, 1.0, vectors.data(), n, M_vectors.data(), n, 0.0, A.data(), m);
    blas_gemm('T', 'N', m, m, n, 1.0, coordinates.data(), n, coordinates.data(), n, 0.0, B.data(),
              m);
    A = (0.5 * (A + A.transpose())).eval();
    B = (0.5 * (B + B.transpose())).eval();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ritz(B, A);
    if (ritz.info() != Eigen::Success) {
      summary.termination = ModalTermination::kNotConverged;
      summary.message = "the Lanczos vectors are linearly dependent in the M inner product (" +
                        std::to_string(m) + " modes): no M-orthonormal basis";
      summary.iteration_seconds = seconds_since(start);
      result.eigenvalues.resize(0);
      result.modes.resize(n, 0);
      return result;
    }
    result.eigenvalues = (ritz.eigenvalues().array() + options.shift).matrix();
    const Eigen::MatrixXd S = ritz.eigenvectors();  // Sᵀ A S = I, ascending μ
    blas_gemm('N', 'N', n, m, m, 1.0, vectors.data(), n, S.data(), m, 0.0, result.modes.data(), n);
    for (Eigen::Index j = 0; j < m; ++j) {  // deterministic sign
      auto phi = result.modes.col(j);
      if (phi(sign_component(phi)) < 0.0) phi = -phi;
    }
  }

  if (converged) {
    summary.termination = ModalTermination::kConverged;
    summary.message = std::to_string(nev) + " modes converged: " + method +
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

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

ModalResult dense_modes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M) {
  const Eigen::Index n = K.rows();
  require(K.cols() == n && M.rows() == n && M.cols() == n, "K, M",
          std::to_string(K.rows()) + " x " + std::to_string(K.cols()) + ", " +
              std::to_string(M.rows()) + " x " + std::to_string(M.cols()),
          "square and of the same size");
  ModalResult result;
  ModalSummary& summary = result.summary;
  const auto start = std::chrono::steady_clock::now();
  const Eigen::VectorXd diagonal = M.diagonal();
  if (n > 0 && !(diagonal.minCoeff() > 0.0)) {
    summary.termination = ModalTermination::kFactorizationFailed;
    summary.message = "the mass matrix has a diagonal entry <= 0: not positive definite";
    return result;
  }
  const Eigen::VectorXd d = diagonal.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Ks = d.asDiagonal() * (0.5 * (K + K.transpose())) * d.asDiagonal();
  const Eigen::MatrixXd Ms = d.asDiagonal() * (0.5 * (M + M.transpose())) * d.asDiagonal();
  // A singular M (a rank-deficient mass rule: C3D20R, C3D4 or C3D8R integrated with CalculiX's
  // stiffness rule) has massless modes, of infinite frequency: the generalised solve would return
  // garbage for them. Ms has a unit diagonal, so its Cholesky pivots are <= 1; one below
  // kSingularMassPivot is a singular M to round-off.
  constexpr double kSingularMassPivot = 1e-13;
  {
    const Eigen::LLT<Eigen::MatrixXd> llt(Ms);
    if (n > 0 && (llt.info() != Eigen::Success ||
                  !(llt.matrixLLT().diagonal().cwiseAbs2().minCoeff() >= kSingularMassPivot))) {
      summary.termination = ModalTermination::kFactorizationFailed;
      summary.message =
          "the mass matrix is singular or not positive definite (massless modes: a "
          "rank-deficient mass rule such as mass_rule: calculix with C3D20R, C3D4 or C3D8R "
          "elements needs fewer modes than DOFs)";
      return result;
    }
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(Ks, Ms);
  summary.iteration_seconds = seconds_since(start);
  if (eig.info() != Eigen::Success) {
    summary.termination = ModalTermination::kFactorizationFailed;
    summary.message = "the mass matrix is not positive definite";
    return result;
  }
  result.eigenvalues = eig.eigenvalues();
  result.modes = d.asDiagonal() * eig.eigenvectors();  // Φᵀ M Φ = I
  for (Eigen::Index j = 0; j < n; ++j) {
    auto phi = result.modes.col(j);
    if (phi(sign_component(phi)) < 0.0) phi = -phi;
  }
  summary.termination = ModalTermination::kConverged;
  summary.converged_modes = static_cast<int>(n);
  summary.message = std::to_string(n) + " modes by a dense eigen-solve";
  return result;
}

ModalResult dense_modes(const SparseMatrix& K, const SparseMatrix& M) {
  return dense_modes(Eigen::MatrixXd(K), Eigen::MatrixXd(M));
}

}  // namespace stickslip
