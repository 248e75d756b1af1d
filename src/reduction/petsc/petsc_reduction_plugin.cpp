// The PETSc plugin (reduction/petsc_plugin_api.h): the only code of stickslip that calls PETSc
// and SLEPc, built as libstickslip_petsc.so and loaded by model/petsc_reduction.cpp.
//
// The interior rows are split into contiguous shares, one per process (the first n_i mod P
// processes one row more). Each process holds its share of K_ii and M_ii (MPIAIJ) and of the
// constraint and fixed-interface modes (dense, rows of its share); the sums over the interior of
// the reduced matrices are formed per share and added over the processes (MPI_Allreduce).
//   - Constraint modes K_ii Φ_c = −K_ib: one KSP with the options prefix cb_constraint_, by
//     default a direct Cholesky by MUMPS (-cb_constraint_ksp_type preonly -cb_constraint_pc_type
//     cholesky -cb_constraint_pc_factor_mat_solver_type mumps), its right-hand sides in blocks;
//     any other KSP (e.g. cg with gamg or hypre) solves them one by one to a relative residual of
//     1e-12 unless told otherwise.
//   - Fixed-interface modes: SLEPc's EPS (prefix cb_modes_), generalised Hermitian, shift-invert
//     about 0, the m eigenvalues nearest 0, to a relative residual of 1e-10. Its inner solves:
//     with the direct default above, that same KSP (STSetKSP: one factorisation of K_ii serves
//     both); with a Krylov KSP for the constraint modes, the ST's own KSP (prefix cb_modes_st_),
//     MUMPS's Cholesky unless -cb_modes_st_ksp_type etc. say else (an iterative eigen-solve
//     needs no factor at all, but each shift-invert step is then a solve to 1e-12).
//     The eigenvectors are M_ii-normalised here.
// Options come from PETSc's usual sources (PETSC_OPTIONS, ~/.petscrc); PETSc's signal handlers
// are off (-no_signal_handler): the program keeps its own.
// slepceps.h first: petscblaslapack.h needs petscsys.h before it.
#include <slepceps.h>
// clang-format off
#include <petscblaslapack.h>
// clang-format on
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "reduction/petsc_plugin_api.h"

namespace {

using stickslip::PetscCsr;
using stickslip::PetscReductionRequest;
using stickslip::PetscReductionResult;

std::string g_error;

void check(PetscErrorCode code, const char* call) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(std::string(call) + ": " + (text != nullptr ? text : "PETSc error") +
                           " (PETSc error " + std::to_string(static_cast<int>(code)) + ")");
}
#define CHK(call) check((call), #call)

// Owners of PETSc objects, destroyed on every path out.
struct MatHolder {
  Mat m = nullptr;
  ~MatHolder() { MatDestroy(&m); }
};
struct VecHolder {
  Vec v = nullptr;
  ~VecHolder() { VecDestroy(&v); }
};
struct KspHolder {
  KSP k = nullptr;
  ~KspHolder() { KSPDestroy(&k); }
};
struct EpsHolder {
  EPS e = nullptr;
  ~EpsHolder() { EPSDestroy(&e); }
};

bool g_started_mpi = false;

void finalize_at_exit() {
  if (g_started_mpi) SlepcFinalize();  // also MPI_Finalize: PETSc started MPI
}

// SlepcInitialize once per process. MPI is started here unless the program's MPI plugin (cli/
// processes.h) started it, which then also finalizes it.
void ensure_initialized() {
  PetscBool done = PETSC_FALSE;
  CHK(SlepcInitialized(&done));
  if (done) return;
  int mpi_up = 0;
  MPI_Initialized(&mpi_up);
  g_started_mpi = mpi_up == 0;
  CHK(PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr));
  CHK(SlepcInitialize(nullptr, nullptr, nullptr, nullptr));
  // Errors come back as codes (turned into messages), not as PETSc's printed traceback.
  CHK(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr));
  if (g_started_mpi) std::atexit(&finalize_at_exit);
}

