#include "linalg/modal.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>
#include <vector>

#include "core/errors.h"

namespace stickslip {
namespace {

// Lanczos tolerance 1e-10 on Ritz values plus round-off of a well-conditioned chain.
constexpr double kEigenvalueTolerance = 1e-9;
// Residuals and orthogonality are governed by the same tolerance (square root: vectors converge
// like the square root of the Ritz values) and by round-off in (K − σM)⁻¹.
constexpr double kResidualTolerance = 1e-6;
constexpr double kOrthogonalityTolerance = 1e-9;
// Two solves of the same problem (different shift or factor): mass-normalised modes agree to
// about the square root of the Lanczos tolerance.
constexpr double kSameModeTolerance = 1e-6;

// Spring–mass chain: n masses m joined by springs k; `fixed` adds a spring to ground at each end.
void chain(int n, double k, double m, bool fixed, SparseMatrix* K, SparseMatrix* M) {
  std::vector<Triplet> kt;
  std::vector<Triplet> mt;
  for (int i = 0; i < n; ++i) {
    mt.emplace_back(i, i, m);
    const bool has_left = i > 0 || fixed;
    const bool has_right = i + 1 < n || fixed;
    kt.emplace_back(i, i, k * ((has_left ? 1 : 0) + (has_right ? 1 : 0)));
    if (i + 1 < n) {
      kt.emplace_back(i, i + 1, -k);
      kt.emplace_back(i + 1, i, -k);
    }
  }
  K->resize(n, n);
  M->resize(n, n);
  K->setFromTriplets(kt.begin(), kt.end());
  M->setFromTriplets(mt.begin(), mt.end());
}

void expect_modal_properties(const SparseMatrix& K, const SparseMatrix& M, const ModalResult& r) {
  const int count = static_cast<int>(r.eigenvalues.size());
  ASSERT_EQ(r.modes.cols(), count);
  for (int j = 1; j < count; ++j) EXPECT_LE(r.eigenvalues(j - 1), r.eigenvalues(j));
  const Eigen::MatrixXd MPhi = M * r.modes;
  const Eigen::MatrixXd KPhi = K * r.modes;
  const Eigen::MatrixXd gram = r.modes.transpose() * MPhi;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(count, count)).cwiseAbs().maxCoeff(),
            kOrthogonalityTolerance);
  for (int j = 0; j < count; ++j) {
    const Eigen::VectorXd residual = KPhi.col(j) - r.eigenvalues(j) * MPhi.col(j);
    // Scale: ||Kφ||, or ||Mφ|| for a rigid-body mode where Kφ ≈ 0.
    const double scale = std::max(KPhi.col(j).norm(), MPhi.col(j).norm());
    EXPECT_LT(residual.norm() / scale, kResidualTolerance) << "mode " << j;
    // Sign convention: the first component within 1e-4 of the largest magnitude is positive.
    const Eigen::VectorXd a = r.modes.col(j).cwiseAbs();
    Eigen::Index first = 0;
    while (a(first) < (1.0 - 1e-4) * a.maxCoeff()) ++first;
    EXPECT_GT(r.modes(first, j), 0.0) << "sign convention, mode " << j;
  }
}

TEST(SolveModes, FixedFixedChainMatchesClosedForm) {
  const int n = 200;
  const double k = 3.0e6;
  const double m = 0.25;
  SparseMatrix K, M;
  chain(n, k, m, /*fixed=*/true, &K, &M);
  // Single-vector Lanczos (block 1, automatic for this size) and block Lanczos (4 and 7 vectors
  // per step: 7 does not divide the basis evenly into num_modes).
  for (int block : {0, 4, 7}) {
    ModalOptions options;
    options.num_modes = 12;
    options.block_size = block;
    const ModalResult r = solve_modes(K, M, options);
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    EXPECT_EQ(r.summary.block_size, block == 0 ? 1 : block) << r.summary.message;
    ASSERT_EQ(r.eigenvalues.size(), options.num_modes);
    for (int j = 1; j <= options.num_modes; ++j) {
      const double s = std::sin(j * kPi / (2.0 * (n + 1)));
      const double exact = 4.0 * k / m * s * s;
      EXPECT_NEAR(r.eigenvalues(j - 1), exact, kEigenvalueTolerance * exact)
          << "mode " << j << ", block " << block;
    }
    expect_modal_properties(K, M, r);
    EXPECT_NEAR(r.frequencies_hz()(0), std::sqrt(r.eigenvalues(0)) / (2 * kPi), 1e-12);
  }
}

