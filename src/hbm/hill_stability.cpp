#include "hbm/hill_stability.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/errors.h"
#include "core/format.h"
#include "linalg/blas.h"
#include "linalg/blas_threads.h"

namespace stickslip {

namespace {
// Mean harmonic indices closer than this count as equal (then the smaller |Im μ| is preferred).
constexpr double kSameIndex = 0.25;
// Two eigenvalues are members of one family (μ and μ + imΩ, m ≠ 0) when their imaginary parts
// differ by at least half of Ω (kOtherMember) and their multipliers e^{μT} agree to kSameMultiplier
// (relative): the members of a family differ only by the truncation of the harmonics (far below
// 1e-6 for the members near the centre), a complex pair of multipliers ρ, ρ̄ near the real axis
// by 2 |Im ρ| (kept apart down to angles of 5e-7 rad).
constexpr double kOtherMember = 0.5;
constexpr double kSameMultiplier = 1e-6;
// The centred member of a family has |k̄| ≤ ½ (exactly one member does when the harmonics are not
// truncated: the members' indices differ by whole numbers; two, ±½, for a real negative
// multiplier); kCentred leaves room for the truncation's distortion of that ½.
constexpr double kCentred = 0.55;
// Eigenvalues of the scaled companion matrix (norm ≈ 1) closer than this are one cluster.
constexpr double kSameEigenvalue = 1e-8;

// Eigenvalues and the first `rows` entries of the right eigenvectors (columns) of a real square
// matrix A (overwritten), by LAPACK's dgeev: balanced (permutation and diagonal scaling), blocked
// Hessenberg reduction, multishift QR. False when dgeev fails.
bool eigenpairs(Eigen::MatrixXd& A, int rows, Eigen::VectorXcd& values, Eigen::MatrixXcd& heads) {
  const int n = static_cast<int>(A.rows());
  Eigen::VectorXd wr(n), wi(n);
  Eigen::MatrixXd vr(n, n);
  const char jobvl = 'N', jobvr = 'V';
  const int one = 1;
  int lwork = -1, info = 0;
  double query = 0, vl = 0;
  dgeev_(&jobvl, &jobvr, &n, A.data(), &n, wr.data(), wi.data(), &vl, &one, vr.data(), &n, &query,
         &lwork, &info);
  if (info != 0) return false;
  lwork = static_cast<int>(query);
  std::vector<double> work(std::max(lwork, 1));
  dgeev_(&jobvl, &jobvr, &n, A.data(), &n, wr.data(), wi.data(), &vl, &one, vr.data(), &n,
         work.data(), &lwork, &info);
  if (info != 0) return false;
  values.resize(n);
  heads.resize(rows, n);
  // A complex pair is j (Im > 0) and j + 1 (its conjugate), vectors VR(:,j) ± i VR(:,j+1).
  for (int j = 0; j < n; ++j) {
    values[j] = {wr[j], wi[j]};
    heads.col(j).real() = vr.col(j).head(rows);
    if (wi[j] == 0) {
      heads.col(j).imag().setZero();
      continue;
    }
    if (!(wi[j] > 0 && j + 1 < n && wi[j + 1] == -wi[j])) return false;
    values[j + 1] = {wr[j + 1], wi[j + 1]};
    heads.col(j).imag() = vr.col(j + 1).head(rows);
    heads.col(j + 1) = heads.col(j).conjugate();
    ++j;
  }
  return true;
}

// X ← A⁻¹ X for a real square A (overwritten by its LU), by LAPACK's dgetrf/dgetrs. False when A
// is exactly singular.
bool solve_in_place(Eigen::MatrixXd& A, Eigen::MatrixXd& X) {
  const int n = static_cast<int>(A.rows()), nrhs = static_cast<int>(X.cols());
  std::vector<int> pivots(n);
  int info = 0;
  dgetrf_(&n, &n, A.data(), &n, pivots.data(), &info);
  if (info != 0) return false;
  const char trans = 'N';
  dgetrs_(&trans, &n, &nrhs, A.data(), &n, pivots.data(), X.data(), &n, &info);
  return info == 0;
}
}  // namespace

void validate(const HillOptions& options) {
  if (!(std::isfinite(options.dynamic_mode_factor) && options.dynamic_mode_factor >= 0)) {
    throw InvalidInput("HillOptions.dynamic_mode_factor = " +
                       format_number(options.dynamic_mode_factor) + ": must be finite and >= 0");
  }
  if (!(std::isfinite(options.stability_tolerance) && options.stability_tolerance > 0)) {
    throw InvalidInput("HillOptions.stability_tolerance = " +
                       format_number(options.stability_tolerance) + ": must be finite and > 0");
  }
}

FloquetSummary hill_stability(const HarmonicBalanceSystem& system, const Eigen::VectorXd& x,
                              double omega, const HillOptions& options) {
  validate(options);
  if (!(std::isfinite(omega) && omega > 0)) {
    throw InvalidInput("hill_stability: Ω = " + format_number(omega) + " rad/s: must be > 0");
  }
  if (x.size() != system.size()) {
    throw InvalidInput("hill_stability: " + std::to_string(x.size()) + " unknowns given, the " +
                       "system has " + std::to_string(system.size()));
  }
  if (system.travelling_wave()) {
    throw InvalidInput("hill_stability: a travelling-wave (cyclic) system is not supported yet");
  }
  const LinearModel& model = system.linear_model();
  const Eigen::MatrixXd& Psi = system.contact_modes();  // nu x nm
  // The perturbation's harmonics: 0..H_max (harmonic 0 and any gaps of the solution's set added).
  const HarmonicSet& solved = system.unknown_harmonics();
  const HarmonicSet S = HarmonicSet::up_to(solved.max_harmonic(), true);
  const bool wider = S.harmonics() != solved.harmonics();
  const int nm = static_cast<int>(model.omega2.size());
  const int nu = system.contact_rows();
  const int nc = S.coefficient_count();
  const int n = nu * nc;

  // Dynamic and quasi-static modes.
  const double factor = options.dynamic_mode_factor;
  const double cutoff = factor * (S.max_harmonic() + 1) * omega;
  std::vector<int> dynamic, quasi_static;
  for (int r = 0; r < nm; ++r) {
    const double w = std::sqrt(std::max(model.omega2[r], 0.0));
    (factor == 0 || w <= cutoff ? dynamic : quasi_static).push_back(r);
  }
  const int nd = static_cast<int>(dynamic.size());
  FloquetSummary summary;
  summary.dynamic_modes = nd;
  summary.quasi_static_modes = static_cast<int>(quasi_static.size());

  // J = ∂F/∂U over the perturbation's harmonics.
  Eigen::MatrixXd J;
  if (wider) {
    const Aft aft(
        FourierBasis(S, std::max(system.aft().basis().time_samples(), S.min_time_samples())),
        system.aft().method());
    J = system.force_jacobian(x, &aft);
  } else {
    J = system.force_jacobian(x);
  }
  if (nd == 0) return summary;

  // Ψ_S = kron(Ψ_d, I_nc): unknown layout (row·nc + c) x mode-major (mode·nc + c).
  const int m = nd * nc;
  Eigen::MatrixXd PsiS = Eigen::MatrixXd::Zero(n, m);
  for (int a = 0; a < nu; ++a) {
    for (int j = 0; j < nd; ++j) {
      const double v = Psi(a, dynamic[j]);
      if (v == 0) continue;
      for (int c = 0; c < nc; ++c) PsiS(a * nc + c, j * nc + c) = v;
    }
  }
  // J is block-diagonal per pair: products with it block by block.
  const auto times_J = [&](const Eigen::MatrixXd& X) {
    Eigen::MatrixXd Y(n, X.cols());
    for (size_t p = 0; p < system.pairs().size(); ++p) {
      const int w = system.pairs()[p].element->dimension() * nc;
      const int c = system.pair_row(static_cast<int>(p)) * nc;
      Y.middleRows(c, w).noalias() = J.block(c, c, w, w) * X.middleRows(c, w);
    }
    return Y;
  };
  // Ψ_Sᵀ J_eff Ψ_S with J_eff = (I + J G_s)⁻¹ J, G_s = kron(Ψ_s diag(1/ω_s²) Ψ_sᵀ, I_nc).
  Eigen::MatrixXd JPsi = times_J(PsiS);
  if (!quasi_static.empty()) {
    Eigen::MatrixXd Ps(nu, quasi_static.size());
    for (size_t i = 0; i < quasi_static.size(); ++i) {
      Ps.col(i) = Psi.col(quasi_static[i]) / std::sqrt(model.omega2[quasi_static[i]]);
    }
    const Eigen::MatrixXd Gs = Ps * Ps.transpose();
    Eigen::MatrixXd Gbig = Eigen::MatrixXd::Zero(n, n);
    for (int a = 0; a < nu; ++a) {
      for (int b = 0; b < nu; ++b) {
        for (int c = 0; c < nc; ++c) Gbig(a * nc + c, b * nc + c) = Gs(a, b);
      }
    }
    Eigen::MatrixXd IJG = times_J(Gbig);
    IJG.diagonal().array() += 1.0;
    const ScopedBlasThreads one_thread(1);  // threads only spin at these sizes (blas_threads.h)
    STICKSLIP_VERIFY(solve_in_place(IJG, JPsi),
                     "hill_stability: I + J G_s is singular (the quasi-static modes' fold)");
  }
  const Eigen::MatrixXd D = FourierBasis(S, S.min_time_samples()).derivative() * omega;  // d/dt
  const Eigen::MatrixXd D2 = D * D;
  const bool dense_damping = model.modal_damping_matrix.size() > 0;
  Eigen::MatrixXd M1 = Eigen::MatrixXd::Zero(m, m), M0 = PsiS.transpose() * JPsi;
  for (int i = 0; i < nd; ++i) {
    const int r = dynamic[i];
    M1.block(i * nc, i * nc, nc, nc) += 2 * D;
    M0.block(i * nc, i * nc, nc, nc) += D2;
    M0.block(i * nc, i * nc, nc, nc).diagonal().array() += model.omega2[r];
    for (int j = 0; j < nd; ++j) {
      const double c = dense_damping ? model.modal_damping_matrix(r, dynamic[j])
                                     : (i == j ? model.modal_damping[r] : 0.0);
      if (c == 0) continue;
      M1.block(i * nc, j * nc, nc, nc).diagonal().array() += c;
      M0.block(i * nc, j * nc, nc, nc) += c * D;
    }
  }
  // Companion form of the scaled problem (μ = γ λ, γ² = ‖M0‖∞): [p; λp]' = A [p; λp],
  // A = [0 I; −M0/γ² −M1/γ]. Unscaled, ‖A‖ ≈ ‖M0‖ ≈ ω_max² (10¹⁰ on the reference joint) against
  // exponents of |μ| ≈ 10⁵: the eigen-solver's backward error ε‖A‖ then moved the two exponents of
  // a nearly double pair (the identical beams' modes that the joint barely couples) by
  // √(ε‖A‖|μ|) ≈ 0.3 1/s (docs/performance.md).
  const double gamma2 =
      std::max(M0.cwiseAbs().rowwise().sum().maxCoeff(), std::numeric_limits<double>::min());
  const double gamma = std::sqrt(gamma2);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  A.topRightCorner(m, m).setIdentity();
  A.bottomLeftCorner(m, m) = -M0 / gamma2;
  A.bottomRightCorner(m, m) = -M1 / gamma;
  // The eigenvectors' periodic parts p(t) (their first m entries) in complex exponentials: a
  // harmonic k ≥ 1 with (complex) coefficients a, b is (a − ib)/2 e^{ikθ} + (a + ib)/2 e^{−ikθ}.
  // Row layout: mode j, index k = −H..H at j (2H + 1) + H + k (absent harmonics of S stay 0).
  const int H = S.max_harmonic(), width = 2 * H + 1;
  const auto exponentials = [&](const Eigen::MatrixXcd& v) {
    Eigen::MatrixXcd e = Eigen::MatrixXcd::Zero(nd * width, v.cols());
    const std::complex<double> i(0, 1);
    for (int j = 0; j < nd; ++j) {
      for (int h = 0; h < S.size(); ++h) {
        const int k = S.harmonics()[h], o = j * nc + S.offset(h), c = j * width + H;
        if (k == 0) {
          e.row(c) = v.row(o);
          continue;
        }
        e.row(c + k) = 0.5 * (v.row(o) - i * v.row(o + 1));
        e.row(c - k) = 0.5 * (v.row(o) + i * v.row(o + 1));
      }
    }
    return e;
  };
  Eigen::VectorXd harmonic_index(nd * width);
  for (int j = 0; j < nd; ++j) {
    for (int k = -H; k <= H; ++k) harmonic_index[j * width + H + k] = k;
  }

  {
    Eigen::VectorXcd all;
    Eigen::MatrixXcd vectors;  // the eigenvectors' first m entries: p
    {
      const ScopedBlasThreads one_thread(1);
      STICKSLIP_VERIFY(eigenpairs(A, m, all, vectors), "hill_stability: the eigen-solver failed");
    }
    const int ns = static_cast<int>(all.size());
    const Eigen::MatrixXcd p = exponentials(vectors);
    // Mean harmonic index k̄ = Σ k |p_k|² / Σ |p_k|² of each eigenvector (Parseval: the time
    // average of |p(t)|² split by harmonic).
    std::vector<double> index(ns, 0.0);
    for (int e = 0; e < ns; ++e) {
      const double weight = p.col(e).squaredNorm();
      if (weight > 0) {
        index[e] = harmonic_index.dot(p.col(e).cwiseAbs2()) / weight;
      }
    }
    // A cluster of (numerically) equal eigenvalues has an invariant subspace, not eigenvectors:
    // the solver returns any basis of it, e.g. when two families meet (μ_r ≈ μ_s + imΩ, exactly
    // so in a time-invariant system with equal damping), mixtures of the centred member of one
    // and an outer member of the other, neither centred. Within such a cluster the basis that
    // diagonalises the harmonic index (the Hermitian pencil Vᴴ K V y = κ Vᴴ V y) separates the
    // members again; its indices κ (ascending) go to the cluster's eigenvalues in the order of
    // their own k̄ (the eigenvalues are equal to kSameEigenvalue: which one carries which κ does
    // not change the exponents).
    {
      std::vector<int> by_value(ns);
      std::iota(by_value.begin(), by_value.end(), 0);
      std::sort(by_value.begin(), by_value.end(), [&](int a, int b) {
        return all[a].imag() < all[b].imag() ||
               (all[a].imag() == all[b].imag() && all[a].real() < all[b].real());
      });
      std::vector<bool> done(ns, false);
      for (int a = 0; a < ns; ++a) {
        const int ea = by_value[a];
        if (done[ea]) continue;
        std::vector<int> cluster = {ea};
        for (int b = a + 1; b < ns; ++b) {
          const int eb = by_value[b];
          if (all[eb].imag() - all[ea].imag() > kSameEigenvalue) break;
          if (!done[eb] && std::abs(all[eb] - all[ea]) <= kSameEigenvalue) cluster.push_back(eb);
        }
        for (const int e : cluster) done[e] = true;
        if (cluster.size() < 2) continue;
        const int c = static_cast<int>(cluster.size());
        Eigen::MatrixXcd V(p.rows(), c);
        for (int j = 0; j < c; ++j) V.col(j) = p.col(cluster[j]);
        const Eigen::MatrixXcd gram = V.adjoint() * V;
        const Eigen::MatrixXcd moment = V.adjoint() * harmonic_index.asDiagonal() * V;
        const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> pencil(
            0.5 * (moment + moment.adjoint()), 0.5 * (gram + gram.adjoint()));
        if (pencil.info() != Eigen::Success) continue;  // a degenerate basis: keep the k̄ as is
        std::sort(cluster.begin(), cluster.end(),
                  [&](int x, int y) { return index[x] < index[y]; });
        for (int j = 0; j < c; ++j) index[cluster[j]] = pencil.eigenvalues()[j];
      }
    }
    all *= gamma;
    std::vector<int> order;
    for (int e = 0; e < ns; ++e) {
      if (std::abs(index[e]) <= kCentred) order.push_back(e);
    }
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      const double da = std::abs(index[a]), db = std::abs(index[b]);
      if (std::abs(da - db) > kSameIndex) return da < db;
      return std::abs(all[a].imag()) < std::abs(all[b].imag());
    });
    // One member per family: a candidate with the multiplier of one already taken but another
    // member (Im μ differs by Ω/2 or more) is skipped, and used only if too few are left (two
    // families with one multiplier, μ_s = μ_r + imΩ, both centred).
    const double T = 2 * std::numbers::pi / omega;
    std::vector<int> chosen, skipped;
    for (const int e : order) {
      if (static_cast<int>(chosen.size()) == 2 * nd) break;
      const std::complex<double> rho = std::exp(all[e] * T);
      const bool member = std::any_of(chosen.begin(), chosen.end(), [&](int c) {
        return std::abs(all[c].imag() - all[e].imag()) >= kOtherMember * omega &&
               std::abs(std::exp(all[c] * T) - rho) <= kSameMultiplier * std::abs(rho);
      });
      (member ? skipped : chosen).push_back(e);
    }
    for (size_t i = 0; static_cast<int>(chosen.size()) < 2 * nd && i < skipped.size(); ++i) {
      chosen.push_back(skipped[i]);
    }
    // Families without a centred member are not placed: their exponents are not filled in from
    // outer members (whose real parts are the truncation's, not the family's).
    order = std::move(chosen);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return all[a].real() > all[b].real(); });
    const int placed = static_cast<int>(order.size());
    summary.unplaced_exponents = 2 * nd - placed;
    summary.exponents.resize(placed);
    for (int i = 0; i < placed; ++i) summary.exponents[i] = all[order[i]];
  }
  if (summary.exponents.size() == 0) {  // no family placed: unknown
    summary.max_real_part = summary.max_multiplier = std::numeric_limits<double>::quiet_NaN();
    summary.stable = false;
    return summary;
  }
  summary.max_real_part = summary.exponents[0].real();
  summary.max_multiplier = std::exp(summary.max_real_part * 2 * std::numbers::pi / omega);
  summary.stable = summary.max_real_part <= options.stability_tolerance * omega;
  return summary;
}