// The rows [first, first + count) of `csr` as a PETSc MPIAIJ matrix with `columns` columns
// (columns sorted in each row, as MatCreateMPIAIJWithArrays wants them).
void local_aij(MPI_Comm comm, const PetscCsr& csr, PetscInt first, PetscInt count, PetscInt rows,
               PetscInt columns, Mat* A) {
  std::vector<PetscInt> ia(static_cast<size_t>(count) + 1, 0), ja;
  std::vector<PetscScalar> a;
  const std::int64_t begin = csr.row_start[first], end = csr.row_start[first + count];
  ja.reserve(static_cast<size_t>(end - begin));
  a.reserve(static_cast<size_t>(end - begin));
  std::vector<std::pair<int, double>> row;
  for (PetscInt r = 0; r < count; ++r) {
    row.clear();
    for (std::int64_t k = csr.row_start[first + r]; k < csr.row_start[first + r + 1]; ++k) {
      row.emplace_back(csr.columns[k], csr.values[k]);
    }
    std::sort(row.begin(), row.end());
    for (const auto& [c, v] : row) {
      ja.push_back(c);
      a.push_back(v);
    }
    ia[static_cast<size_t>(r) + 1] = static_cast<PetscInt>(ja.size());
  }
  CHK(MatCreateMPIAIJWithArrays(comm, count, count == rows ? columns : PETSC_DECIDE, rows, columns,
                                ia.data(), ja.data(), a.data(), A));
}

// out (nb x k, column-major) += Bᵀ D: B the rows [first, first + count) of an n_i x nb CSR,
// D (count x k, column-major, leading dimension count) the same rows of a dense block.
void add_csr_transpose_times(const PetscCsr& B, PetscInt first, PetscInt count, int nb,
                             const double* D, int k, double* out) {
  for (PetscInt r = 0; r < count; ++r) {
    for (std::int64_t e = B.row_start[first + r]; e < B.row_start[first + r + 1]; ++e) {
      const int c = B.columns[e];
      const double v = B.values[e];
      for (int j = 0; j < k; ++j) {
        out[c + static_cast<size_t>(j) * nb] += v * D[r + static_cast<size_t>(j) * count];
      }
    }
  }
}

// C (m x n) += Aᵀ B, A count x m and B count x n, column-major.
void add_transpose_times(int count, int m, int n, const double* A, int lda, const double* B,
                         int ldb, double* C) {
  if (count == 0 || m == 0 || n == 0) return;
  PetscBLASInt M = m, N = n, K = count, LDA = std::max(lda, 1), LDB = std::max(ldb, 1),
               LDC = std::max(m, 1);
  const PetscScalar one = 1.0;
  BLASgemm_("T", "N", &M, &N, &K, &one, A, &LDA, B, &LDB, &one, C, &LDC);
}

double now() { return MPI_Wtime(); }