TEST(SolveModes, FreeChainHasOneRigidModeWithNegativeShift) {
  const int n = 50;
  const double k = 1.0;
  const double m = 1.0;
  SparseMatrix K, M;
  chain(n, k, m, /*fixed=*/false, &K, &M);
  ModalOptions options;
  options.num_modes = 6;  // default shift −1 < 0 = lowest eigenvalue
  const ModalResult r = solve_modes(K, M, options);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  // Rigid mode: ω² = 0 up to round-off relative to the largest eigenvalue 4k/m.
  EXPECT_NEAR(r.eigenvalues(0), 0.0, kEigenvalueTolerance * 4.0 * k / m);
  // and uniform translation with φᵀMφ = 1: every component 1/sqrt(n m).
  for (int i = 0; i < n; ++i) EXPECT_NEAR(r.modes(i, 0), 1.0 / std::sqrt(n * m), 1e-9);
  for (int j = 1; j < options.num_modes; ++j) {
    const double s = std::sin(j * kPi / (2.0 * n));
    const double exact = 4.0 * k / m * s * s;
    EXPECT_NEAR(r.eigenvalues(j), exact, kEigenvalueTolerance * exact) << "mode " << j;
  }
  expect_modal_properties(K, M, r);
}

TEST(SolveModes, RandomGeneralisedProblemMatchesDenseSolver) {
  const int n = 120;
  std::mt19937 rng(20261121);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::uniform_int_distribution<int> index(0, n - 1);
  // K = Bᵀ B + small diagonal (SPD), M = diag + sparse symmetric coupling (SPD by dominance).
  std::vector<Triplet> bt, mt;
  for (int i = 0; i < n; ++i) {
    bt.emplace_back(i, i, 2.0 + value(rng));
    mt.emplace_back(i, i, 3.0 + value(rng));
  }
  for (int c = 0; c < 4 * n; ++c) bt.emplace_back(index(rng), index(rng), value(rng));
  for (int c = 0; c < n; ++c) {
    const int i = index(rng), j = index(rng);
    if (i == j) continue;
    const double v = 0.4 * value(rng);
    mt.emplace_back(i, j, v);
    mt.emplace_back(j, i, v);
  }
  SparseMatrix B(n, n), M(n, n);
  B.setFromTriplets(bt.begin(), bt.end());
  M.setFromTriplets(mt.begin(), mt.end());
  // Dominance: each row of M has at most a few couplings of size <= 0.4; diagonal >= 2.
  const SparseMatrix K = SparseMatrix(B.transpose()) * B;

  const Eigen::MatrixXd K_dense = Eigen::MatrixXd(K);
  const Eigen::MatrixXd M_dense = Eigen::MatrixXd(M);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(K_dense, M_dense);
  ASSERT_EQ(dense.info(), Eigen::Success);
  const double scale = dense.eigenvalues().maxCoeff();
  // Single-vector Lanczos; block Lanczos with room for the whole space (it must stop there);
  // block Lanczos with the default room, which may fall back to the single-vector method on
  // this clustered random spectrum: the modes must be right either way.
  struct Case {
    int block, subspace, expected_block;
  };
  for (const Case c : {Case{1, 0, 1}, Case{5, 115, 5}, Case{5, 0, 0}}) {
    const int block = c.block;
    ModalOptions options;
    options.num_modes = 15;
    options.block_size = c.block;
    options.subspace_size = c.subspace;
    const ModalResult r = solve_modes(K, M, options);
    ASSERT_TRUE(r.summary.ok()) << r.summary.message;
    if (c.expected_block > 0) {
      EXPECT_EQ(r.summary.block_size, c.expected_block);
    }
    for (int j = 0; j < options.num_modes; ++j) {
      EXPECT_NEAR(r.eigenvalues(j), dense.eigenvalues()(j), kEigenvalueTolerance * scale)
          << "mode " << j << ", block " << block;
    }
    expect_modal_properties(K, M, r);
  }
}

