#include "reduction/craig_bampton.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/parallel.h"
#include "linalg/blas.h"
#include "linalg/floating_factor.h"
#include "linalg/sparse_cholesky.h"
#include "linalg/sparse_ops.h"

namespace stickslip {
namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU seconds (user + system) of the whole process so far, all threads.
double process_cpu_seconds() {
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// C (m x n, column-major, leading dimension ldc) = op(A) op(B) through BLAS dgemm.
void gemm(char transa, char transb, int m, int n, int k, const double* a, int lda, const double* b,
          int ldb, double* c, int ldc) {
  if (m == 0 || n == 0) return;
  const double one = 1.0, zero = 0.0;
  if (k == 0) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < m; ++i) c[static_cast<size_t>(j) * ldc + i] = 0.0;
    return;
  }
  dgemm_(&transa, &transb, &m, &n, &k, &one, a, &lda, b, &ldb, &zero, c, &ldc);
}

// Rows of a sparse product per thread at least: a row costs an axpy per nonzero (≈ 80 of them,
// on rows of 8–30 entries), so 1024 rows take ~1 ms, far more than starting a thread (~30 µs).
constexpr std::ptrdiff_t kRowsPerThread = 1024;

// Y (rows of A x cols) = A X for A sparse row-major and X, Y dense row-major: one pass over A,
// each nonzero an axpy on a contiguous row (cols = first `cols` columns of X). The rows are split
// over the hardware threads (parallel_for; the product is memory-bound).
void sparse_times_rows(const RowSparse& A, const RowMatrix& X, int cols, RowMatrix& Y) {
  Y.resize(A.rows(), cols);
  parallel_for(
      A.outerSize(), thread_count(),
      [&](std::ptrdiff_t r0, std::ptrdiff_t r1, int) {
        for (Eigen::Index r = r0; r < r1; ++r) {
          auto y = Y.row(r);
          y.setZero();
          for (RowSparse::InnerIterator it(A, r); it; ++it) {
            y.noalias() += it.value() * X.row(it.col()).head(cols);
          }
        }
      },
      kRowsPerThread);
}

// T(rows[r], :) = Psi(r, :) for column-major T and row-major Psi, in column strips so that
// both are walked with short strides.
void scatter_rows(const RowMatrix& Psi, const std::vector<int>& rows, Eigen::MatrixXd& T) {
  constexpr int kStrip = 8;
  const int nr = static_cast<int>(Psi.cols());
  for (int c0 = 0; c0 < nr; c0 += kStrip) {
    const int cs = std::min(kStrip, nr - c0);
    for (size_t r = 0; r < rows.size(); ++r) {
      const double* source = Psi.data() + r * static_cast<size_t>(nr) + c0;
      double* target = T.data() + static_cast<size_t>(c0) * T.rows() + rows[r];
      for (int c = 0; c < cs; ++c) target[static_cast<size_t>(c) * T.rows()] = source[c];
    }
  }
}

// G (cols of A x cols of X) = Aᵀ X for A sparse column-major (rows of A index the rows of X).
Eigen::MatrixXd transpose_times_rows(const SparseMatrix& A, const RowMatrix& X) {
  RowMatrix G = RowMatrix::Zero(A.cols(), X.cols());
  for (int j = 0; j < A.outerSize(); ++j) {
    auto g = G.row(j);
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      g.noalias() += it.value() * X.row(it.row());
  }
  return G;
}

// Column blocks of the symmetric product Φ_cᵀ M_ii Φ_c.
constexpr int kSymmetricBlock = 128;

std::vector<int> all_columns(int n) {
  std::vector<int> c(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j) c[static_cast<size_t>(j)] = j;
  return c;
}