int reduce_impl(const PetscReductionRequest& rq, PetscReductionResult& out) {
  ensure_initialized();
  MPI_Comm comm = rq.collective != 0 ? PETSC_COMM_WORLD : PETSC_COMM_SELF;
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  out.processes = size;
  const PetscInt ni = rq.num_interior;
  const int nb = rq.num_boundary, m = rq.num_modes;
  if (ni <= 0 || m < 0 || m >= ni || nb < 0) {
    throw std::runtime_error("bad sizes: " + std::to_string(ni) + " interior DOFs, " +
                             std::to_string(m) + " modes");
  }
  // This process's share of the interior rows.
  std::vector<PetscInt> counts(static_cast<size_t>(size)), firsts(static_cast<size_t>(size));
  for (int p = 0; p < size; ++p) {
    counts[p] = ni / size + (p < ni % size ? 1 : 0);
    firsts[p] = p == 0 ? 0 : firsts[p - 1] + counts[p - 1];
  }
  const PetscInt first = firsts[rank], nloc = counts[rank];

  double t = now();
  MatHolder Kii, Mii;
  local_aij(comm, rq.K_ii, first, nloc, ni, ni, &Kii.m);
  local_aij(comm, rq.M_ii, first, nloc, ni, ni, &Mii.m);
  for (Mat A : {Kii.m, Mii.m}) {
    CHK(MatSetOption(A, MAT_SYMMETRIC, PETSC_TRUE));
    CHK(MatSetOption(A, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  }

  // Constraint modes, Φ_c: nloc x nb, column-major.
  std::vector<double> phic(static_cast<size_t>(nloc) * nb, 0.0);
  KspHolder ksp;
  CHK(KSPCreate(comm, &ksp.k));
  CHK(KSPSetOperators(ksp.k, Kii.m, Kii.m));
  CHK(KSPSetOptionsPrefix(ksp.k, "cb_constraint_"));
  CHK(KSPSetType(ksp.k, KSPPREONLY));
  PC pc = nullptr;
  CHK(KSPGetPC(ksp.k, &pc));
  CHK(PCSetType(pc, PCCHOLESKY));
  CHK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  CHK(KSPSetTolerances(ksp.k, 1e-12, 0.0, PETSC_DEFAULT, 100000));
  CHK(KSPSetFromOptions(ksp.k));
  CHK(KSPSetUp(ksp.k));
  KSPType ksp_type = nullptr;
  PCType pc_type = nullptr;
  CHK(KSPGetType(ksp.k, &ksp_type));
  CHK(PCGetType(pc, &pc_type));
  const bool direct = std::string(ksp_type) == KSPPREONLY;
  {
    std::string name = std::string(ksp_type) + "+" + pc_type;
    MatSolverType factor = nullptr;
    if (PCFactorGetMatSolverType(pc, &factor) == 0 && factor != nullptr) {
      name += std::string("(") + factor + ")";
    }
    std::snprintf(out.solver, sizeof out.solver, "%s", name.c_str());
  }
  const auto failed_solve = [&](KSPConvergedReason reason) {
    PCFailedReason pc_reason = PC_NOERROR;
    PCGetFailedReason(pc, &pc_reason);
    return std::runtime_error(
        std::string("the constraint modes' solve of K_ii failed (") + KSPConvergedReasons[reason] +
        (pc_reason != PC_NOERROR ? std::string(", ") + PCFailedReasons[pc_reason] : "") +
        "): K_ii is singular (the boundary and the constraints do not hold the body: a floating "
        "interior, which this path does not reduce) or not positive definite, or the iterative "
        "solver did not converge");
  };
  // A singular K_ii (a floating interior) may factor without complaint (MUMPS takes tiny pivots
  // of round-off for real ones): the factor must give back a test vector, x = K_ii⁻¹(K_ii v) = v
  // to 1e-6 (as reduction/craig_bampton.h checks CHOLMOD's).
  {
    VecHolder v, b, x;
    CHK(MatCreateVecs(Kii.m, &v.v, &b.v));
    CHK(VecDuplicate(v.v, &x.v));
    PetscScalar* vv = nullptr;
    CHK(VecGetArray(v.v, &vv));
    for (PetscInt r = 0; r < nloc; ++r)
      vv[r] = 1.0 + 0.5 * std::sin(0.7 * static_cast<double>(first + r));
    CHK(VecRestoreArray(v.v, &vv));
    CHK(MatMult(Kii.m, v.v, b.v));
    CHK(KSPSolve(ksp.k, b.v, x.v));
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    CHK(KSPGetConvergedReason(ksp.k, &reason));
    if (reason < 0) throw failed_solve(reason);
    CHK(VecAXPY(x.v, -1.0, v.v));
    PetscReal error = 0.0, size_v = 0.0;
    CHK(VecNorm(x.v, NORM_INFINITY, &error));
    CHK(VecNorm(v.v, NORM_INFINITY, &size_v));
    if (!(error <= 1e-6 * size_v)) {
      throw std::runtime_error(
          "K_ii is singular: its factor does not give back a test vector (error " +
          std::to_string(error / size_v) +
          "): the boundary and the constraints do not hold the body (a floating interior, which "
          "the PETSc path does not reduce; reduction_solver: direct does)");
    }
  }
  if (direct) {
    // Blocks of right-hand sides −K_ib[:, c0:c0+bs], solved together (MatMatSolve of the factor).
    const int block = std::max(1, rq.block_size);
    std::vector<double> rhs;
    for (int c0 = 0; c0 < nb; c0 += block) {
      const int bs = std::min(block, nb - c0);
      rhs.assign(static_cast<size_t>(nloc) * bs, 0.0);
      for (PetscInt r = 0; r < nloc; ++r) {
        for (std::int64_t e = rq.K_ib.row_start[first + r]; e < rq.K_ib.row_start[first + r + 1];
             ++e) {
          const int c = rq.K_ib.columns[e];
          if (c >= c0 && c < c0 + bs)
            rhs[r + static_cast<size_t>(c - c0) * nloc] -= rq.K_ib.values[e];
        }
      }
      MatHolder B, X;
      CHK(MatCreateDense(comm, nloc, PETSC_DECIDE, ni, bs, nloc > 0 ? rhs.data() : nullptr, &B.m));
      CHK(MatCreateDense(comm, nloc, PETSC_DECIDE, ni, bs,
                         nloc > 0 ? phic.data() + static_cast<size_t>(nloc) * c0 : nullptr, &X.m));
      CHK(KSPMatSolve(ksp.k, B.m, X.m));
      KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
      CHK(KSPGetConvergedReason(ksp.k, &reason));
      if (reason < 0) throw failed_solve(reason);
    }
  } else {
    VecHolder b, x;
    CHK(MatCreateVecs(Kii.m, &x.v, &b.v));
    for (int c = 0; c < nb; ++c) {
      PetscScalar* bb = nullptr;
      CHK(VecGetArray(b.v, &bb));
      std::fill(bb, bb + nloc, 0.0);
      for (PetscInt r = 0; r < nloc; ++r) {
        for (std::int64_t e = rq.K_ib.row_start[first + r]; e < rq.K_ib.row_start[first + r + 1];
             ++e) {
          if (rq.K_ib.columns[e] == c) bb[r] -= rq.K_ib.values[e];
        }
      }
      CHK(VecRestoreArray(b.v, &bb));
      CHK(VecSet(x.v, 0.0));
      CHK(KSPSolve(ksp.k, b.v, x.v));
      KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
      CHK(KSPGetConvergedReason(ksp.k, &reason));
      if (reason < 0) throw failed_solve(reason);
      PetscInt its = 0;
      CHK(KSPGetIterationNumber(ksp.k, &its));
      out.constraint_iterations += static_cast<int>(its);
      const PetscScalar* xx = nullptr;
      CHK(VecGetArrayRead(x.v, &xx));
      std::copy(xx, xx + nloc, phic.begin() + static_cast<size_t>(nloc) * c);
      CHK(VecRestoreArrayRead(x.v, &xx));
    }
  }
  out.seconds_constraint = now() - t;

  // Fixed-interface modes, Φ_n: nloc x m, column-major, M_ii-normalised.
  t = now();
  std::vector<double> phin(static_cast<size_t>(nloc) * m, 0.0);
  if (m > 0) {
    EpsHolder eps;
    CHK(EPSCreate(comm, &eps.e));
    CHK(EPSSetOperators(eps.e, Kii.m, Mii.m));
    CHK(EPSSetProblemType(eps.e, EPS_GHEP));
    CHK(EPSSetOptionsPrefix(eps.e, "cb_modes_"));
    CHK(EPSSetDimensions(eps.e, m, PETSC_DEFAULT, PETSC_DEFAULT));
    CHK(EPSSetTarget(eps.e, 0.0));
    CHK(EPSSetWhichEigenpairs(eps.e, EPS_TARGET_MAGNITUDE));
    CHK(EPSSetTolerances(eps.e, 1e-10, 1000));
    ST st = nullptr;
    CHK(EPSGetST(eps.e, &st));
    CHK(STSetType(st, STSINVERT));
    if (direct) {
      CHK(STSetKSP(st, ksp.k));  // the factor of K_ii (shift 0) serves the eigen-solve too
    } else {
      // A Krylov solver for the constraint modes: the shift-invert's own KSP (prefix
      // cb_modes_st_), by default MUMPS's Cholesky; -cb_modes_st_ksp_type etc. change it.
      KSP inner = nullptr;
      CHK(STGetKSP(st, &inner));
      CHK(KSPSetType(inner, KSPPREONLY));
      PC inner_pc = nullptr;
      CHK(KSPGetPC(inner, &inner_pc));
      CHK(PCSetType(inner_pc, PCCHOLESKY));
      CHK(PCFactorSetMatSolverType(inner_pc, MATSOLVERMUMPS));
      CHK(KSPSetTolerances(inner, 1e-12, 0.0, PETSC_DEFAULT, 100000));
    }
    CHK(EPSSetFromOptions(eps.e));
    CHK(EPSSolve(eps.e));
    PetscInt converged = 0, its = 0;
    CHK(EPSGetConverged(eps.e, &converged));
    CHK(EPSGetIterationNumber(eps.e, &its));
    out.eigen_converged = static_cast<int>(converged);
    out.eigen_iterations = static_cast<int>(its);
    if (converged < m) {
      throw std::runtime_error("SLEPc found " + std::to_string(converged) + " of the " +
                               std::to_string(m) + " fixed-interface modes in " +
                               std::to_string(its) + " iterations");
    }
    std::vector<double> lambda(static_cast<size_t>(converged));
    for (PetscInt j = 0; j < converged; ++j) {
      CHK(EPSGetEigenvalue(eps.e, j, &lambda[j], nullptr));
    }
    std::vector<int> order(static_cast<size_t>(converged));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return lambda[a] < lambda[b]; });
    VecHolder x, Mx;
    CHK(MatCreateVecs(Kii.m, &x.v, &Mx.v));
    for (int j = 0; j < m; ++j) {
      CHK(EPSGetEigenpair(eps.e, order[j], &out.eigenvalues[j], nullptr, x.v, nullptr));
      PetscReal error = 0.0;
      CHK(EPSComputeError(eps.e, order[j], EPS_ERROR_RELATIVE, &error));
      out.max_eigen_residual = std::max(out.max_eigen_residual, static_cast<double>(error));
      CHK(MatMult(Mii.m, x.v, Mx.v));
      PetscScalar norm2 = 0.0;
      CHK(VecDot(x.v, Mx.v, &norm2));
      CHK(VecScale(x.v, 1.0 / std::sqrt(norm2)));
      const PetscScalar* xx = nullptr;
      CHK(VecGetArrayRead(x.v, &xx));
      std::copy(xx, xx + nloc, phin.begin() + static_cast<size_t>(nloc) * j);
      CHK(VecRestoreArrayRead(x.v, &xx));
    }
  }
  out.seconds_modes = now() - t;

  // The sums over the interior, per share, then over the processes.
  t = now();
  const size_t nbb = static_cast<size_t>(nb) * nb, nbm = static_cast<size_t>(nb) * m;
  std::vector<double> sums(2 * nbb + nbm, 0.0);
  double* kbb = sums.data();
  double* mbb = kbb + nbb;
  double* mbe = mbb + nbb;
  add_csr_transpose_times(rq.K_ib, first, nloc, nb, phic.data(), nb, kbb);  // K_bi Φ_c
  {
    std::vector<double> X(nbb, 0.0);  // M_bi Φ_c
    add_csr_transpose_times(rq.M_ib, first, nloc, nb, phic.data(), nb, X.data());
    for (int i = 0; i < nb; ++i) {
      for (int j = 0; j < nb; ++j)
        mbb[i + static_cast<size_t>(j) * nb] =
            X[i + static_cast<size_t>(j) * nb] + X[j + static_cast<size_t>(i) * nb];
    }
  }
  add_csr_transpose_times(rq.M_ib, first, nloc, nb, phin.data(), m, mbe);  // M_bi Φ_n
  if (nb > 0) {
    MatHolder P, V;  // Φ_c as a distributed dense matrix; V = M_ii Φ_c
    CHK(MatCreateDense(comm, nloc, PETSC_DECIDE, ni, nb, nloc > 0 ? phic.data() : nullptr, &P.m));
    CHK(MatMatMult(Mii.m, P.m, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &V.m));
    const PetscScalar* v = nullptr;
    PetscInt ldv = 0;
    CHK(MatDenseGetLDA(V.m, &ldv));
    CHK(MatDenseGetArrayRead(V.m, &v));
    add_transpose_times(static_cast<int>(nloc), nb, nb, phic.data(), static_cast<int>(nloc), v,
                        static_cast<int>(ldv), mbb);  // Φ_cᵀ M_ii Φ_c
    add_transpose_times(static_cast<int>(nloc), nb, m, v, static_cast<int>(ldv), phin.data(),
                        static_cast<int>(nloc), mbe);  // Φ_cᵀ M_ii Φ_n
    CHK(MatDenseRestoreArrayRead(V.m, &v));
  }
  CHK(MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM,
                    comm));
  std::copy(kbb, kbb + nbb, out.K_bb_add);
  std::copy(mbb, mbb + nbb, out.M_bb_add);
  std::copy(mbe, mbe + nbm, out.M_b_eta);
  if (rq.keep_basis != 0) {
    std::vector<int> recv_counts(static_cast<size_t>(size)), displs(static_cast<size_t>(size));
    for (int p = 0; p < size; ++p) {
      recv_counts[p] = static_cast<int>(counts[p]);
      displs[p] = static_cast<int>(firsts[p]);
    }
    for (int col = 0; col < nb + m; ++col) {
      const double* mine = col < nb ? phic.data() + static_cast<size_t>(nloc) * col
                                    : phin.data() + static_cast<size_t>(nloc) * (col - nb);
      CHK(MPI_Allgatherv(mine, static_cast<int>(nloc), MPI_DOUBLE,
                         out.basis + static_cast<size_t>(ni) * col, recv_counts.data(),
                         displs.data(), MPI_DOUBLE, comm));
    }
  }
  out.seconds_projection = now() - t;

  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  long rss = usage.ru_maxrss;
  CHK(MPI_Allreduce(&rss, &out.peak_rss_kb_max, 1, MPI_LONG, MPI_MAX, comm));
  CHK(MPI_Allreduce(&rss, &out.peak_rss_kb_min, 1, MPI_LONG, MPI_MIN, comm));
  return 0;
}

int reduce(const PetscReductionRequest* request, PetscReductionResult* result) {
  try {
    return reduce_impl(*request, *result);
  } catch (const std::exception& e) {
    g_error = e.what();
    return 1;
  }
}

const char* last_error() { return g_error.c_str(); }

}  // namespace

extern "C" __attribute__((visibility("default"))) const stickslip::PetscPluginApi*
stickslip_petsc_plugin_api() {
  static const stickslip::PetscPluginApi api{
      .abi = stickslip::kPetscPluginAbi,
      .reduce = &reduce,
      .last_error = &last_error,
  };
  return &api;
}