MultiplierKind multiplier_kind(std::complex<double> exponent, double omega) {
  const double pi = std::numbers::pi;
  // θ = Im μ · 2π/Ω wrapped to [0, π] by symmetry (ρ and its conjugate are of one kind).
  const double theta = std::abs(std::remainder(exponent.imag() * 2 * pi / omega, 2 * pi));
  if (theta <= kRealMultiplierAngle) return MultiplierKind::kPlusOne;
  if (theta >= pi - kRealMultiplierAngle) return MultiplierKind::kMinusOne;
  return MultiplierKind::kComplex;
}

namespace {
int largest_of_kind(const FloquetSummary& s, MultiplierKind kind, double omega) {
  int best = -1;
  for (int i = 0; i < s.exponents.size(); ++i) {
    if (multiplier_kind(s.exponents[i], omega) != kind) continue;
    if (best < 0 || s.exponents[i].real() > s.exponents[best].real()) best = i;
  }
  return best;
}
}  // namespace

double largest_real_part(const FloquetSummary& s, MultiplierKind kind, double omega) {
  const int i = largest_of_kind(s, kind, omega);
  return i < 0 ? -std::numeric_limits<double>::infinity() : s.exponents[i].real();
}

std::complex<double> critical_multiplier(const FloquetSummary& s, MultiplierKind kind,
                                         double omega) {
  const int i = largest_of_kind(s, kind, omega);
  if (i < 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan};
  }
  return std::exp(s.exponents[i] * (2 * std::numbers::pi / omega));
}

std::vector<MultiplierKind> unit_circle_crossings(const FloquetSummary& a, double omega_a,
                                                  const FloquetSummary& b, double omega_b,
                                                  const HillOptions& options) {
  validate(options);
  const auto outside = [&](const FloquetSummary& s, double omega, MultiplierKind kind) {
    int count = 0;
    for (const std::complex<double>& mu : s.exponents) {
      count += multiplier_kind(mu, omega) == kind && mu.real() > options.stability_tolerance * omega
                   ? 1
                   : 0;
    }
    return count;
  };
  std::vector<MultiplierKind> crossed;
  for (const MultiplierKind kind :
       {MultiplierKind::kPlusOne, MultiplierKind::kMinusOne, MultiplierKind::kComplex}) {
    if (outside(a, omega_a, kind) != outside(b, omega_b, kind)) crossed.push_back(kind);
  }
  return crossed;
}

}  // namespace stickslip