void check_dof_list(std::span<const int> dofs, int n, const char* field, std::vector<char>& mark,
                    char tag) {
  for (size_t k = 0; k < dofs.size(); ++k) {
    const int d = dofs[k];
    if (d < 0 || d >= n) {
      throw InvalidInput(std::string("craig_bampton: ") + field + "[" + std::to_string(k) +
                         "] = " + std::to_string(d) + " is outside 0.." + std::to_string(n - 1));
    }
    if (mark[d] == tag) {
      throw InvalidInput(std::string("craig_bampton: ") + field + " lists DOF " +
                         std::to_string(d) + " twice");
    }
    if (mark[d] != 0) {
      throw InvalidInput("craig_bampton: DOF " + std::to_string(d) +
                         " is both constrained and boundary");
    }
    mark[d] = tag;
  }
}

// ---------------------------------------------------------------------------------------------
// Floating interior: K_ii singular because the boundary and the constraints do not hold every
// rigid motion of the body (no masters: a free–free body; one master node: three rotations; a
// damper held by one contact patch in some directions only). See craig_bampton.h.

// The kept fixed-interface modes of a floating interior (every rigid mode of the interior plus
// the num_modes lowest elastic ones, at most every interior mode) and its constraint modes
// Φ_c = −K_ii⁺ K_ib (the particular solution M-orthogonal to the rigid modes: K_ib's columns are
// orthogonal to null(K_ii), so K_ii Φ_c = −K_ib has solutions), written into Psi's first n_b
// columns; both from linalg's FloatingFactor (one factor of K_ii − σM_ii, refinement).
struct FloatingModes {
  bool ok = false;
  bool factor_failed = false;  // K_ii − σM_ii not positive definite (else the eigen-solve failed)
  std::string message;
  double shift = 0.0;           // σ of the factor, (rad/s)²
  int num_rigid = 0;            // the first num_rigid modes are rigid (eigenvalue set to 0)
  Eigen::VectorXd eigenvalues;  // kept modes, ascending
  ModalSummary modal;
  int refinement_steps = 0;  // most steps any block of constraint modes took
};

FloatingModes floating_interior(const SparseMatrix& K_ii, const SparseMatrix& M_ii,
                                const SparseMatrix& K_ib, int num_modes,
                                const CraigBamptonOptions& options, RowMatrix& Psi) {
  FloatingModes out;
  const int ni = static_cast<int>(K_ii.rows());
  const int nb = static_cast<int>(K_ib.cols());
  FloatingFactor factor;
  factor.compute(K_ii, M_ii, {.num_elastic_modes = num_modes, .modal = options.modal});
  out.modal = factor.modal_summary();
  out.shift = factor.shift();
  if (!factor.ok()) {
    out.factor_failed = factor.factor_failed();
    out.message = (factor.factor_failed() ? "" : "fixed-interface ") + factor.message();
    return out;
  }
  out.num_rigid = factor.num_rigid();
  out.eigenvalues = factor.eigenvalues();
  const Eigen::Index kept = out.eigenvalues.size();
  Psi.resize(ni, nb + kept);
  for (int c0 = 0; c0 < nb; c0 += options.block_size) {
    const int bs = std::min(options.block_size, nb - c0);
    FloatingSolveSummary solved;
    Psi.middleCols(c0, bs) = factor.solve(-Eigen::MatrixXd(K_ib.middleCols(c0, bs)), &solved);
    if (!solved.converged) {
      out.message = "the constraint modes of the floating interior did not converge in " +
                    std::to_string(solved.steps) + " refinement steps (residual " +
                    std::to_string(solved.residual) +
                    " of ‖K_ib‖): the first elastic eigenvalue not kept is too close to the "
                    "shift; keep more modes";
      return out;
    }
    out.refinement_steps = std::max(out.refinement_steps, solved.steps);
  }
  Psi.rightCols(kept) = factor.modes();
  out.ok = true;
  return out;
}

}  // namespace

