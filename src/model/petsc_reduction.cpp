#include "model/petsc_reduction.h"

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <vector>

#include <fmt/core.h>

#include "core/errors.h"
#include "io/plugin_loader.h"
#include "reduction/petsc_plugin_api.h"

namespace stickslip {
namespace {

bool g_collective = false;

const PetscPluginApi* load_plugin(std::string* failures) {
  static std::once_flag once;
  static const PetscPluginApi* api = nullptr;
  static std::string why;
  std::call_once(once, [] {
    PluginSearch search;
    search.file = "libstickslip_petsc.so";
    search.environment = "STICKSLIP_PETSC_PLUGIN";
#ifdef STICKSLIP_PETSC_PLUGIN_BUILD_PATH
    search.build_path = STICKSLIP_PETSC_PLUGIN_BUILD_PATH;
#endif
    search.what = "a PETSc plugin of this version of stickslip";
    // PETSc and SLEPc open parts of themselves (and Open MPI its components) with dlopen.
    search.global_symbols = true;
    api = static_cast<const PetscPluginApi*>(open_plugin(
        search,
        [](void* handle) -> const void* {
          using Entry = const PetscPluginApi* (*)();
          auto entry = reinterpret_cast<Entry>(dlsym(handle, "stickslip_petsc_plugin_api"));
          if (entry == nullptr) return nullptr;
          const PetscPluginApi* a = entry();
          return a != nullptr && a->abi == kPetscPluginAbi ? a : nullptr;
        },
        why));
  });
  if (api == nullptr && failures != nullptr) *failures = why;
  return api;
}

// The rows of K (both triangles stored) split by the partition: row r of the interior gives
// K_ii's row (columns: interior numbers) and K_ib's row (columns: boundary positions).
struct SplitRows {
  std::vector<std::int64_t> ii_start{0}, ib_start{0};
  std::vector<int> ii_col, ib_col;
  std::vector<double> ii_val, ib_val;
  PetscCsr ii() const { return {ii_start.data(), ii_col.data(), ii_val.data()}; }
  PetscCsr ib() const { return {ib_start.data(), ib_col.data(), ib_val.data()}; }
};

// where[d]: -1 constrained, 0..n_b-1 boundary position, n_b + k interior number k.
SplitRows split_rows(const SparseMatrix& A, const std::vector<int>& where,
                     const std::vector<int>& interior, int nb, Eigen::MatrixXd* bb) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor, int> R(A);
  SplitRows s;
  *bb = Eigen::MatrixXd::Zero(nb, nb);
  for (int row = 0; row < R.rows(); ++row) {
    const int wr = where[row];
    if (wr < 0 || wr >= nb) continue;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(R, row); it; ++it) {
      const int wc = where[it.col()];
      if (wc >= 0 && wc < nb) (*bb)(wr, wc) += it.value();
    }
  }
  for (int d : interior) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor, int>::InnerIterator it(R, d); it; ++it) {
      const int wc = where[it.col()];
      if (wc < 0) continue;
      if (wc < nb) {
        s.ib_col.push_back(wc);
        s.ib_val.push_back(it.value());
      } else {
        s.ii_col.push_back(wc - nb);
        s.ii_val.push_back(it.value());
      }
    }
    s.ii_start.push_back(static_cast<std::int64_t>(s.ii_col.size()));
    s.ib_start.push_back(static_cast<std::int64_t>(s.ib_col.size()));
  }
  return s;
}

}  // namespace

bool petsc_reduction_available(std::string* why) { return load_plugin(why) != nullptr; }

void set_petsc_reduction_collective(bool collective) { g_collective = collective; }
bool petsc_reduction_collective() { return g_collective; }

