#include "recovery/harmonic_response.h"

#include <Eigen/QR>
#include <Eigen/UmfPackSupport>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/parallel.h"
#include "linalg/floating_factor.h"
#include "linalg/sparse_cholesky.h"

namespace stickslip {

namespace {

std::string to_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", v);
  return buffer;
}

void check_loads(const Eigen::MatrixXcd& F, int num_dofs, int harmonic, double omega,
                 const char* where) {
  if (F.rows() != num_dofs) {
    throw InvalidInput(std::string(where) + ": load has " + std::to_string(F.rows()) +
                       " rows, the model has " + std::to_string(num_dofs) + " DOFs");
  }
  require(harmonic >= 0, std::string(where) + " harmonic", std::to_string(harmonic),
          "harmonic >= 0");
  require(std::isfinite(omega) && omega >= 0.0, std::string(where) + " omega", to_text(omega),
          "finite and >= 0 (rad/s)");
}

// Rows of the free DOFs of every column, real and imaginary parts side by side:
// [Re F_f, Im F_f] (num_free x 2m).
Eigen::MatrixXd restrict_split(const DofMap& dofs, const Eigen::MatrixXcd& F) {
  const Eigen::Index m = F.cols();
  Eigen::MatrixXd out(dofs.num_free(), 2 * m);
  if (dofs.has_dependents()) {  // loads on dependent DOFs go to the DOFs they depend on: TᵀF
    const Eigen::MatrixXcd Ff = dofs.restrict_load(F);
    out << Ff.real(), Ff.imag();
    return out;
  }
  for (int f = 0; f < dofs.num_free(); ++f) {
    const int d = dofs.full_dof(f);
    for (Eigen::Index j = 0; j < m; ++j) {
      out(f, j) = F(d, j).real();
      out(f, m + j) = F(d, j).imag();
    }
  }
  return out;
}

Eigen::MatrixXcd expand_columns(const DofMap& dofs, const Eigen::MatrixXcd& x_free) {
  Eigen::MatrixXcd x = Eigen::MatrixXcd::Zero(dofs.num_dofs(), x_free.cols());
  if (dofs.has_dependents()) {  // x = T x_f
    for (Eigen::Index j = 0; j < x_free.cols(); ++j) {
      x.col(j) = dofs.expand(Eigen::VectorXcd(x_free.col(j)));
    }
    return x;
  }
  for (int f = 0; f < dofs.num_free(); ++f) x.row(dofs.full_dof(f)) = x_free.row(f);
  return x;
}

Eigen::MatrixXcd join(const Eigen::MatrixXd& split) {
  const Eigen::Index m = split.cols() / 2;
  Eigen::MatrixXcd out(split.rows(), m);
  out.real() = split.leftCols(m);
  out.imag() = split.rightCols(m);
  return out;
}

// Below this many rows per thread a thread costs more than it saves.
constexpr std::ptrdiff_t kRowsPerThread = 20000;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// add_rigid_motion: singular values of the master rows of the rigid modes below this fraction
// of the largest are motions the masters do not see (exactly 0 in exact arithmetic: 1e-10 is far
// above the round-off of M-orthonormal modes, far below any motion the masters do see).
constexpr double kRigidFitRank = 1e-10;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void validate(const RayleighDamping& damping) {
  require(std::isfinite(damping.alpha) && damping.alpha >= 0.0, "RayleighDamping::alpha",
          to_text(damping.alpha), "finite and >= 0 (1/s)");
  require(std::isfinite(damping.beta) && damping.beta >= 0.0, "RayleighDamping::beta",
          to_text(damping.beta), "finite and >= 0 (s)");
}

void validate(const ModalRecoveryOptions& options) {
  require(options.num_modes >= 1, "ModalRecoveryOptions::num_modes",
          std::to_string(options.num_modes), "num_modes >= 1");
  require(options.num_threads >= 0, "ModalRecoveryOptions::num_threads",
          std::to_string(options.num_threads), "num_threads >= 0 (0 = one per hardware thread)");
  ModalOptions modal = options.modal;
  modal.num_modes = options.num_modes;
  validate(modal);
}

Eigen::VectorXcd complex_nodal_force_vector(int num_nodes,
                                            std::span<const ComplexNodalForce> forces) {
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(3 * static_cast<Eigen::Index>(num_nodes));
  for (size_t i = 0; i < forces.size(); ++i) {
    const int n = forces[i].node;
    if (n < 0 || n >= num_nodes) {
      throw InvalidInput("forces[" + std::to_string(i) + "].node = " + std::to_string(n) +
                         ". Violated constraint: 0 <= node < " + std::to_string(num_nodes));
    }
    f.segment<3>(3 * static_cast<Eigen::Index>(n)) += forces[i].force;
  }
  return f;
}

Eigen::MatrixXcd harmonic_response(const HarmonicSolver& solver, const Eigen::MatrixXcd& loads,
                                   std::span<const int> harmonics, double omega,
                                   RecoverySummary* summary) {
  if (loads.cols() != static_cast<Eigen::Index>(harmonics.size())) {
    throw InvalidInput("harmonic_response: loads has " + std::to_string(loads.cols()) +
                       " columns but " + std::to_string(harmonics.size()) + " harmonics");
  }
  for (Eigen::Index j = 0; j < loads.cols(); ++j) {
    if (harmonics[static_cast<size_t>(j)] != 0) continue;
    // max(|Re|, |Im|) over the column: within a factor √2 of max|F|, without a hypot per DOF.
    const double scale = std::max(loads.col(j).real().cwiseAbs().maxCoeff(),
                                  loads.col(j).imag().cwiseAbs().maxCoeff());
    // Harmonic 0 is the mean of a real signal: its amplitude must be real.
    constexpr double kRealTolerance = 1e-12;
    if (loads.col(j).imag().cwiseAbs().maxCoeff() > kRealTolerance * scale) {
      throw InvalidInput("harmonic_response: the load of harmonic 0 (column " + std::to_string(j) +
                         ") has an imaginary part; the mean must be real");
    }
  }
  Eigen::MatrixXcd x = solver.solve_harmonics(loads, harmonics, omega, summary);
  for (Eigen::Index j = 0; j < loads.cols(); ++j) {
    if (harmonics[static_cast<size_t>(j)] == 0 && !std::isnan(x.col(j).real().sum())) {
      x.col(j).imag().setZero();
    }
  }
  return x;
}

namespace {

// Adds a failed harmonic to a summary (the first failure sets the termination type).
void record_failure(RecoverySummary* summary, RecoveryTermination termination, int harmonic,
                    const std::string& message) {
  if (summary == nullptr) return;
  if (summary->ok()) summary->termination = termination;
  summary->failed_harmonics.push_back(harmonic);
  summary->message += (summary->message.empty() ? "" : "; ") + message;
}

// A static load on a body with unheld rigid motion has an equilibrium only if it has no resultant
// on the rigid modes Φ_0 (free DOFs x r). Per mode r and column j the resultant φ_rᵀf_j is compared
// with Σ_i |φ_ri f_ij| (what it would be if every force pushed the same way): the loads recovery
// gets come from a solve that balanced them to its Newton tolerance (1e-8 by default), so a
// resultant above kUnheldResultant of that is not round-off but a load nothing holds. Below it
// the resultant is dropped (FloatingFactor solves the load without it), changing x by as little.
constexpr double kUnheldResultant = 1e-4;

// Empty when every column of F (free DOFs x m) is balanced; else what is not. The same from the
// resultants Φ_0ᵀF and the scales |Φ_0|ᵀ|F| (r x m).
std::string unheld_resultant_of(const Eigen::MatrixXd& resultant, const Eigen::MatrixXd& scale);
std::string unheld_resultant(const Eigen::MatrixXd& rigid, const Eigen::MatrixXd& F) {
  return unheld_resultant_of(rigid.transpose() * F, rigid.cwiseAbs().transpose() * F.cwiseAbs());
}
std::string unheld_resultant_of(const Eigen::MatrixXd& resultant, const Eigen::MatrixXd& scale) {
  double worst = 0.0;
  for (Eigen::Index j = 0; j < resultant.cols(); ++j) {
    for (Eigen::Index r = 0; r < resultant.rows(); ++r) {
      if (scale(r, j) > 0.0) worst = std::max(worst, std::abs(resultant(r, j)) / scale(r, j));
    }
  }
  if (worst <= kUnheldResultant) return {};
  return "the static (harmonic 0) load has a resultant on rigid-body motion that the body's "
         "clamps and supports do not hold (" +
         to_text(worst) +
         " of the sum of its forces' magnitudes along that motion): no static equilibrium";
}

}  // namespace

Eigen::MatrixXcd HarmonicSolver::solve_harmonics(const Eigen::MatrixXcd& loads,
                                                 std::span<const int> harmonics, double omega,
                                                 RecoverySummary* summary) const {
  if (summary != nullptr) *summary = RecoverySummary{};
  Eigen::MatrixXcd x(num_dofs(), loads.cols());
  for (Eigen::Index j = 0; j < loads.cols(); ++j) {
    RecoverySummary one;
    x.col(j) = solve(loads.col(j), harmonics[static_cast<size_t>(j)], omega, &one);
    if (!one.ok()) {
      record_failure(summary, one.termination, harmonics[static_cast<size_t>(j)], one.message);
    }
  }
  return x;
}

// ---------------------------------------------------------------------------------------------
// DirectRecovery

struct DirectRecovery::Impl {
  SparseMatrix K_ff, M_ff;
  RayleighDamping damping;
  SparseCholesky static_factor;
  FloatingFactor floating;   // when K_ff is singular: the body's unheld rigid motion
  Eigen::MatrixXd rigid;     // its rigid modes, full size (num_dofs x r)
  std::string message;
  bool ok = false;
};

DirectRecovery::DirectRecovery(const SparseMatrix& K, const SparseMatrix& M, const DofMap& dofs,
                               RayleighDamping damping)
    : impl_(std::make_unique<Impl>()), dofs_(dofs) {
  validate(damping);
  if (K.rows() != dofs.num_dofs() || M.rows() != dofs.num_dofs() || K.cols() != K.rows() ||
      M.cols() != M.rows()) {
    throw InvalidInput("DirectRecovery: K, M must be square with the DofMap's " +
                       std::to_string(dofs.num_dofs()) + " DOFs");
  }
  impl_->K_ff = dofs.restrict(K);
  impl_->M_ff = dofs.restrict(M);
  impl_->damping = damping;
  if (impl_->static_factor.factorize(impl_->K_ff) &&
      factor_gives_back(impl_->static_factor, impl_->K_ff)) {
    impl_->ok = true;
    return;
  }
  // K_ff singular: the clamps and supports do not hold every rigid motion of the body (a damper,
  // a body on springs or contacts only). Harmonic 0 is then solved without rigid motion.
  const std::string why = impl_->static_factor.ok()
                              ? "numerically singular"
                              : "not positive definite (" + impl_->static_factor.message() + ")";
  impl_->static_factor = SparseCholesky();
  if (!impl_->floating.compute(impl_->K_ff, impl_->M_ff, {})) {
    impl_->message = "K_ff is " + why +
                     " and its factorisation as a body with free rigid-body motion failed: " +
                     impl_->floating.message();
    return;
  }
  const Eigen::MatrixXd rigid_free = impl_->floating.rigid_modes();
  impl_->rigid.resize(dofs.num_dofs(), rigid_free.cols());
  for (Eigen::Index r = 0; r < rigid_free.cols(); ++r) {
    impl_->rigid.col(r) = dofs.expand(Eigen::VectorXd(rigid_free.col(r)));
  }
  impl_->ok = true;
}

DirectRecovery::~DirectRecovery() = default;
bool DirectRecovery::ok() const { return impl_->ok; }
Eigen::MatrixXd DirectRecovery::rigid_modes() const {
  return impl_->rigid.cols() > 0 ? impl_->rigid : Eigen::MatrixXd(dofs_.num_dofs(), 0);
}
const std::string& DirectRecovery::message() const { return impl_->message; }

Eigen::MatrixXcd DirectRecovery::solve(const Eigen::MatrixXcd& F, int harmonic, double omega,
                                       RecoverySummary* summary) const {
  if (summary != nullptr) *summary = RecoverySummary{};
  check_loads(F, dofs_.num_dofs(), harmonic, omega, "DirectRecovery::solve");
  if (!ok()) throw InvalidInput("DirectRecovery::solve: setup failed: " + impl_->message);
  const double w = harmonic * omega;
  const Eigen::MatrixXd Ff = restrict_split(dofs_, F);
  if (w == 0.0) {
    if (impl_->static_factor.ok()) return expand_columns(dofs_, join(impl_->static_factor.solve(Ff)));
    const std::string unbalanced = unheld_resultant(impl_->floating.rigid_modes(), Ff);
    if (!unbalanced.empty()) {
      record_failure(summary, RecoveryTermination::kUnbalanced, harmonic, unbalanced);
      return Eigen::MatrixXcd::Constant(dofs_.num_dofs(), F.cols(), kNaN);
    }
    FloatingSolveSummary solved;
    const Eigen::MatrixXd x = impl_->floating.solve(Ff, &solved);
    if (!solved.converged) {
      record_failure(summary, RecoveryTermination::kFailure, harmonic,
                     "the static solve of the body with free rigid-body motion did not converge "
                     "(residual " + to_text(solved.residual) + ")");
      return Eigen::MatrixXcd::Constant(dofs_.num_dofs(), F.cols(), kNaN);
    }
    return expand_columns(dofs_, join(x));
  }

  // D = (1 + i w beta) K − (w² − i w alpha) M.
  using Complex = std::complex<double>;
  const Complex a(1.0, w * impl_->damping.beta);
  const Complex b(-w * w, w * impl_->damping.alpha);
  // 64-bit indices (umfpack_zl_*): the LU of a 3D body soon outgrows 32-bit workspace sizes.
  using LongComplexSparse = Eigen::SparseMatrix<Complex, Eigen::ColMajor, SuiteSparse_long>;
  LongComplexSparse D = impl_->K_ff.cast<Complex>() * a + impl_->M_ff.cast<Complex>() * b;
  D.makeCompressed();
  Eigen::UmfPackLU<LongComplexSparse> lu;
  lu.compute(D);
  if (lu.info() != Eigen::Success) {
    const long status = lu.info() == Eigen::InvalidInput ? -999 : lu.umfpackFactorizeReturncode();
    const bool singular = status == UMFPACK_WARNING_singular_matrix;
    const std::string what = singular ? "D_k is singular (undamped resonance)"
                             : status == UMFPACK_ERROR_out_of_memory
                                 ? "UMFPACK ran out of memory"
                                 : "UMFPACK failed (status " + std::to_string(status) + ")";
    record_failure(summary,
                   singular ? RecoveryTermination::kSingular : RecoveryTermination::kFailure,
                   harmonic,
                   what + " for harmonic " + std::to_string(harmonic) +
                       " at omega = " + to_text(omega) + " rad/s");
    return Eigen::MatrixXcd::Constant(dofs_.num_dofs(), F.cols(), kNaN);
  }
  const Eigen::MatrixXcd x_free = lu.solve(join(Ff));
  return expand_columns(dofs_, x_free);
}

// ---------------------------------------------------------------------------------------------
// ModalRecovery

struct ModalRecovery::Impl {
  ModalResult modes;
  Eigen::VectorXd damping_rates;  // c_r = alpha + beta ω_r²
  bool residual = true;
  SparseCholesky static_factor;
  // A body its clamps and supports do not hold: the first num_rigid modes are its rigid modes
  // (eigenvalue exactly 0), from `floating`, which also gives the residual term's K⁺.
  FloatingFactor floating;
  int num_rigid = 0;
  Eigen::MatrixXd rigid;  // full size, num_dofs x num_rigid
  // Optional attachment modes on the load DOFs (ModalRecoveryOptions::load_dofs).
  std::vector<int> load_full;     // full DOFs of B (free ones only)
  std::vector<char> is_load_dof;  // per full DOF
  Eigen::MatrixXd Phi_B;          // |B| x n: rows of Φ at B
  Eigen::MatrixXd R;              // num_free x |B| (empty without residual correction)
  std::string message;
  bool ok = false;
  double setup_seconds = 0.0;
  int num_threads = 1;
};

ModalRecovery::ModalRecovery(const SparseMatrix& K, const SparseMatrix& M, const DofMap& dofs,
                             RayleighDamping damping, const ModalRecoveryOptions& options)
    : impl_(std::make_unique<Impl>()), dofs_(dofs) {
  validate(damping);
  validate(options);
  if (K.rows() != dofs.num_dofs() || M.rows() != dofs.num_dofs() || K.cols() != K.rows() ||
      M.cols() != M.rows()) {
    throw InvalidInput("ModalRecovery: K, M must be square with the DofMap's " +
                       std::to_string(dofs.num_dofs()) + " DOFs");
  }
  require(options.num_modes < dofs.num_free(), "ModalRecoveryOptions::num_modes",
          std::to_string(options.num_modes),
          "num_modes < number of free DOFs (" + std::to_string(dofs.num_free()) + ")");
  const auto start = std::chrono::steady_clock::now();
  const SparseMatrix K_ff = dofs.restrict(K);
  const SparseMatrix M_ff = dofs.restrict(M);
  ModalOptions modal = options.modal;
  modal.num_modes = options.num_modes;
  impl_->residual = options.residual_correction;
  // Held (K_ff's factor gives back K_ff v) or with free rigid motion; the factor is kept for the
  // residual correction.
  if (impl_->static_factor.factorize(K_ff) && factor_gives_back(impl_->static_factor, K_ff)) {
    if (!impl_->residual) impl_->static_factor = SparseCholesky();
    impl_->modes = solve_modes(K_ff, M_ff, modal);
  } else {
    impl_->static_factor = SparseCholesky();
    // The rigid modes (a block eigen-solve finds the repeated zero eigenvalue in full, exactly 0)
    // beside num_modes elastic ones.
    if (!impl_->floating.compute(K_ff, M_ff,
                                 {.num_elastic_modes = options.num_modes, .modal = modal})) {
      impl_->message = "K_ff is singular and its factorisation as a body with free rigid-body "
                       "motion failed: " +
                       impl_->floating.message();
      impl_->setup_seconds = seconds_since(start);
      return;
    }
    impl_->num_rigid = impl_->floating.num_rigid();
    impl_->modes.eigenvalues = impl_->floating.eigenvalues();
    impl_->modes.modes = impl_->floating.modes();
    impl_->modes.summary = impl_->floating.modal_summary();
    impl_->rigid.resize(dofs.num_dofs(), impl_->num_rigid);
    for (int r = 0; r < impl_->num_rigid; ++r) {
      impl_->rigid.col(r) = dofs.expand(Eigen::VectorXd(impl_->modes.modes.col(r)));
    }
  }
  if (!impl_->modes.summary.ok()) {
    impl_->message = "modal solve failed: " + impl_->modes.summary.message;
    impl_->setup_seconds = seconds_since(start);
    return;
  }
  impl_->damping_rates = (damping.alpha + damping.beta * impl_->modes.eigenvalues.array()).matrix();
  impl_->num_threads = thread_count(options.num_threads);
  if (impl_->residual &&
      impl_->modes.eigenvalues.tail(impl_->modes.eigenvalues.size() - impl_->num_rigid)
              .minCoeff() <= 0.0) {
    impl_->message = "an elastic mode with omega^2 <= 0 (K_ff is not positive semi-definite)";
    impl_->setup_seconds = seconds_since(start);
    return;
  }
  if (!options.load_dofs.empty()) {
    impl_->is_load_dof.assign(static_cast<size_t>(dofs.num_dofs()), 0);
    for (size_t i = 0; i < options.load_dofs.size(); ++i) {
      const int d = options.load_dofs[i];
      require(d >= 0 && d < dofs.num_dofs(),
              "ModalRecoveryOptions::load_dofs[" + std::to_string(i) + "]", std::to_string(d),
              "0 <= DOF < " + std::to_string(dofs.num_dofs()));
      require(!dofs.is_dependent(d),
              "ModalRecoveryOptions::load_dofs[" + std::to_string(i) + "]", std::to_string(d),
              "not a dependent DOF of an equation (" +
                  (dofs.is_dependent(d) ? dofs.dependent_origin(d) : std::string()) + ")");
      if (dofs.is_constrained(d) || impl_->is_load_dof[static_cast<size_t>(d)]) continue;
      impl_->is_load_dof[static_cast<size_t>(d)] = 1;
      impl_->load_full.push_back(d);
    }
    const Eigen::Index nb = static_cast<Eigen::Index>(impl_->load_full.size());
    const Eigen::MatrixXd& Phi = impl_->modes.modes;
    impl_->Phi_B.resize(nb, Phi.cols());
    for (Eigen::Index b = 0; b < nb; ++b) {
      impl_->Phi_B.row(b) = Phi.row(dofs.free_index(impl_->load_full[static_cast<size_t>(b)]));
    }
    if (impl_->residual && nb > 0) {
      Eigen::MatrixXd B = Eigen::MatrixXd::Zero(dofs.num_free(), nb);
      for (Eigen::Index b = 0; b < nb; ++b) {
        B(dofs.free_index(impl_->load_full[static_cast<size_t>(b)]), b) = 1.0;
      }
      impl_->R = static_solve(B);
      Eigen::VectorXd inv_lambda = impl_->modes.eigenvalues.cwiseInverse();
      inv_lambda.head(impl_->num_rigid).setZero();  // K⁺ has no rigid part
      impl_->R.noalias() -= Phi * (inv_lambda.asDiagonal() * impl_->Phi_B.transpose());
    }
  }
  impl_->ok = true;
  impl_->setup_seconds = seconds_since(start);
}

ModalRecovery::~ModalRecovery() = default;
bool ModalRecovery::ok() const { return impl_->ok; }
const std::string& ModalRecovery::message() const { return impl_->message; }
const Eigen::VectorXd& ModalRecovery::eigenvalues() const { return impl_->modes.eigenvalues; }
const Eigen::MatrixXd& ModalRecovery::modes() const { return impl_->modes.modes; }
const ModalSummary& ModalRecovery::modal_summary() const { return impl_->modes.summary; }
Eigen::MatrixXd ModalRecovery::rigid_modes() const {
  return impl_->num_rigid > 0 ? impl_->rigid : Eigen::MatrixXd(dofs_.num_dofs(), 0);
}

// K_ff⁻¹ B, or K_ff⁺ B for a body with free rigid motion (free DOFs x k).
Eigen::MatrixXd ModalRecovery::static_solve(const Eigen::MatrixXd& B) const {
  if (impl_->num_rigid == 0) return impl_->static_factor.solve(B);
  FloatingSolveSummary solved;
  Eigen::MatrixXd X = impl_->floating.solve(B, &solved);
  if (!solved.converged) X.setConstant(kNaN);  // never a finite wrong answer
  return X;
}
double ModalRecovery::setup_seconds() const { return impl_->setup_seconds; }

Eigen::MatrixXcd ModalRecovery::solve(const Eigen::MatrixXcd& F, int harmonic, double omega,
                                      RecoverySummary* summary) const {
  check_loads(F, dofs_.num_dofs(), harmonic, omega, "ModalRecovery::solve");
  if (!ok()) throw InvalidInput("ModalRecovery::solve: setup failed: " + impl_->message);
  const std::vector<int> harmonics(static_cast<size_t>(F.cols()), harmonic);
  return solve_columns(F, Eigen::VectorXd::Constant(F.cols(), harmonic * omega), harmonics,
                       summary);
}

Eigen::MatrixXcd ModalRecovery::solve_harmonics(const Eigen::MatrixXcd& loads,
                                                std::span<const int> harmonics, double omega,
                                                RecoverySummary* summary) const {
  Eigen::VectorXd w(loads.cols());
  for (Eigen::Index j = 0; j < loads.cols(); ++j) {
    const int k = harmonics[static_cast<size_t>(j)];
    check_loads(loads.col(j), dofs_.num_dofs(), k, omega, "ModalRecovery::solve");
    w(j) = k * omega;
  }
  if (!ok()) throw InvalidInput("ModalRecovery::solve: setup failed: " + impl_->message);
  return solve_columns(loads, w, harmonics, summary);
}

// One pass over Φ (and R) for all columns: column j at angular frequency w(j).
Eigen::MatrixXcd ModalRecovery::solve_columns(const Eigen::MatrixXcd& F, const Eigen::VectorXd& w,
                                              std::span<const int> harmonics,
                                              RecoverySummary* summary) const {
  if (summary != nullptr) *summary = RecoverySummary{};
  const Eigen::MatrixXd& Phi = impl_->modes.modes;
  const Eigen::VectorXd& lambda = impl_->modes.eigenvalues;
  const Eigen::Index m = F.cols();
  // Loads supported on the load DOFs: the precomputed attachment modes replace the factor.
  bool on_load_dofs = !impl_->is_load_dof.empty();
  for (Eigen::Index d = 0; on_load_dofs && d < F.rows(); ++d) {
    if (!impl_->is_load_dof[static_cast<size_t>(d)] && !dofs_.is_constrained(static_cast<int>(d)) &&
        !F.row(d).isZero(0.0)) {
      on_load_dofs = false;
    }
  }
  Eigen::MatrixXd Ff, FB;   // [Re, Im] on the free DOFs, or on B
  Eigen::MatrixXd q_split;  // n x 2m
  if (on_load_dofs) {
    const Eigen::Index nb = static_cast<Eigen::Index>(impl_->load_full.size());
    FB.resize(nb, 2 * m);
    for (Eigen::Index b = 0; b < nb; ++b) {
      const int d = impl_->load_full[static_cast<size_t>(b)];
      FB.row(b).head(m) = F.row(d).real();
      FB.row(b).tail(m) = F.row(d).imag();
    }
    q_split = impl_->Phi_B.transpose() * FB;
  } else {
    Ff = restrict_split(dofs_, F);
    q_split = Phi.transpose() * Ff;
  }
  const Eigen::MatrixXcd q = join(q_split);
  const int nr = impl_->num_rigid;
  std::vector<char> singular(static_cast<size_t>(m), 0);
  if (nr > 0) {  // a static column must have no resultant on the rigid modes
    const Eigen::MatrixXd& Phi_rows = on_load_dofs ? impl_->Phi_B : Phi;
    const Eigen::MatrixXd& loads = on_load_dofs ? FB : Ff;
    const Eigen::MatrixXd scale_split =
        Phi_rows.leftCols(nr).cwiseAbs().transpose() * loads.cwiseAbs();
    for (Eigen::Index j = 0; j < m; ++j) {
      if (w(j) != 0.0) continue;
      Eigen::MatrixXd resultant(nr, 2), scale(nr, 2);  // real and imaginary parts
      resultant << q_split.col(j).head(nr), q_split.col(m + j).head(nr);
      scale << scale_split.col(j), scale_split.col(m + j);
      const std::string unbalanced = unheld_resultant_of(resultant, scale);
      if (unbalanced.empty()) continue;
      singular[static_cast<size_t>(j)] = 1;
      record_failure(summary, RecoveryTermination::kUnbalanced,
                     harmonics[static_cast<size_t>(j)], unbalanced);
    }
  }
  // Modal coordinates: h_r q_r, minus q_r / ω_r² when the static residual is added. A rigid mode
  // has no static part (K⁺ has none) and, at kΩ = 0, no coordinate: its static motion is the
  // caller's (add_rigid_motion).
  Eigen::MatrixXcd eta(q.rows(), m);
  for (Eigen::Index j = 0; j < m; ++j) {
    for (Eigen::Index r = 0; r < q.rows(); ++r) {
      if (r < nr) {
        eta(r, j) = w(j) == 0.0 ? std::complex<double>(0.0)
                                : q(r, j) / std::complex<double>(-w(j) * w(j),
                                                                 w(j) * impl_->damping_rates(r));
        continue;
      }
      const std::complex<double> den(lambda(r) - w(j) * w(j), w(j) * impl_->damping_rates(r));
      if (den == 0.0 && !singular[static_cast<size_t>(j)]) {
        singular[static_cast<size_t>(j)] = 1;
        const int k = harmonics[static_cast<size_t>(j)];
        record_failure(summary, RecoveryTermination::kSingular, k,
                       "undamped mode " + std::to_string(r + 1) + " at resonance for harmonic " +
                           std::to_string(k) + " (k omega = omega_r)");
      }
      const std::complex<double> h = 1.0 / den;
      const std::complex<double> g = impl_->residual ? h - 1.0 / lambda(r) : h;
      eta(r, j) = g * q(r, j);
    }
  }
  Eigen::MatrixXd eta_split(eta.rows(), 2 * m);
  eta_split.leftCols(m) = eta.real();
  eta_split.rightCols(m) = eta.imag();
  // With the attachment modes R (which already hold −Φ Ω⁻² ΦᵀB) the modal part uses h alone.
  const bool use_R = on_load_dofs && impl_->residual;
  if (use_R) {
    for (Eigen::Index r = nr; r < q.rows(); ++r) {
      eta_split.row(r).head(m) += q_split.row(r).head(m) / lambda(r);
      eta_split.row(r).tail(m) += q_split.row(r).tail(m) / lambda(r);
    }
  }
  if (!use_R && impl_->residual) {
    Eigen::MatrixXd x_split = static_solve(Ff);
    x_split.noalias() += Phi * eta_split;
    Eigen::MatrixXcd x = expand_columns(dofs_, join(x_split));
    for (Eigen::Index j = 0; j < m; ++j) {
      if (singular[static_cast<size_t>(j)]) x.col(j).setConstant(kNaN);
    }
    return x;
  }
  // x = Φ η (+ R F_B): memory bound (Φ and R are streamed once); rows split over threads, each
  // writing its rows straight into the full complex result.
  Eigen::MatrixXcd x = Eigen::MatrixXcd::Zero(dofs_.num_dofs(), m);
  const Eigen::Index num_free = Phi.rows();
  auto rows = [&](std::ptrdiff_t r0, std::ptrdiff_t r1, int) {
    constexpr Eigen::Index kBlock = 4096;  // rows per product: the block result stays in cache
    Eigen::MatrixXd y;
    for (Eigen::Index b0 = r0; b0 < r1; b0 += kBlock) {
      const Eigen::Index len = std::min(kBlock, r1 - b0);
      y.noalias() = Phi.middleRows(b0, len) * eta_split;
      if (use_R) y.noalias() += impl_->R.middleRows(b0, len) * FB;
      for (Eigen::Index i = 0; i < len; ++i) {
        const int d = dofs_.full_dof(static_cast<int>(b0 + i));
        for (Eigen::Index j = 0; j < m; ++j) x(d, j) = {y(i, j), y(i, m + j)};
      }
    }
  };
  parallel_for(num_free, impl_->num_threads, rows, kRowsPerThread);
  for (Eigen::Index j = 0; j < m; ++j) {
    if (singular[static_cast<size_t>(j)]) x.col(j).setConstant(kNaN);
  }
  return x;
}

int ModalRecovery::num_basis_columns() const {
  return static_cast<int>(impl_->modes.modes.cols() + impl_->R.cols());
}

Eigen::MatrixXcd ModalRecovery::coordinates(const Eigen::MatrixXcd& loads,
                                            std::span<const int> harmonics, double omega) const {
  if (!ok()) throw InvalidInput("ModalRecovery::coordinates: setup failed: " + impl_->message);
  if (impl_->is_load_dof.empty()) {
    throw InvalidInput("ModalRecovery::coordinates: needs ModalRecoveryOptions::load_dofs");
  }
  if (loads.rows() != dofs_.num_dofs() ||
      loads.cols() != static_cast<Eigen::Index>(harmonics.size())) {
    throw InvalidInput("ModalRecovery::coordinates: loads must be num_dofs x harmonics");
  }
  for (Eigen::Index d = 0; d < loads.rows(); ++d) {
    if (!impl_->is_load_dof[static_cast<size_t>(d)] && !dofs_.is_constrained(static_cast<int>(d)) &&
        !loads.row(d).isZero(0.0)) {
      throw InvalidInput("ModalRecovery::coordinates: a load on DOF " + std::to_string(d) +
                         ", which is not in ModalRecoveryOptions::load_dofs");
    }
  }
  const Eigen::Index n = impl_->modes.modes.cols(), nb = impl_->R.cols();
  const Eigen::Index nh = loads.cols();
  Eigen::MatrixXcd FB(static_cast<Eigen::Index>(impl_->load_full.size()), nh);
  for (Eigen::Index b = 0; b < FB.rows(); ++b) {
    FB.row(b) = loads.row(impl_->load_full[static_cast<size_t>(b)]);
  }
  Eigen::MatrixXcd q(n, nh);
  q.real() = impl_->Phi_B.transpose() * FB.real();
  q.imag() = impl_->Phi_B.transpose() * FB.imag();
  Eigen::MatrixXcd c(n + nb, nh);
  for (Eigen::Index j = 0; j < nh; ++j) {
    const int k = harmonics[static_cast<size_t>(j)];
    require(k >= 0, "harmonics[" + std::to_string(j) + "]", std::to_string(k), "harmonic >= 0");
    const double w = k * omega;
    for (Eigen::Index r = 0; r < n; ++r) {
      // A rigid mode at kΩ = 0: no coordinate (rigid motion has no strain; see rigid_modes()).
      c(r, j) = r < impl_->num_rigid && w == 0.0
                    ? std::complex<double>(0.0)
                    : q(r, j) / std::complex<double>(impl_->modes.eigenvalues(r) - w * w,
                                                     w * impl_->damping_rates(r));
    }
  }
  if (nb > 0) c.bottomRows(nb) = FB;
  return c;
}

Eigen::VectorXd ModalRecovery::basis_column(int c) const {
  const Eigen::Index n = impl_->modes.modes.cols();
  if (c < 0 || c >= num_basis_columns()) {
    throw InvalidInput("ModalRecovery::basis_column: column " + std::to_string(c) +
                       " out of range");
  }
  return dofs_.expand(Eigen::VectorXd(c < n ? impl_->modes.modes.col(c) : impl_->R.col(c - n)));
}

// ---------------------------------------------------------------------------------------------
// Expansion and comparison

Eigen::VectorXcd add_rigid_motion(const Eigen::MatrixXd& rigid_modes, std::span<const int> dofs,
                                  const Eigen::VectorXcd& target, Eigen::Ref<Eigen::VectorXcd> x) {
  const Eigen::Index r = rigid_modes.cols();
  if (rigid_modes.rows() != x.size() || target.size() != static_cast<Eigen::Index>(dofs.size())) {
    throw InvalidInput("add_rigid_motion: rigid_modes, x, dofs and target sizes do not match");
  }
  if (r == 0) return Eigen::VectorXcd(0);
  Eigen::MatrixXd A(static_cast<Eigen::Index>(dofs.size()), r);
  Eigen::VectorXcd b(A.rows());
  for (size_t i = 0; i < dofs.size(); ++i) {
    const int d = dofs[i];
    if (d < 0 || d >= x.size()) {
      throw InvalidInput("add_rigid_motion: dofs[" + std::to_string(i) + "] = " +
                         std::to_string(d) + " out of range");
    }
    A.row(static_cast<Eigen::Index>(i)) = rigid_modes.row(d);
    b(static_cast<Eigen::Index>(i)) = target(static_cast<Eigen::Index>(i)) - x(d);
  }
  // Rank-revealing: a rigid motion the DOFs do not see (its columns of A zero or dependent to
  // round-off of A's largest singular value) gets no amplitude.
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
  cod.setThreshold(kRigidFitRank);
  Eigen::VectorXcd a(r);
  a.real() = cod.solve(Eigen::VectorXd(b.real()));
  a.imag() = cod.solve(Eigen::VectorXd(b.imag()));
  x.real() += rigid_modes * a.real();
  x.imag() += rigid_modes * a.imag();
  return a;
}

Eigen::MatrixXcd expand_reduced_response(const Eigen::MatrixXd& T, const Eigen::MatrixXcd& q) {
  if (T.cols() != q.rows()) {
    throw InvalidInput("expand_reduced_response: T has " + std::to_string(T.cols()) +
                       " columns but q has " + std::to_string(q.rows()) + " rows");
  }
  Eigen::MatrixXcd x(T.rows(), q.cols());
  x.real() = T * q.real();
  x.imag() = T * q.imag();
  return x;
}

Eigen::MatrixXcd expand_reduced_response(const Eigen::MatrixXd& T_free, const DofMap& dofs,
                                         const Eigen::MatrixXcd& q) {
  if (T_free.rows() != dofs.num_free()) {
    throw InvalidInput("expand_reduced_response: T has " + std::to_string(T_free.rows()) +
                       " rows but the DofMap has " + std::to_string(dofs.num_free()) +
                       " free DOFs");
  }
  return expand_columns(dofs, expand_reduced_response(T_free, q));
}

ResponseDifference compare_responses(const Eigen::MatrixXcd& a, const Eigen::MatrixXcd& b,
                                     std::span<const int> dofs) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) {
    throw InvalidInput("compare_responses: the responses have different sizes");
  }
  for (size_t i = 0; i < dofs.size(); ++i) {
    if (dofs[i] < 0 || dofs[i] >= a.rows()) {
      throw InvalidInput("compare_responses: dofs[" + std::to_string(i) +
                         "] = " + std::to_string(dofs[i]) + " out of range");
    }
  }
  ResponseDifference out;
  const double inf = std::numeric_limits<double>::infinity();
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    double max_diff = 0.0, max_ref = 0.0, sum_diff = 0.0, sum_ref = 0.0;
    for (int d : dofs) {
      const double diff = std::abs(a(d, j) - b(d, j));
      const double ref = std::abs(b(d, j));
      max_diff = std::max(max_diff, diff);
      max_ref = std::max(max_ref, ref);
      sum_diff += diff * diff;
      sum_ref += ref * ref;
    }
    out.max_absolute.push_back(max_diff);
    if (max_ref == 0.0) {
      out.max_relative.push_back(max_diff == 0.0 ? 0.0 : inf);
      out.rms_relative.push_back(max_diff == 0.0 ? 0.0 : inf);
    } else {
      out.max_relative.push_back(max_diff / max_ref);
      out.rms_relative.push_back(std::sqrt(sum_diff / sum_ref));
    }
  }
  return out;
}

}  // namespace stickslip