void validate(const CraigBamptonOptions& options) {
  require(options.num_modes >= 0, "CraigBamptonOptions::num_modes",
          std::to_string(options.num_modes), "num_modes >= 0");
  require(options.block_size >= 1, "CraigBamptonOptions::block_size",
          std::to_string(options.block_size), "block_size >= 1");
  if (options.num_modes > 0) {
    ModalOptions modal = options.modal;
    modal.num_modes = options.num_modes;
    validate(modal);
  }
}

CraigBamptonResult craig_bampton(const SparseMatrix& K, const SparseMatrix& M,
                                 std::span<const int> constrained_dofs,
                                 std::span<const int> boundary_dofs,
                                 const CraigBamptonOptions& options) {
  validate(options);
  const int n = static_cast<int>(K.rows());
  if (K.cols() != n || M.rows() != n || M.cols() != n) {
    throw InvalidInput("craig_bampton: K (" + std::to_string(K.rows()) + " x " +
                       std::to_string(K.cols()) + ") and M (" + std::to_string(M.rows()) + " x " +
                       std::to_string(M.cols()) + ") must be square and of the same size");
  }
  std::vector<char> mark(static_cast<size_t>(n), 0);
  check_dof_list(constrained_dofs, n, "constrained_dofs", mark, 1);
  check_dof_list(boundary_dofs, n, "boundary_dofs", mark, 2);

  CraigBamptonResult result;
  CraigBamptonSummary& summary = result.summary;
  std::vector<int>& interior = result.interior_dofs;
  for (int d = 0; d < n; ++d)
    if (mark[d] == 0) interior.push_back(d);
  const std::vector<int> boundary(boundary_dofs.begin(), boundary_dofs.end());
  const int nb = static_cast<int>(boundary.size());
  const int ni = static_cast<int>(interior.size());
  int nm = options.num_modes;  // a floating interior keeps its rigid modes beside these
  summary.num_dofs = n;
  summary.num_constrained = static_cast<int>(constrained_dofs.size());
  summary.num_boundary = nb;
  summary.num_interior = ni;
  summary.num_modes = nm;
  if (nm > ni) {
    throw InvalidInput("craig_bampton: CraigBamptonOptions::num_modes = " + std::to_string(nm) +
                       ". Violated constraint: num_modes <= number of interior DOFs (" +
                       std::to_string(ni) + ")");
  }
  int nr = nb + nm;
  // The real form of a Hermitian pair: interior DOF p < ni/2 and p + ni/2 are d and d + n.
  const bool paired = options.hermitian_real_form;
  if (paired) {
    bool symmetric = n % 2 == 0 && nb % 2 == 0 && ni % 2 == 0;
    for (int k = 0; symmetric && k < nb / 2; ++k)
      symmetric = boundary[k] < n / 2 && boundary[nb / 2 + k] == boundary[k] + n / 2;
    for (int p = 0; symmetric && p < ni / 2; ++p)
      symmetric = interior[ni / 2 + p] == interior[p] + n / 2;
    if (!symmetric) {
      throw InvalidInput(
          "craig_bampton: CraigBamptonOptions::hermitian_real_form needs an even size 2n and "
          "boundary (and constrained) DOFs {b, n + b}, the second half the first plus n");
    }
  }
  // Boundary columns whose constraint modes are solved for (the others are J times them).
  const int solved = paired ? nb / 2 : nb;

  // Partition and factorise K_ii.
  auto start = std::chrono::steady_clock::now();
  double cpu = process_cpu_seconds();
  const SparseMatrix K_ii = submatrix(K, interior, interior);
  const SparseMatrix K_ib = submatrix(K, interior, boundary);
  const SparseMatrix M_ii = submatrix(M, interior, interior);
  const SparseMatrix M_ib = submatrix(M, interior, boundary);
  const Eigen::MatrixXd K_bb(submatrix(K, boundary, boundary));
  const Eigen::MatrixXd M_bb(submatrix(M, boundary, boundary));
  // The interior DOFs coupled to the boundary (rows of K_ib with entries). Ordered last in the
  // factor G Gᵀ = K_ii, G⁻¹ K_ib is zero but in its last m rows, Z: the forward half solves of
  // the constraint modes reduce to one dense m x m triangular solve.
  std::vector<int> coupled;
  {
    std::vector<char> flag(static_cast<size_t>(ni), 0);
    for (int j = 0; j < K_ib.outerSize(); ++j)
      for (SparseMatrix::InnerIterator it(K_ib, j); it; ++it) flag[it.row()] = 1;
    for (int r = 0; r < ni; ++r)
      if (flag[r]) coupled.push_back(r);
  }
  // Cost model of the choice: nb constraint modes, and the block Lanczos's solves over the same
  // factor (typically about 6 per mode).
  const double lanczos_solves = nm > 0 && options.modal.shift == 0.0 ? 6.0 * nm : 0.0;
  SparseCholesky cholesky;
  const bool held =
      ni == 0 || (cholesky.factorize(K_ii, coupled, options.coupled_last, nb, lanczos_solves) &&
                  factor_gives_back(cholesky, K_ii));
  RowMatrix Psi;  // [Φ_c Φ_n] (n_i x n_r), row-major: contiguous rows for the sparse products
  // K_bi Φ_c = −(G⁻¹K_ib)ᵀ(G⁻¹K_ib) = −ZᵀZ with the trailing ordering of m interior DOFs
  // (symmetric by construction); otherwise (m = 0) formed in the projection from Φ_c.
  Eigen::MatrixXd KbiPhic;
  int m = 0;
  if (!held) {
    // The boundary and constraints do not hold every rigid motion: the floating interior's
    // constraint modes and kept modes (its rigid modes among them) from a shifted factor.
    cholesky = SparseCholesky();
    summary.seconds_factor = seconds_since(start);
    summary.cpu_seconds_factor = process_cpu_seconds() - cpu;
    start = std::chrono::steady_clock::now();
    cpu = process_cpu_seconds();
    FloatingModes floating = floating_interior(K_ii, M_ii, K_ib, nm, options, Psi);
    summary.modal = floating.modal;
    summary.seconds_modes = seconds_since(start);
    summary.cpu_seconds_modes = process_cpu_seconds() - cpu;
    if (!floating.ok) {
      summary.termination = floating.factor_failed ? CraigBamptonTermination::kFactorizationFailed
                                                   : CraigBamptonTermination::kEigenSolveFailed;
      summary.message =
          "K_ii is singular or indefinite (the boundary and constraints do not hold "
          "every rigid motion of the body, or K is not positive semi-definite), and "
          "its floating-interior reduction failed: " +
          floating.message;
      return result;
    }
    summary.floating_shift = floating.shift;
    summary.num_rigid_modes = floating.num_rigid;
    summary.refinement_steps = floating.refinement_steps;
    nm = static_cast<int>(floating.eigenvalues.size());
    nr = nb + nm;
    summary.num_modes = nm;
    result.mode_eigenvalues = floating.eigenvalues;
  } else {
    summary.factor_nonzeros = ni > 0 ? cholesky.factor_nonzeros() : 0.0;
    summary.coupled_last = ni > 0 ? cholesky.num_last() : 0;
    summary.seconds_factor = seconds_since(start);
    summary.cpu_seconds_factor = process_cpu_seconds() - cpu;

    start = std::chrono::steady_clock::now();
    cpu = process_cpu_seconds();
    Psi.resize(ni, nr);
    m = ni > 0 ? cholesky.num_last() : 0;
    if (m > 0) {
      const Eigen::MatrixXd Z =
          cholesky.solve_lower_last(Eigen::MatrixXd(submatrix(K_ib, coupled, all_columns(nb))));
      KbiPhic = Eigen::MatrixXd(nb, nb);
      KbiPhic.setZero();
      KbiPhic.selfadjointView<Eigen::Lower>().rankUpdate(Z.transpose(), -1.0);
      KbiPhic = KbiPhic.selfadjointView<Eigen::Lower>();
      Eigen::MatrixXd padded = Eigen::MatrixXd::Zero(ni, std::min(options.block_size, nb));
      for (int c0 = 0; c0 < solved; c0 += options.block_size) {
        const int bs = std::min(options.block_size, solved - c0);
        if (bs < padded.cols()) padded = Eigen::MatrixXd::Zero(ni, bs);
        padded.bottomRows(m) = -Z.middleCols(c0, bs);  // Φ_c = G⁻ᵀ [0; −Z]
        Psi.middleCols(c0, bs) = cholesky.solve_upper(padded);
      }
    } else if (ni > 0) {
      for (int c0 = 0; c0 < solved; c0 += options.block_size) {
        const int bs = std::min(options.block_size, solved - c0);
        const Eigen::MatrixXd rhs = -Eigen::MatrixXd(K_ib.middleCols(c0, bs));
        Psi.middleCols(c0, bs) = cholesky.solve(rhs);
      }
    }
    if (paired && ni > 0) {  // column nb/2 + j = J column j: (x; y) -> (−y; x)
      const int h = ni / 2, half = nb / 2;
      Psi.block(0, half, h, half) = -Psi.block(h, 0, h, half);
      Psi.block(h, half, h, half) = Psi.block(0, 0, h, half);
    }
    summary.seconds_constraint = seconds_since(start);
    summary.cpu_seconds_constraint = process_cpu_seconds() - cpu;
    if (options.modal.shift != 0.0) {
      cholesky = SparseCholesky();  // release the factor before the eigen-solve factorises again
    }

    start = std::chrono::steady_clock::now();
    cpu = process_cpu_seconds();
    result.mode_eigenvalues.resize(nm);
    if (nm > 0) {
      ModalOptions modal = options.modal;
      modal.num_modes = nm;
      // Shift 0: the factor of K_ii is the factor of K_ii − σM_ii (no second factorisation).
      // Every interior mode: a dense eigen-solve (Lanczos needs n_modes < n_i).
      ModalResult modes = nm == ni             ? dense_modes(K_ii, M_ii)
                          : modal.shift == 0.0 ? solve_modes(cholesky, M_ii, modal)
                                               : solve_modes(K_ii, M_ii, modal);
      summary.modal = modes.summary;
      if (!modes.summary.ok()) {
        summary.termination = CraigBamptonTermination::kEigenSolveFailed;
        summary.message = "fixed-interface eigen-solve failed: " + modes.summary.message;
        summary.seconds_modes = seconds_since(start);
        summary.cpu_seconds_modes = process_cpu_seconds() - cpu;
        return result;
      }
      result.mode_eigenvalues = modes.eigenvalues;
      Psi.rightCols(nm) = modes.modes;
    }
    cholesky = SparseCholesky();
    summary.seconds_modes = seconds_since(start);
    summary.cpu_seconds_modes = process_cpu_seconds() - cpu;
  }  // held

  // Reduced matrices. With K_ii Φ_c = −K_ib, Φ_nᵀ K_ii Φ_n = Ω², Φ_nᵀ M_ii Φ_n = I:
  //   K_r = [K_bb + K_bi Φ_c, 0; 0, Ω²]
  //   M_r = [M_bb + X + Xᵀ + Φ_cᵀ V, G_η + Vᵀ Φ_n; (sym), I],  V = M_ii Φ_c,
  //   [X G_η] = M_bi [Φ_c Φ_n].
  start = std::chrono::steady_clock::now();
  cpu = process_cpu_seconds();
  ReducedBody& body = result.body;
  body.K = Eigen::MatrixXd::Zero(nr, nr);
  body.M = Eigen::MatrixXd::Zero(nr, nr);
  {
    if (m == 0) KbiPhic = transpose_times_rows(K_ib, Psi).leftCols(nb);  // nb x nb
    body.K.topLeftCorner(nb, nb) = K_bb + KbiPhic;
    body.K.bottomRightCorner(nm, nm).diagonal() = result.mode_eigenvalues;

    const Eigen::MatrixXd G = transpose_times_rows(M_ib, Psi);  // nb x nr: M_bi [Φ_c Φ_n]
    RowMatrix V;
    sparse_times_rows(RowSparse(M_ii), Psi, nb, V);  // n_i x nb, row-major
    // Row-major n_i x k blocks are column-major k x n_i: Φ_cᵀ V = (Psiᵀ)[0:nb, :] (Vᵀ)ᵀ. It is
    // symmetric: only the blocks on and above the diagonal are formed (half the flops).
    Eigen::MatrixXd S(nb, nb);
    for (int c0 = 0; c0 < nb; c0 += kSymmetricBlock) {
      const int bs = std::min(kSymmetricBlock, nb - c0);
      gemm('N', 'T', c0 + bs, bs, ni, Psi.data(), std::max(nr, 1), V.data() + c0, std::max(nb, 1),
           S.data() + static_cast<size_t>(c0) * nb, std::max(nb, 1));
    }
    S = S.selfadjointView<Eigen::Upper>();
    body.M.topLeftCorner(nb, nb) = M_bb + G.leftCols(nb) + G.leftCols(nb).transpose() + S;
    if (nm > 0) {
      Eigen::MatrixXd R(nb, nm);  // Φ_cᵀ M_ii Φ_n = Vᵀ Φ_n
      gemm('N', 'T', nb, nm, ni, V.data(), std::max(nb, 1), Psi.data() + nb, nr, R.data(),
           std::max(nb, 1));
      body.M.topRightCorner(nb, nm) = G.rightCols(nm) + R;
      body.M.bottomLeftCorner(nm, nb) = body.M.topRightCorner(nb, nm).transpose();
      body.M.bottomRightCorner(nm, nm).setIdentity();
    }
  }
  // Round-off leaves K_bb + K_bi Φ_c and Φ_cᵀ V asymmetric in the last digits.
  body.K = 0.5 * (body.K + body.K.transpose()).eval();
  body.M = 0.5 * (body.M + body.M.transpose()).eval();

  body.dofs = craig_bampton_dofs(boundary, result.mode_eigenvalues);

  if (options.keep_basis) {
    result.T = Eigen::MatrixXd::Zero(n, nr);
    for (int k = 0; k < nb; ++k) result.T(boundary[k], k) = 1.0;
    scatter_rows(Psi, interior, result.T);
  }
  summary.seconds_projection = seconds_since(start);
  summary.cpu_seconds_projection = process_cpu_seconds() - cpu;
  return result;
}

std::vector<ReducedDof> craig_bampton_dofs(std::span<const int> boundary_dofs,
                                           const Eigen::VectorXd& mode_eigenvalues) {
  const int nb = static_cast<int>(boundary_dofs.size());
  const int nm = static_cast<int>(mode_eigenvalues.size());
  std::vector<ReducedDof> dofs(static_cast<size_t>(nb + nm));
  for (int k = 0; k < nb; ++k) {
    ReducedDof& d = dofs[k];
    d.kind = ReducedDof::Kind::kPhysical;
    d.full_dof = boundary_dofs[k];
    d.node_index = boundary_dofs[k] / kDofsPerNode;
    d.direction = boundary_dofs[k] % kDofsPerNode;
  }
  for (int j = 0; j < nm; ++j) {
    ReducedDof& d = dofs[nb + j];
    d.kind = ReducedDof::Kind::kModal;
    d.mode = j;
    d.frequency_hz = rad_s_to_hz(std::sqrt(std::max(mode_eigenvalues(j), 0.0)));
  }
  return dofs;
}

}  // namespace stickslip
