#include "recovery/stress_envelope.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <exception>
#include <limits>
#include <set>
#include <string>

#include "core/errors.h"
#include "core/parallel.h"
#include "core/types.h"

namespace stickslip {

namespace {

using Voigt = Eigen::Matrix<double, 6, 1>;

void check_amplitudes(std::span<const ComplexStressMatrix> amplitudes,
                      std::span<const int> harmonics) {
  if (amplitudes.size() != harmonics.size()) {
    throw InvalidInput("stress envelope: " + std::to_string(amplitudes.size()) +
                       " stress amplitudes but " + std::to_string(harmonics.size()) + " harmonics");
  }
  if (amplitudes.empty()) throw InvalidInput("stress envelope: no harmonics given");
  std::set<int> seen;
  for (size_t h = 0; h < harmonics.size(); ++h) {
    const int k = harmonics[h];
    require(k >= 0 && seen.insert(k).second, "harmonics[" + std::to_string(h) + "]",
            std::to_string(k), "harmonic >= 0, listed once");
    if (amplitudes[h].cols() != amplitudes[0].cols()) {
      throw InvalidInput("stress envelope: amplitudes[" + std::to_string(h) + "] has " +
                         std::to_string(amplitudes[h].cols()) + " nodes, amplitudes[0] has " +
                         std::to_string(amplitudes[0].cols()));
    }
    if (k == 0 && amplitudes[h].size() > 0) {
      // The mean of a real signal is real (round-off from a complex solve is tolerated).
      constexpr double kRealTolerance = 1e-10;
      const double scale = amplitudes[h].cwiseAbs().maxCoeff();
      if (amplitudes[h].imag().cwiseAbs().maxCoeff() > kRealTolerance * scale) {
        throw InvalidInput("stress envelope: harmonic 0 (amplitudes[" + std::to_string(h) +
                           "]) has an imaginary part; the mean must be real");
      }
    }
  }
}

int max_harmonic(std::span<const int> harmonics) {
  return harmonics.empty() ? 0 : *std::max_element(harmonics.begin(), harmonics.end());
}

// Invariants of σ: I1 = tr σ; deviator d = σ − I1/3 I; J2 = ½ d:d (= σ_vm² / 3); J3 = det d;
// q = sqrt(J2 / 3) (the deviatoric principal stresses are 2 q cos(φ − 2πm/3), m = 0, 1, 2).
struct Invariants {
  double I1 = 0.0, J2 = 0.0, J3 = 0.0, q = 0.0;
};

template <class V>
Invariants invariants(const V& s) {
  Invariants out;
  out.I1 = s[0] + s[1] + s[2];
  const double m = out.I1 / 3.0;
  const double d0 = s[0] - m, d1 = s[1] - m, d2 = s[2] - m;
  const double xy = s[3], xz = s[4], yz = s[5];
  out.J2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + xy * xy + xz * xz + yz * yz;
  out.J3 = d0 * (d1 * d2 - yz * yz) - xy * (xy * d2 - yz * xz) + xz * (xy * yz - d1 * xz);
  out.q = std::sqrt(out.J2 / 3.0);
  return out;
}

// φ in [0, π/3] with cos 3φ = J3 / (2 q³): the largest deviatoric principal stress is 2 q cos φ.
double principal_angle(const Invariants& inv) {
  const double r = inv.J3 / (2.0 * inv.q * inv.q * inv.q);
  return std::acos(std::clamp(r, -1.0, 1.0)) / 3.0;
}

double max_principal(const Invariants& inv) {
  if (!(inv.q > 0.0)) return inv.I1 / 3.0;
  return inv.I1 / 3.0 + 2.0 * inv.q * std::cos(principal_angle(inv));
}

// Sign of σ_1 + σ_3 (+1 on a tie) without an eigen-solve: σ_1 + σ_3 = c − s_2 with c = 2 I1 / 3
// and s_2 the middle deviatoric principal stress, |s_2| <= q <= s_1, s_3 <= −q. If |c| > q the
// sign is that of c; otherwise s_3 <= c <= s_1 and the characteristic polynomial
// g(c) = c³ − J2 c − J3 = (c − s_1)(c − s_2)(c − s_3) has the sign of −(c − s_2).
double svm_sign(const Invariants& inv) {
  const double c = 2.0 * inv.I1 / 3.0;
  if (c > inv.q) return 1.0;
  if (c < -inv.q) return -1.0;
  const double g = (c * c - inv.J2) * c - inv.J3;
  return g > 0.0 ? -1.0 : 1.0;
}

// σ_vm² = σᵀPσ as a symmetric bilinear form, for the derivatives along the period.
template <class V, class W>
double vm_dot(const V& x, const W& y) {
  return x[0] * y[0] + x[1] * y[1] + x[2] * y[2] -
         0.5 * (x[0] * y[1] + x[1] * y[0] + x[1] * y[2] + x[2] * y[1] + x[0] * y[2] + x[2] * y[0]) +
         3.0 * (x[3] * y[3] + x[4] * y[4] + x[5] * y[5]);
}

// One node's stress cycle σ(θ) = Σ_h A_h cos k_h θ + B_h sin k_h θ (θ = Ωt), A = Re S, B = −Im S.
struct Cycle {
  int nh = 0;
  const int* k = nullptr;
  const double* A = nullptr;  // 6 per harmonic
  const double* B = nullptr;
  int max_k = 0;
  mutable std::vector<double> cos_k, sin_k;  // cos kθ, sin kθ for k = 0..max_k