TEST(SolveModes, ExplicitSubspaceAndZeroShiftGiveTheSameModes) {
  SparseMatrix K, M;
  chain(80, 5.0, 2.0, /*fixed=*/true, &K, &M);
  ModalOptions a;
  a.num_modes = 5;
  ModalOptions b = a;
  b.shift = 0.0;
  b.subspace_size = 7;
  const ModalResult ra = solve_modes(K, M, a);
  const ModalResult rb = solve_modes(K, M, b);
  ASSERT_TRUE(ra.summary.ok()) << ra.summary.message;
  ASSERT_TRUE(rb.summary.ok()) << rb.summary.message;
  for (int j = 0; j < a.num_modes; ++j) {
    EXPECT_NEAR(ra.eigenvalues(j), rb.eigenvalues(j), kEigenvalueTolerance * ra.eigenvalues(j));
    // Same sign convention: the same vector, not its negative.
    EXPECT_LT((ra.modes.col(j) - rb.modes.col(j)).norm(), 1e-6);
  }
}

TEST(SolveModes, GivenFactorOfKWithZeroShiftMatchesDenseSolver) {
  // Fixed-fixed chain with a non-uniform mass (so modes are not the closed-form sines): the
  // overload reuses a caller's Cholesky of K (σ = 0) and must give the dense generalised
  // eigenpairs, like the factorising overload.
  const int n = 90;
  SparseMatrix K, M;
  chain(n, 7.0, 1.0, /*fixed=*/true, &K, &M);
  for (int i = 0; i < n; ++i) M.coeffRef(i, i) = 1.0 + 0.5 * std::sin(0.3 * i) * std::sin(0.3 * i);
  const SparseCholesky factor(K);
  ASSERT_TRUE(factor.ok()) << factor.message();
  ModalOptions options;
  options.num_modes = 8;
  options.shift = 0.0;
  const ModalResult r = solve_modes(factor, M, options);
  ASSERT_TRUE(r.summary.ok()) << r.summary.message;
  EXPECT_EQ(r.summary.factorization_seconds, 0.0);

  const Eigen::MatrixXd K_dense = Eigen::MatrixXd(K);
  const Eigen::MatrixXd M_dense = Eigen::MatrixXd(M);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(K_dense, M_dense);
  ASSERT_EQ(dense.info(), Eigen::Success);
  for (int j = 0; j < options.num_modes; ++j) {
    EXPECT_NEAR(r.eigenvalues(j), dense.eigenvalues()(j),
                kEigenvalueTolerance * dense.eigenvalues().maxCoeff())
        << "mode " << j;
  }
  expect_modal_properties(K, M, r);

  const ModalResult own = solve_modes(K, M, options);  // its own factorisation of K
  ASSERT_TRUE(own.summary.ok()) << own.summary.message;
  for (int j = 0; j < options.num_modes; ++j)
    EXPECT_LT((own.modes.col(j) - r.modes.col(j)).norm(), kSameModeTolerance) << "mode " << j;
}

TEST(SolveModes, GivenFactorMustBeValidAndMatchM) {
  SparseMatrix K, M;
  chain(20, 1.0, 1.0, /*fixed=*/true, &K, &M);
  ModalOptions options;
  options.num_modes = 3;
  options.shift = 0.0;
  const SparseCholesky empty;
  EXPECT_THROW(solve_modes(empty, M, options), InvalidInput);
  SparseMatrix K_small, M_small;
  chain(10, 1.0, 1.0, /*fixed=*/true, &K_small, &M_small);
  const SparseCholesky small(K_small);
  ASSERT_TRUE(small.ok());
  EXPECT_THROW(solve_modes(small, M, options), InvalidInput);
}

