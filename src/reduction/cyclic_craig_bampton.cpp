#include "reduction/cyclic_craig_bampton.h"

#include <algorithm>
#include <complex>
#include <string>

#include <Eigen/Eigenvalues>

#include "core/errors.h"

namespace stickslip {
namespace {

using Complex = std::complex<double>;

// The Hermitian matrix A + iB of a real form [A −B; B A] (2n square): A its top-left block, B its
// bottom-left block.
ComplexSparseMatrix hermitian_of(const SparseMatrix& real_form, Eigen::Index n) {
  const SparseMatrix A = real_form.block(0, 0, n, n);
  const SparseMatrix B = real_form.block(n, 0, n, n);
  return A.cast<Complex>() + Complex(0, 1) * B.cast<Complex>();
}

// Columns of a real-form basis (2n rows, (x; y)) as complex vectors x + iy.
Eigen::MatrixXcd complex_columns(const Eigen::MatrixXd& X, Eigen::Index n, Eigen::Index first,
                                 Eigen::Index count) {
  return X.block(0, first, n, count).cast<Complex>() +
         Complex(0, 1) * X.block(n, first, n, count).cast<Complex>();
}

// The Ritz step keeps the directions of the M-Gram matrix of the complex mode vectors above this
// fraction of its largest eigenvalue. The pairs (x; y), (−y; x) of the real form give complex
// vectors z and iz: exactly dependent, so the Gram matrix (unit diagonal: the real modes are
// M-normalised) has eigenvalues 2 and 0 up to the eigen-solve's round-off (~1e-10); 1e-6 separates
// the two by orders of magnitude either way.
constexpr double kRitzRankTolerance = 1e-6;
// Vectors per Lanczos step of the real form's fixed-interface eigen-solve (see above).
constexpr int kPairBlockSize = 4;

}  // namespace

CyclicReducedSector cyclic_craig_bampton(const SparseMatrix& K, const SparseMatrix& M, bool doubled,
                                         int nodal_diameter, std::span<const int> boundary,
                                         const CraigBamptonOptions& options) {
  validate(options);
  const Eigen::Index size = K.rows();
  if (K.cols() != size || M.rows() != size || M.cols() != size || (doubled && size % 2 != 0)) {
    throw InvalidInput(
        "cyclic_craig_bampton: K and M must be square of the same size (even when "
        "doubled), got " +
        std::to_string(K.rows()) + " x " + std::to_string(K.cols()) + " and " +
        std::to_string(M.rows()) + " x " + std::to_string(M.cols()));
  }
  const Eigen::Index n = doubled ? size / 2 : size;
  std::vector<int> real_boundary(boundary.begin(), boundary.end());
  for (int b : boundary) {
    if (b < 0 || b >= n) {
      throw InvalidInput("cyclic_craig_bampton: boundary index " + std::to_string(b) +
                         " is outside the sector's " + std::to_string(n) + " independent DOFs");
    }
  }
  if (doubled) {
    for (int b : boundary) real_boundary.push_back(static_cast<int>(n) + b);
  }
  CraigBamptonOptions real_options = options;
  real_options.keep_basis = true;  // the complex basis is made from it
  if (doubled) {
    real_options.num_modes = 2 * options.num_modes;
    // Every fixed-interface eigenvalue of the real form is double: a Lanczos block of at least
    // 2 finds both copies (a single-vector Krylov space holds one in exact arithmetic).
    real_options.modal.block_size = std::max(real_options.modal.block_size, kPairBlockSize);
    real_options.hermitian_real_form = true;  // half the constraint modes solved
  }

  CyclicReducedSector out;
  out.nodal_diameter = nodal_diameter;
  out.boundary.assign(boundary.begin(), boundary.end());
  CraigBamptonResult cb = craig_bampton(K, M, {}, real_boundary, real_options);
  out.summary = cb.summary;
  if (!cb.summary.ok()) return out;
  const Eigen::Index nb = static_cast<Eigen::Index>(boundary.size());

  if (!doubled) {  // h = 0 or N/2: real, nothing to pair
    out.K = cb.body.K.cast<Complex>();
    out.M = cb.body.M.cast<Complex>();
    out.mode_eigenvalues = cb.mode_eigenvalues;
    if (options.keep_basis) out.T = cb.T.cast<Complex>();
    return out;
  }

  const ComplexSparseMatrix Kc = hermitian_of(K, n), Mc = hermitian_of(M, n);
  const Eigen::Index real_modes = cb.T.cols() - 2 * nb;
  // Rayleigh–Ritz in the span of the complex mode vectors: an M-orthonormal basis Q of it from
  // the Gram matrix's dominant eigenvectors, then the Hermitian eigen-problem Qᴴ K Q.
  Eigen::MatrixXcd modes(n, 0);
  Eigen::MatrixXcd coefficients(real_modes, 0);  // modes = Z coefficients
  Eigen::VectorXd eigenvalues(0);
  if (real_modes > 0) {
    const Eigen::MatrixXcd Z = complex_columns(cb.T, n, 2 * nb, real_modes);
    const Eigen::MatrixXcd MZ = Mc * Z;
    Eigen::MatrixXcd G = Z.adjoint() * MZ;
    G = 0.5 * (G + G.adjoint()).eval();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> gram(G);
    const Eigen::VectorXd& g = gram.eigenvalues();
    const double largest = g.maxCoeff();
    std::vector<Eigen::Index> kept;
    for (Eigen::Index j = 0; j < g.size(); ++j) {
      if (g(j) > kRitzRankTolerance * largest) kept.push_back(j);
    }
    if (2 * static_cast<Eigen::Index>(kept.size()) != real_modes) {
      out.summary.termination = CraigBamptonTermination::kEigenSolveFailed;
      out.summary.message =
          "nodal diameter " + std::to_string(nodal_diameter) + ": the " +
          std::to_string(real_modes) + " fixed-interface modes of the real form span " +
          std::to_string(kept.size()) + " complex modes, not " + std::to_string(real_modes / 2) +
          " (a pair (x; y), (-y; x) of one complex mode was split by the eigen-solve)";
      return out;
    }
    Eigen::MatrixXcd W(real_modes, static_cast<Eigen::Index>(kept.size()));  // Q = Z W
    for (size_t c = 0; c < kept.size(); ++c) {
      W.col(static_cast<Eigen::Index>(c)) =
          gram.eigenvectors().col(kept[c]) / std::sqrt(g(kept[c]));
    }
    const Eigen::MatrixXcd Q = Z * W;
    Eigen::MatrixXcd H = Q.adjoint() * (Kc * Q);
    H = 0.5 * (H + H.adjoint()).eval();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> ritz(H);
    eigenvalues = ritz.eigenvalues();
    coefficients = W * ritz.eigenvectors();
    modes = Q * ritz.eigenvectors();
  }
  out.summary.num_modes = static_cast<int>(modes.cols());
  out.summary.num_rigid_modes /= 2;
  out.summary.num_boundary = static_cast<int>(nb);
  out.summary.num_interior = static_cast<int>(n - nb);
  out.summary.num_dofs = static_cast<int>(n);
  out.mode_eigenvalues = eigenvalues;

  // The reduced matrices from the real form's, without products of size n (docs/cyclic.md,
  // "Reduction per nodal diameter"). For complex vectors u, v with real forms U, V:
  //   uᴴ K_h v = Uᵀ K V − i Uᵀ K J V,  J(x; y) = (−y; x) (the real form of i·),
  // and J commutes with K and M. The real form's constraint mode of boundary DOF n + b is J times
  // that of b (their equations are J times each other's), so Uᵀ K J V = −(J U)ᵀ K V is a block of
  // the real form's K_r: for constraint modes u = z_j, v = z_l (real-form reduced DOFs j, l; J z_j
  // is nb + j), z_jᴴ K_h z_l = K_r(j, l) + i K_r(nb + j, l), and for a real-form mode y_i (reduced
  // DOF 2nb + i) z_jᴴ M_h (x_i + i y_i) = M_r(j, 2nb + i) + i M_r(nb + j, 2nb + i). The kept modes
  // are combinations of those, Φ_n = Z C; Kᴴ-orthogonality of constraint and fixed-interface
  // modes and the Ritz step's Φ_nᴴ K Φ_n = Ω², Φ_nᴴ M Φ_n = I give the other blocks, as
  // craig_bampton sets them for a real body.
  const Eigen::MatrixXd& Kreal = cb.body.K;
  const Eigen::MatrixXd& Mreal = cb.body.M;
  const Eigen::Index nr = nb + modes.cols();
  Eigen::MatrixXcd Kr = Eigen::MatrixXcd::Zero(nr, nr), Mr = Eigen::MatrixXcd::Zero(nr, nr);
  Kr.topLeftCorner(nb, nb).real() = Kreal.topLeftCorner(nb, nb);
  Kr.topLeftCorner(nb, nb).imag() = Kreal.block(nb, 0, nb, nb);
  Mr.topLeftCorner(nb, nb).real() = Mreal.topLeftCorner(nb, nb);
  Mr.topLeftCorner(nb, nb).imag() = Mreal.block(nb, 0, nb, nb);
  if (modes.cols() > 0) {
    Eigen::MatrixXcd Mbz(nb, real_modes);  // z_jᴴ M_h (x_i + i y_i)
    Mbz.real() = Mreal.block(0, 2 * nb, nb, real_modes);
    Mbz.imag() = Mreal.block(nb, 2 * nb, nb, real_modes);
    Kr.bottomRightCorner(modes.cols(), modes.cols()).diagonal() = eigenvalues.cast<Complex>();
    Mr.topRightCorner(nb, modes.cols()) = Mbz * coefficients;
    Mr.bottomLeftCorner(modes.cols(), nb) = Mr.topRightCorner(nb, modes.cols()).adjoint();
    Mr.bottomRightCorner(modes.cols(), modes.cols()).setIdentity();
  }
  out.K = 0.5 * (Kr + Kr.adjoint());
  out.M = 0.5 * (Mr + Mr.adjoint());
  if (options.keep_basis) {
    Eigen::MatrixXcd T(n, nr);
    T.leftCols(nb) = complex_columns(cb.T, n, 0, nb);
    T.rightCols(modes.cols()) = modes;
    out.T = std::move(T);
  }
  return out;
}

}  // namespace stickslip