  void at(double theta, double* s, double* ds = nullptr, double* dds = nullptr) const {
    for (int i = 0; i < 6; ++i) s[i] = 0.0;
    if (ds) {
      for (int i = 0; i < 6; ++i) ds[i] = dds[i] = 0.0;
    }
    // One sine and cosine; the multiples by the angle-addition recurrence (max_k is small).
    const double c1 = std::cos(theta), s1 = std::sin(theta);
    cos_k[0] = 1.0, sin_k[0] = 0.0;
    for (int m = 1; m <= max_k; ++m) {
      cos_k[static_cast<size_t>(m)] =
          cos_k[static_cast<size_t>(m - 1)] * c1 - sin_k[static_cast<size_t>(m - 1)] * s1;
      sin_k[static_cast<size_t>(m)] =
          sin_k[static_cast<size_t>(m - 1)] * c1 + cos_k[static_cast<size_t>(m - 1)] * s1;
    }
    for (int h = 0; h < nh; ++h) {
      const double kk = k[h];
      const double c = cos_k[static_cast<size_t>(k[h])], sn = sin_k[static_cast<size_t>(k[h])];
      const double* a = A + 6 * h;
      const double* b = B + 6 * h;
      for (int i = 0; i < 6; ++i) s[i] += a[i] * c + b[i] * sn;
      if (ds) {
        for (int i = 0; i < 6; ++i) {
          ds[i] += kk * (b[i] * c - a[i] * sn);
          dds[i] -= kk * kk * (a[i] * c + b[i] * sn);
        }
      }
    }
  }
};

// Result of a search: the best value of the objective found at an evaluated instant.
// Objective: dir · σ_vm²(θ) (dir = +1 maximise, −1 minimise), restricted to instants where the
// sign of σ_svm equals `sign` (sign = 0: no restriction), searched in [lo, hi] from theta0
// (whose value f0 is known and admissible) by safeguarded Newton steps on σ_vm².
double newton_vm2(const Cycle& cycle, double theta0, double f0, double lo, double hi, double dir,
                  double sign, double start_sign = 0.0, bool* stayed = nullptr) {
  constexpr int kMaxSteps = 8;
  // Radians: Newton converges quadratically, so after a step this small the maximum's value is
  // at round-off (its error is ~ f'' Δθ²).
  constexpr double kStepTolerance = 1e-8;
  double theta = theta0, best = f0;
  double s[6], ds[6], dds[6];
  if (stayed != nullptr) *stayed = true;
  cycle.at(theta, s, ds, dds);
  for (int it = 0; it < kMaxSteps; ++it) {
    const double g = 2.0 * dir * vm_dot(s, ds);
    const double h = 2.0 * dir * (vm_dot(ds, ds) + vm_dot(s, dds));
    double next;
    if (h < 0.0) {
      next = theta - g / h;
    } else {  // not concave here: move to the end of the bracket that the slope points to
      next = g > 0.0 ? hi : lo;
    }
    next = std::clamp(next, lo, hi);
    if (std::abs(next - theta) < kStepTolerance) break;
    theta = next;
    cycle.at(theta, s, ds, dds);
    const double f = dir * vm_dot(s, s);
    if (sign != 0.0 || stayed != nullptr) {
      const double sg = svm_sign(invariants(s));
      if (sign != 0.0 && sg != sign) break;
      if (stayed != nullptr && sg != start_sign) *stayed = false;
    }
    best = std::max(best, f);
  }
  return best;
}

// The jump of σ_svm between two instants of opposite sign (t_a of sign +, t_b of sign −), by
// bisection: σ_vm² at the last instants found on each side (initially the given values).
struct SignJump {
  double vm2_positive = 0.0, vm2_negative = 0.0;
};
SignJump sign_jump(const Cycle& cycle, double t_positive, double vm2_positive, double t_negative,
                   double vm2_negative) {
  // Bracket (2π/N) 2^-12: σ_vm² moves by at most 2H max σ_vm² per radian (Bernstein), so the
  // value found is within 2H (2π/N) 2^-12 (< 1.3e-4 H of max σ_vm², N >= 24) of the one-sided
  // limit: finer than any sampling of a jump, which is resolution-dependent anyway.
  constexpr int kBisections = 12;
  SignJump jump{vm2_positive, vm2_negative};
  double s[6];
  for (int it = 0; it < kBisections; ++it) {
    const double mid = 0.5 * (t_positive + t_negative);
    cycle.at(mid, s);
    const Invariants v = invariants(s);
    if (svm_sign(v) > 0.0) {
      t_positive = mid, jump.vm2_positive = 3.0 * v.J2;
    } else {
      t_negative = mid, jump.vm2_negative = 3.0 * v.J2;
    }
  }
  return jump;
}

// Maximum of σ_1 in [theta0 − delta, theta0 + delta] from sample theta0 (value f0 >= the values
// fm, fp at the ends): successive parabolic interpolation, with a golden-section step whenever
// the parabola's vertex is unusable; returns the best value evaluated.
double refine_principal(const Cycle& cycle, double theta0, double delta, double fm, double f0,
                        double fp) {
  constexpr int kMaxSteps = 24;
  // Radians, on the bracket or on the last parabolic step: the value error is then
  // ~ H² A Δθ² / 2 (< 1e-10 of the amplitude A for H <= 3).
  constexpr double kBracket = 1e-5, kStep = 1e-6;
  constexpr double kGolden = 0.3819660112501051;
  double x[3] = {theta0 - delta, theta0, theta0 + delta};
  double f[3] = {fm, f0, fp};
  double best = f0;
  double s[6];
  for (int it = 0; it < kMaxSteps && x[2] - x[0] > kBracket; ++it) {
    const double a = x[1] - x[0], b = x[1] - x[2];
    const double fa = f[1] - f[0], fb = f[1] - f[2];
    const double den = a * fb - b * fa;
    double v = den != 0.0 ? x[1] - 0.5 * (a * a * fb - b * b * fa) / den : x[1];
    const bool parabolic = den != 0.0 && v > x[0] && v < x[2];
    // The parabola's vertex has settled on the middle point: that point is the maximum.
    if (parabolic && std::abs(v - x[1]) < kStep) break;
    if (!parabolic) {  // golden-section step into the larger side
      v = (x[1] - x[0] > x[2] - x[1]) ? x[1] - kGolden * (x[1] - x[0])
                                      : x[1] + kGolden * (x[2] - x[1]);
    }
    cycle.at(v, s);
    const double fv = max_principal(invariants(s));
    best = std::max(best, fv);
    if (v < x[1]) {
      if (fv >= f[1]) {
        x[2] = x[1], f[2] = f[1], x[1] = v, f[1] = fv;
      } else {
        x[0] = v, f[0] = fv;
      }
    } else {
      if (fv >= f[1]) {
        x[0] = x[1], f[0] = f[1], x[1] = v, f[1] = fv;
      } else {
        x[2] = v, f[2] = fv;
      }
    }
  }
  return best;
}

}  // namespace

void validate(const StressEnvelopeOptions& options, int max_harmonic) {
  require(options.time_samples == 0 || options.time_samples >= 2 * (2 * max_harmonic + 1),
          "StressEnvelopeOptions::time_samples", std::to_string(options.time_samples),
          "0 (automatic) or time_samples >= 2 (2 H + 1) = " +
              std::to_string(2 * (2 * max_harmonic + 1)) +
              " for the highest harmonic H = " + std::to_string(max_harmonic));
  require(options.num_threads >= 0, "StressEnvelopeOptions::num_threads",
          std::to_string(options.num_threads), "num_threads >= 0 (0 = one per hardware thread)");
}

int envelope_time_samples(const StressEnvelopeOptions& options, int max_harmonic) {
  validate(options, max_harmonic);
  return options.time_samples > 0 ? options.time_samples : std::max(16, 8 * (2 * max_harmonic + 1));
}

double von_mises_stress(const Voigt& s) {
  const double a = s(0) - s(1), b = s(1) - s(2), c = s(2) - s(0);
  const double shear = s(3) * s(3) + s(4) * s(4) + s(5) * s(5);
  return std::sqrt(std::max(0.0, 0.5 * (a * a + b * b + c * c) + 3.0 * shear));
}

Eigen::Vector3d principal_stresses(const Voigt& s) {
  const Invariants inv = invariants(s);
  const double mean = inv.I1 / 3.0;
  if (!(inv.q > 0.0)) return Eigen::Vector3d::Constant(mean);
  const double phi = principal_angle(inv);
  const double s1 = 2.0 * inv.q * std::cos(phi);
  const double s3 = 2.0 * inv.q * std::cos(phi + 2.0 * kPi / 3.0);
  return {mean + s1, mean - s1 - s3, mean + s3};
}

double signed_von_mises_stress(const Voigt& s) {
  const Invariants inv = invariants(s);
  return svm_sign(inv) * std::sqrt(3.0 * inv.J2);
}

std::vector<ComplexStressMatrix> harmonic_stresses(const Mesh& mesh,
                                                   const IsotropicMaterial& material,
                                                   const AssemblyOptions& options,
                                                   const Eigen::MatrixXcd& x,
                                                   std::span<const int> elements) {
  std::vector<ComplexStressMatrix> out;
  out.reserve(static_cast<size_t>(x.cols()));
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    out.push_back(nodal_stress(mesh, material, options, Eigen::VectorXcd(x.col(j)), elements));
  }
  return out;
}