TEST(SolveModes, InvalidOptionsThrow) {
  SparseMatrix K, M;
  chain(10, 1.0, 1.0, true, &K, &M);
  auto with = [](auto edit) {
    ModalOptions o;
    o.num_modes = 3;
    edit(o);
    return o;
  };
  EXPECT_THROW(validate(with([](ModalOptions& o) { o.num_modes = 0; })), InvalidInput);
  EXPECT_THROW(validate(with([](ModalOptions& o) { o.shift = std::nan(""); })), InvalidInput);
  EXPECT_THROW(validate(with([](ModalOptions& o) { o.subspace_size = 3; })), InvalidInput);
  EXPECT_THROW(validate(with([](ModalOptions& o) { o.tolerance = 0.0; })), InvalidInput);
  EXPECT_THROW(validate(with([](ModalOptions& o) { o.max_iterations = 0; })), InvalidInput);
  EXPECT_NO_THROW(validate(with([](ModalOptions&) {})));
  // Size rules need the matrices.
  EXPECT_THROW(solve_modes(K, M, with([](ModalOptions& o) { o.num_modes = 10; })), InvalidInput);
  EXPECT_THROW(solve_modes(K, M, with([](ModalOptions& o) { o.subspace_size = 11; })),
               InvalidInput);
  SparseMatrix M_small, K_small;
  chain(9, 1.0, 1.0, true, &K_small, &M_small);
  EXPECT_THROW(solve_modes(K, M_small, with([](ModalOptions&) {})), InvalidInput);
  try {
    validate(with([](ModalOptions& o) { o.num_modes = -2; }));
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("num_modes"), std::string::npos) << e.what();
  }
}

TEST(SolveModes, IndefiniteShiftedMatrixGivesFactorisationFailureSummary) {
  SparseMatrix K, M;
  chain(30, 1.0, 1.0, /*fixed=*/true, &K, &M);
  // A shift above the lowest eigenvalue makes K − σM indefinite.
  ModalOptions options;
  options.num_modes = 4;
  options.shift = 0.5;  // lowest eigenvalue 4 sin²(π/62) ≈ 0.0103
  ModalResult r = solve_modes(K, M, options);
  EXPECT_EQ(r.summary.termination, ModalTermination::kFactorizationFailed);
  EXPECT_FALSE(r.summary.ok());
  EXPECT_NE(r.summary.message.find("not positive definite"), std::string::npos)
      << r.summary.message;
  EXPECT_EQ(r.eigenvalues.size(), 0);

  // An indefinite K (a negative spring) with the default negative shift fails the same way.
  SparseMatrix K_bad = K;
  K_bad.coeffRef(10, 10) = -5.0;
  r = solve_modes(K_bad, M, ModalOptions{.num_modes = 4});
  EXPECT_EQ(r.summary.termination, ModalTermination::kFactorizationFailed);
  EXPECT_NE(r.summary.message.find("not positive definite"), std::string::npos)
      << r.summary.message;
}

TEST(SolveModes, TooFewIterationsAreReportedAsNotConverged) {
  SparseMatrix K, M;
  chain(2000, 1.0, 1.0, /*fixed=*/true, &K, &M);
  ModalOptions options;
  options.num_modes = 20;
  options.subspace_size = 21;  // minimal Krylov space, clustered low spectrum
  options.max_iterations = 1;
  options.tolerance = 1e-14;
  const ModalResult r = solve_modes(K, M, options);
  EXPECT_EQ(r.summary.termination, ModalTermination::kNotConverged);
  EXPECT_LT(r.summary.converged_modes, options.num_modes);
  EXPECT_NE(r.summary.message.find("did not converge"), std::string::npos) << r.summary.message;
}

}  // namespace
}  // namespace stickslip