CraigBamptonResult craig_bampton_petsc(const SparseMatrix& K, const SparseMatrix& M,
                                       std::span<const int> constrained_dofs,
                                       std::span<const int> boundary_dofs,
                                       const CraigBamptonOptions& options,
                                       PetscReductionInfo* info) {
  validate(options);
  const int n = static_cast<int>(K.rows());
  if (K.cols() != n || M.rows() != n || M.cols() != n) {
    throw InvalidInput(fmt::format("K is {} x {} and M {} x {}: both must be square and alike",
                                   K.rows(), K.cols(), M.rows(), M.cols()));
  }
  const int nb = static_cast<int>(boundary_dofs.size());
  std::vector<int> where(static_cast<size_t>(n), -2);  // -2: interior (numbered below)
  for (int d : constrained_dofs) {
    if (d < 0 || d >= n) throw InvalidInput(fmt::format("constrained DOF {} not in [0, {})", d, n));
    where[d] = -1;
  }
  for (int k = 0; k < nb; ++k) {
    const int d = boundary_dofs[k];
    if (d < 0 || d >= n) throw InvalidInput(fmt::format("boundary DOF {} not in [0, {})", d, n));
    if (where[d] != -2) {
      throw InvalidInput(fmt::format("DOF {} is boundary twice or boundary and constrained", d));
    }
    where[d] = k;
  }
  CraigBamptonResult result;
  std::vector<int>& interior = result.interior_dofs;
  for (int d = 0; d < n; ++d) {
    if (where[d] == -2) {
      where[d] = nb + static_cast<int>(interior.size());
      interior.push_back(d);
    }
  }
  const int ni = static_cast<int>(interior.size());
  const int m = options.num_modes;
  CraigBamptonSummary& summary = result.summary;
  summary.num_dofs = n;
  summary.num_constrained = static_cast<int>(constrained_dofs.size());
  summary.num_boundary = nb;
  summary.num_interior = ni;
  summary.num_modes = m;
  if (ni == 0 || m >= ni) {
    throw InvalidInput(fmt::format(
        "the PETSc reduction keeps fewer fixed-interface modes than interior DOFs: {} modes, {} "
        "interior DOFs (keep at most {}, or reduce with the direct solver)",
        m, ni, std::max(ni - 1, 0)));
  }
  std::string failures;
  const PetscPluginApi* api = load_plugin(&failures);
  if (api == nullptr) {
    throw PetscUnavailable(
        "a body asks for reduction_solver: petsc, but the PETSc plugin libstickslip_petsc.so "
        "did not load (build with STICKSLIP_PETSC and libpetsc-real-dev libslepc-real-dev; "
        "docs/distributed-reduction.md); tried:" +
        failures);
  }

  const auto start = std::chrono::steady_clock::now();
  Eigen::MatrixXd K_bb, M_bb;
  const SplitRows k_rows = split_rows(K, where, interior, nb, &K_bb);
  const SplitRows m_rows = split_rows(M, where, interior, nb, &M_bb);
  PetscReductionRequest request;
  request.num_interior = ni;
  request.num_boundary = nb;
  request.num_modes = m;
  request.K_ii = k_rows.ii();
  request.K_ib = k_rows.ib();
  request.M_ii = m_rows.ii();
  request.M_ib = m_rows.ib();
  request.collective = g_collective ? 1 : 0;
  request.block_size = options.block_size;
  request.keep_basis = options.keep_basis ? 1 : 0;
  Eigen::MatrixXd K_add(nb, nb), M_add(nb, nb), M_be(nb, m), basis;
  result.mode_eigenvalues.resize(m);
  if (options.keep_basis) basis.resize(ni, nb + m);
  PetscReductionResult out;
  out.K_bb_add = K_add.data();
  out.M_bb_add = M_add.data();
  out.M_b_eta = M_be.data();
  out.eigenvalues = result.mode_eigenvalues.data();
  out.basis = options.keep_basis ? basis.data() : nullptr;
  const double seconds_split =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (api->reduce(&request, &out) != 0) {
    summary.termination = CraigBamptonTermination::kFactorizationFailed;
    summary.message = std::string("PETSc reduction: ") + api->last_error();
    return result;
  }
  summary.seconds_factor = seconds_split;
  summary.seconds_constraint = out.seconds_constraint;
  summary.seconds_modes = out.seconds_modes;
  if (info != nullptr) {
    info->processes = out.processes;
    info->solver = out.solver;
    info->constraint_iterations = out.constraint_iterations;
    info->eigen_iterations = out.eigen_iterations;
    info->max_eigen_residual = out.max_eigen_residual;
    info->peak_rss_kb_max = out.peak_rss_kb_max;
    info->peak_rss_kb_min = out.peak_rss_kb_min;
  }

  const auto t_projection = std::chrono::steady_clock::now();
  const int nr = nb + m;
  ReducedBody& body = result.body;
  body.K = Eigen::MatrixXd::Zero(nr, nr);
  body.M = Eigen::MatrixXd::Zero(nr, nr);
  body.K.topLeftCorner(nb, nb) = K_bb + K_add;
  body.K.bottomRightCorner(m, m).diagonal() = result.mode_eigenvalues;
  body.M.topLeftCorner(nb, nb) = M_bb + M_add;
  body.M.topRightCorner(nb, m) = M_be;
  body.M.bottomLeftCorner(m, nb) = M_be.transpose();
  body.M.bottomRightCorner(m, m).setIdentity();
  // Round-off leaves K_bb + K_bi Φ_c and Φ_cᵀ M_ii Φ_c asymmetric in the last digits.
  body.K = 0.5 * (body.K + body.K.transpose()).eval();
  body.M = 0.5 * (body.M + body.M.transpose()).eval();
  body.dofs = craig_bampton_dofs(boundary_dofs, result.mode_eigenvalues);
  if (options.keep_basis) {
    result.T = Eigen::MatrixXd::Zero(n, nr);
    for (int k = 0; k < nb; ++k) result.T(boundary_dofs[k], k) = 1.0;
    for (int k = 0; k < ni; ++k) result.T.row(interior[k]) = basis.row(k);
  }
  summary.seconds_projection =
      out.seconds_projection +
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_projection).count();
  return result;
}

}  // namespace stickslip