ModalStressBasis::ModalStressBasis(const ModalRecovery& modal, const Mesh& mesh,
                                   const IsotropicMaterial& material,
                                   const AssemblyOptions& options, std::span<const int> elements)
    : num_nodes_(mesh.num_nodes()) {
  if (!modal.ok()) throw InvalidInput("ModalStressBasis: the modal recovery failed");
  if (modal.num_dofs() != mesh.num_dofs()) {
    throw InvalidInput("ModalStressBasis: the modal recovery and the mesh have different DOFs");
  }
  S_.resize(6 * num_nodes_, modal.num_basis_columns());
  for (int c = 0; c < modal.num_basis_columns(); ++c) {
    const StressMatrix s = nodal_stress(mesh, material, options, modal.basis_column(c), elements);
    S_.col(c) = Eigen::Map<const Eigen::VectorXd>(s.data(), s.size());
  }
}

ModalStressBasis::ModalStressBasis(const ModalRecovery& modal, const NodalStressOperator& stress)
    : num_nodes_(stress.num_nodes()) {
  if (!modal.ok()) throw InvalidInput("ModalStressBasis: the modal recovery failed");
  if (modal.num_dofs() != 3 * stress.num_nodes()) {
    throw InvalidInput("ModalStressBasis: the modal recovery and the mesh have different DOFs");
  }
  Eigen::MatrixXd U(modal.num_dofs(), modal.num_basis_columns());
  for (int c = 0; c < modal.num_basis_columns(); ++c) U.col(c) = modal.basis_column(c);
  S_ = stress.apply(U);
}

std::vector<ComplexStressMatrix> ModalStressBasis::stresses(const ModalRecovery& modal,
                                                            const Eigen::MatrixXcd& loads,
                                                            std::span<const int> harmonics,
                                                            double omega) const {
  const Eigen::MatrixXcd c = modal.coordinates(loads, harmonics, omega);
  if (c.rows() != S_.cols()) {
    throw InvalidInput("ModalStressBasis::stresses: built for another modal recovery");
  }
  // One pass over S_ for all harmonics, real and imaginary parts: S_ [Re c, Im c].
  const Eigen::Index m = c.cols();
  Eigen::MatrixXd c_split(c.rows(), 2 * m);
  c_split.leftCols(m) = c.real();
  c_split.rightCols(m) = c.imag();
  const Eigen::MatrixXd y = S_ * c_split;
  std::vector<ComplexStressMatrix> out;
  for (Eigen::Index j = 0; j < m; ++j) {
    ComplexStressMatrix s(6, num_nodes_);
    s.real() = Eigen::Map<const StressMatrix>(y.col(j).data(), 6, num_nodes_);
    s.imag() =
        harmonics[static_cast<size_t>(j)] == 0
            ? StressMatrix::Zero(6, num_nodes_)
            : StressMatrix(Eigen::Map<const StressMatrix>(y.col(m + j).data(), 6, num_nodes_));
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<StressMatrix> stress_time_history(std::span<const ComplexStressMatrix> amplitudes,
                                              std::span<const int> harmonics, int time_samples) {
  check_amplitudes(amplitudes, harmonics);
  require(time_samples >= 2 * (2 * max_harmonic(harmonics) + 1), "time_samples",
          std::to_string(time_samples), "time_samples >= 2 (2 H + 1)");
  std::vector<StressMatrix> out;
  out.reserve(static_cast<size_t>(time_samples));
  for (int j = 0; j < time_samples; ++j) {
    StressMatrix s = StressMatrix::Zero(6, amplitudes[0].cols());
    for (size_t h = 0; h < harmonics.size(); ++h) {
      const double theta =
          2.0 * kPi * ((static_cast<long long>(harmonics[h]) * j) % time_samples) / time_samples;
      s += amplitudes[h].real() * std::cos(theta) - amplitudes[h].imag() * std::sin(theta);
    }
    out.push_back(std::move(s));
  }
  return out;
}

StressEnvelope stress_envelope(std::span<const ComplexStressMatrix> amplitudes,
                               std::span<const int> harmonics,
                               const StressEnvelopeOptions& options) {
  check_amplitudes(amplitudes, harmonics);
  const int H = max_harmonic(harmonics);
  const int N = envelope_time_samples(options, H);
  const Eigen::Index num_nodes = amplitudes[0].cols();
  const int nh = static_cast<int>(harmonics.size());
  // cos/sin of every harmonic at every sample (k j reduced mod N first: exact sample angles).
  // Stored per harmonic, contiguous over the samples (the sample loops below vectorise).
  std::vector<double> cos_table(static_cast<size_t>(nh * N)), sin_table(cos_table.size());
  for (int h = 0; h < nh; ++h) {
    for (int j = 0; j < N; ++j) {
      const double theta = 2.0 * kPi * ((static_cast<long long>(harmonics[h]) * j) % N) / N;
      cos_table[static_cast<size_t>(h * N + j)] = std::cos(theta);
      sin_table[static_cast<size_t>(h * N + j)] = std::sin(theta);
    }
  }
  const double delta = 2.0 * kPi / N;
  // Sampling shortfall bound of σ_vm² (degree 2H): g = (2H)² δ² / 8 of its maximum. Sample local
  // maxima within 2g of the best one may hide the true maximum and are refined too.
  const double gap = std::min(1.0, 2.0 * (2.0 * H) * (2.0 * H) * delta * delta / 8.0);
  // The same for σ_1 (a maximum of degree-H functionals n·σn): H² δ² / 8 of the dynamic
  // amplitude, doubled as for σ_vm².
  const double p_gap = 2.0 * H * H * delta * delta / 8.0;
  StressEnvelope env;
  env.von_mises_max.resize(num_nodes);
  env.max_principal_max.resize(num_nodes);
  env.von_mises_alternating.resize(num_nodes);
  env.von_mises_mean.resize(num_nodes);
  env.von_mises_static = Eigen::VectorXd::Zero(num_nodes);
  const bool refine = options.refine;
  constexpr std::ptrdiff_t kNodesPerThread = 2000;  // below this a thread costs more than it saves

  auto work = [&](std::ptrdiff_t n0, std::ptrdiff_t n1, int) {
    std::vector<double> coef(static_cast<size_t>(12 * nh));
    std::vector<double> vm2(static_cast<size_t>(N)), sign(static_cast<size_t>(N)),
        upper(static_cast<size_t>(N)), p1(static_cast<size_t>(N));
    std::vector<double> sig(static_cast<size_t>(6 * N));  // component i at sample j: i N + j
    std::vector<double> I1(static_cast<size_t>(N)), J2(static_cast<size_t>(N)),
        J3(static_cast<size_t>(N)), q(static_cast<size_t>(N));
    std::vector<SignJump> jumps(static_cast<size_t>(N));
    std::vector<char> jump_done(static_cast<size_t>(N));
    std::vector<double> newton_value(static_cast<size_t>(N));
    Cycle cycle{nh,
                harmonics.data(),
                coef.data(),
                coef.data() + 6 * nh,
                H,
                std::vector<double>(static_cast<size_t>(H + 1)),
                std::vector<double>(static_cast<size_t>(H + 1))};
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (Eigen::Index n = n0; n < n1; ++n) {
      for (int h = 0; h < nh; ++h) {
        for (int i = 0; i < 6; ++i) {
          const std::complex<double> a = amplitudes[static_cast<size_t>(h)](i, n);
          coef[static_cast<size_t>(6 * h + i)] = a.real();
          coef[static_cast<size_t>(6 * (nh + h) + i)] = harmonics[h] == 0 ? 0.0 : -a.imag();
        }
      }
      // Samples: σ_vm², sign of σ_svm, the bound on σ_1 (as invariants(), svm_sign() above, in
      // loops over the samples that the compiler vectorises).
      std::fill(sig.begin(), sig.end(), 0.0);
      for (int h = 0; h < nh; ++h) {
        const double* ct = cos_table.data() + h * N;
        const double* st = sin_table.data() + h * N;
        for (int i = 0; i < 6; ++i) {
          const double a = cycle.A[6 * h + i], b = cycle.B[6 * h + i];
          double* out = sig.data() + i * N;
          for (int j = 0; j < N; ++j) out[j] += a * ct[j] + b * st[j];
        }
      }
      {
        const double *sx = sig.data(), *sy = sx + N, *sz = sy + N, *sxy = sz + N, *sxz = sxy + N,
                     *syz = sxz + N;
        for (int j = 0; j < N; ++j) {
          const double i1 = sx[j] + sy[j] + sz[j];
          const double m = i1 / 3.0;
          const double d0 = sx[j] - m, d1 = sy[j] - m, d2 = sz[j] - m;
          const double xy = sxy[j], xz = sxz[j], yz = syz[j];
          const double j2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + xy * xy + xz * xz + yz * yz;
          const double j3 =
              d0 * (d1 * d2 - yz * yz) - xy * (xy * d2 - yz * xz) + xz * (xy * yz - d1 * xz);
          const double qq = std::sqrt(j2 / 3.0);
          const double c = 2.0 * i1 / 3.0;
          const double g = (c * c - j2) * c - j3;
          I1[static_cast<size_t>(j)] = i1;
          J2[static_cast<size_t>(j)] = j2;
          J3[static_cast<size_t>(j)] = j3;
          q[static_cast<size_t>(j)] = qq;
          vm2[static_cast<size_t>(j)] = 3.0 * j2;
          upper[static_cast<size_t>(j)] = m + 2.0 * qq;
          sign[static_cast<size_t>(j)] = c > qq ? 1.0 : (c < -qq ? -1.0 : (g > 0.0 ? -1.0 : 1.0));
          p1[static_cast<size_t>(j)] = nan;
        }
      }
      int j_vm = 0;
      for (int j = 1; j < N; ++j) {
        if (vm2[static_cast<size_t>(j)] > vm2[static_cast<size_t>(j_vm)]) j_vm = j;
      }
      auto theta = [&](int j) { return delta * j; };
      auto wrap = [&](int j) { return (j % N + N) % N; };
      // Bound on |n·(σ(t) − S_0)n| over unit n: Σ_k>0 |S_k| (Frobenius <= √2 Voigt norm).
      auto dynamic_amplitude = [&] {
        double a = 0.0;
        for (int h = 0; h < nh; ++h) {
          if (harmonics[h] == 0) continue;
          double sq = 0.0;
          for (int i = 0; i < 6; ++i) {
            sq += cycle.A[6 * h + i] * cycle.A[6 * h + i] + cycle.B[6 * h + i] * cycle.B[6 * h + i];
          }
          a += std::sqrt(2.0 * sq);
        }
        return a;
      };
      auto principal_at = [&](int j) {
        double& v = p1[static_cast<size_t>(wrap(j))];
        if (std::isnan(v)) {
          const auto w = static_cast<size_t>(wrap(j));
          v = max_principal(Invariants{I1[w], J2[w], J3[w], q[w]});
        }
        return v;
      };

      // von Mises maximum.
      std::fill(newton_value.begin(), newton_value.end(), nan);
      double vm2_max = vm2[static_cast<size_t>(j_vm)];
      if (refine && vm2_max > 0.0) {
        const double floor = vm2_max * (1.0 - gap);
        for (int j = 0; j < N; ++j) {
          const double f = vm2[static_cast<size_t>(j)];
          if (f < floor || f <= vm2[static_cast<size_t>(wrap(j - 1))] ||
              f < vm2[static_cast<size_t>(wrap(j + 1))]) {
            if (j != j_vm) continue;
          }
          bool stayed = false;
          const double v = newton_vm2(cycle, theta(j), f, theta(j) - delta, theta(j) + delta, 1.0,
                                      0.0, sign[static_cast<size_t>(j)], &stayed);
          vm2_max = std::max(vm2_max, v);
          // Reused for the signed extremes if the search never left the sample's sign region.
          if (stayed) newton_value[static_cast<size_t>(j)] = v;
        }
      }

      // Maximum principal stress: exact values only where the bound can beat the best (less
      // the sampling shortfall bound when refining, so that every candidate peak is known).
      int j_p = 0;
      for (int j = 1; j < N; ++j) {
        if (upper[static_cast<size_t>(j)] > upper[static_cast<size_t>(j_p)]) j_p = j;
      }
      double p_max = principal_at(j_p);
      const double p_slack = refine ? p_gap * dynamic_amplitude() : 0.0;
      for (int j = 0; j < N; ++j) {
        if (upper[static_cast<size_t>(j)] > p_max - p_slack && principal_at(j) > p_max) {
          p_max = principal_at(j);
          j_p = j;
        }
      }
      if (refine && vm2_max > 0.0) {
        const double floor = p_max - p_slack;
        for (int j = 0; j < N; ++j) {
          const double f = p1[static_cast<size_t>(j)];
          if (std::isnan(f) || f < floor) continue;
          const double fm = principal_at(j - 1), fp = principal_at(j + 1);
          if (f < fm || f < fp) continue;  // not a sampled peak
          p_max = std::max(p_max, refine_principal(cycle, theta(j), delta, fm, f, fp));
        }
      }

      // Signed von Mises extremes. o_j = sign_j σ_vm²(t_j) orders the samples like σ_svm;
      // up = +1 for the maximum, −1 for the minimum, u = up o is maximised. Candidates: sampled
      // peaks of u within the shortfall bound (polished by Newton on σ_vm² inside their sign
      // region), and, where the sign flips between two samples, the boundary on the side that
      // helps (the supremum there is approached at the jump).
      std::fill(jump_done.begin(), jump_done.end(), 0);
      auto extreme = [&](double up) {
        auto u = [&](int j) {
          return up * sign[static_cast<size_t>(wrap(j))] * vm2[static_cast<size_t>(wrap(j))];
        };
        int jb = 0;
        for (int j = 1; j < N; ++j) {
          if (u(j) > u(jb)) jb = j;
        }
        double best = u(jb);
        if (refine && vm2_max > 0.0) {
          const double slack = gap * vm2_max;
          for (int j = 0; j < N; ++j) {
            if (u(j) < best - slack || (j != jb && (u(j) <= u(j - 1) || u(j) < u(j + 1)))) {
              continue;
            }
            const double sg = sign[static_cast<size_t>(j)];
            // Within the sign region of sample j the objective u is (up sg) σ_vm².
            if (up * sg > 0.0 && !std::isnan(newton_value[static_cast<size_t>(j)])) {
              best = std::max(best, newton_value[static_cast<size_t>(j)]);
              continue;
            }
            best = std::max(best, newton_vm2(cycle, theta(j), u(j), theta(j) - delta,
                                             theta(j) + delta, up * sg, sg));
          }
          // Jumps: vm² on [t_j, t_j+1] is below its end values plus H δ max σ_vm² (Bernstein).
          const double rise = H * delta * vm2_max / (1.0 - std::min(gap, 0.5));
          for (int j = 0; j < N; ++j) {
            const double a = sign[static_cast<size_t>(j)];
            const double b = sign[static_cast<size_t>(wrap(j + 1))];
            if (a == b) continue;
            const double bound =
                std::max(vm2[static_cast<size_t>(j)], vm2[static_cast<size_t>(wrap(j + 1))]) + rise;
            if (bound <= best) continue;
            SignJump& jump = jumps[static_cast<size_t>(j)];
            if (!jump_done[static_cast<size_t>(j)]) {  // shared by the maximum and the minimum
              const int jp = a > 0.0 ? j : j + 1, jn = a > 0.0 ? j + 1 : j;
              jump = sign_jump(cycle, theta(jp), vm2[static_cast<size_t>(wrap(jp))], theta(jn),
                               vm2[static_cast<size_t>(wrap(jn))]);
              jump_done[static_cast<size_t>(j)] = 1;
            }
            best = std::max(best, up > 0.0 ? jump.vm2_positive : jump.vm2_negative);
          }
        }
        const double o = up * best;  // sign · σ_vm²
        return o >= 0.0 ? std::sqrt(o) : -std::sqrt(-o);
      };
      const double svm_max = extreme(1.0);
      const double svm_min = extreme(-1.0);

      env.von_mises_max(n) = std::sqrt(vm2_max);
      env.max_principal_max(n) = p_max;
      env.von_mises_alternating(n) = 0.5 * (svm_max - svm_min);
      env.von_mises_mean(n) = 0.5 * (svm_max + svm_min);
      for (int h = 0; h < nh; ++h) {
        if (harmonics[h] == 0) {
          env.von_mises_static(n) =
              von_mises_stress(Voigt(Eigen::Map<const Voigt>(cycle.A + 6 * h)));
        }
      }
    }
  };
  parallel_for(num_nodes, thread_count(options.num_threads), work, kNodesPerThread);
  return env;
}

}  // namespace stickslip
