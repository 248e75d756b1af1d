#include "hbm/travelling_wave.h"

#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>

#include "core/errors.h"
#include "core/format.h"
#include "hbm/harmonic_balance.h"
#include "linalg/blas.h"

namespace stickslip {

namespace {

using Complex = std::complex<double>;

// S = Ψ diag(d) Ψᴴ (Hermitian, returned full) for a complex Ψ and a real d, through BLAS zherk
// (several times faster than Eigen's portable complex product; half the flops of a general one):
// the columns of Ψ scaled by √|d_r| in two groups, d_r > 0 added and d_r < 0 subtracted, into the
// lower triangle, then mirrored.
void weighted_hermitian_gram(const Eigen::MatrixXcd& Psi, const Eigen::VectorXd& d,
                             Eigen::MatrixXcd& S) {
  const int n = static_cast<int>(Psi.rows());
  S.setZero(n, n);
  if (n == 0) return;  // no contact rows (BLAS refuses a leading dimension of 0)
  Eigen::MatrixXcd scaled;
  for (const double sign : {1.0, -1.0}) {
    int count = 0;
    for (Eigen::Index r = 0; r < d.size(); ++r) count += sign * d[r] > 0 ? 1 : 0;
    if (count == 0) continue;
    scaled.resize(n, count);
    int c = 0;
    for (Eigen::Index r = 0; r < d.size(); ++r) {
      if (sign * d[r] > 0) scaled.col(c++) = std::sqrt(sign * d[r]) * Psi.col(r);
    }
    const double beta = 1.0;
    const char uplo = 'L', trans = 'N';
    zherk_(&uplo, &trans, &n, &count, &sign, scaled.data(), &n, &beta, S.data(), &n);
  }
  S.triangularView<Eigen::StrictlyUpper>() = S.adjoint();
}

// The modes far above the excitation in the receptance, as a power series. With Rayleigh damping
// c_r = α + βω_r² and w = kΩ, every mode's h_r = 1/(ω_r² − w² + iwc_r) = 1/(a(ω_r² − s)),
// a = 1 + iwβ, s = (w² − iwα)/a, so for the modes with ω_r² ≥ λ_c > |s|
//   Σ_r ψ_r h_r ψ_rᴴ = (1/a) Σ_{j≥0} s^j C_j,   C_j = Σ_r ψ_r ω_r^{−2(j+1)} ψ_rᴴ   (Hermitian),
// the C_j independent of Ω: per Ω the receptance then needs the modes below λ_c only (a sweep's
// few dozen of a Craig–Bampton model's hundreds to thousands) and kSeriesTerms sums of nu x nu
// matrices. The first kSeriesTerms terms are kept: the rest is below ρ^p/(1 − ρ) of the high modes'
// part, ρ = |s|/λ_c ≤ kSeriesRatio, 1.3e-17 (round-off). Built with ρ = kSeriesBuildRatio at the
// Ω that needs it, so Ω may grow by √2 before a rebuild.
constexpr double kSeriesBuildRatio = 0.025;
constexpr double kSeriesRatio = 0.05;
constexpr int kSeriesTerms = 13;  // 0.05^13 = 1.2e-17
// c_r = α + βω_r² is recognised to this fraction of the largest c_r (their own round-off).
constexpr double kRayleighTolerance = 1e-12;

}  // namespace

struct TravellingWaveFlexibility::Series {
  double limit = 0.0;             // used while |s| ≤ limit = kSeriesRatio λ_c
  std::vector<Eigen::Index> low;  // the modes below λ_c
  Eigen::MatrixXcd psi_low;       // their columns of Ψ
  // nu² x kSeriesTerms, column j the column-major C_j; rows contiguous, so that the sum reads
  // each entry once and writes G once.
  Eigen::Matrix<Complex, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> terms;
};

namespace {

// H = diag(h) on complex modes: G = Ψ diag(h) Ψᴴ, u_lin = Ψ diag(h) q, dG/dΩ z = Ψ diag(dh) Ψᴴ z.
// With a series (above), G is its low modes' part plus (1/a) Σ s^j C_j.
class ComplexModesHarmonic final : public ModalFlexibility::Harmonic {
 public:
  ComplexModesHarmonic(const Eigen::MatrixXcd& Psi, const Eigen::VectorXcd& load,
                       Eigen::VectorXcd h, Eigen::VectorXcd dh,
                       std::shared_ptr<const TravellingWaveFlexibility::Series> series = nullptr,
                       Complex a = 1.0, Complex s = 0.0)
      : Psi_(Psi),
        load_(load),
        h_(std::move(h)),
        dh_(std::move(dh)),
        series_(std::move(series)),
        a_(a),
        s_(s) {}
  Eigen::MatrixXcd times(const Eigen::MatrixXcd& X) const override { return h_.asDiagonal() * X; }
  void receptance(Eigen::MatrixXd& real, Eigen::MatrixXd& imag) const override;
  Eigen::VectorXcd load_response() const override {
    if (load_.size() == 0) return Eigen::VectorXcd::Zero(Psi_.rows());
    return Psi_ * h_.cwiseProduct(load_);
  }
  Eigen::VectorXcd load_response_derivative() const override {
    STICKSLIP_VERIFY(dh_.size() == h_.size(), "ModalFlexibility: made without the derivative");
    if (load_.size() == 0) return Eigen::VectorXcd::Zero(Psi_.rows());
    return Psi_ * dh_.cwiseProduct(load_);
  }
  Eigen::VectorXcd receptance_derivative_times(const Eigen::VectorXcd& z) const override {
    STICKSLIP_VERIFY(dh_.size() == h_.size(), "ModalFlexibility: made without the derivative");
    return Psi_ * dh_.cwiseProduct(Psi_.adjoint() * z);
  }

 private:
  const Eigen::MatrixXcd& Psi_;
  const Eigen::VectorXcd& load_;
  Eigen::VectorXcd h_, dh_;
  std::shared_ptr<const TravellingWaveFlexibility::Series> series_;
  Complex a_, s_;
};

void ComplexModesHarmonic::receptance(Eigen::MatrixXd& real, Eigen::MatrixXd& imag) const {
  // G = A + iB with the Hermitian A = Ψ diag(Re h) Ψᴴ, B = Ψ diag(Im h) Ψᴴ (the low modes' only
  // with a series).
  Eigen::MatrixXcd A, B;
  if (!series_) {
    weighted_hermitian_gram(Psi_, h_.real(), A);
    weighted_hermitian_gram(Psi_, h_.imag(), B);
    real = A.real() - B.imag();
    imag = A.imag() + B.real();
    return;
  }
  const TravellingWaveFlexibility::Series& series = *series_;
  Eigen::VectorXcd h_low(static_cast<Eigen::Index>(series.low.size()));
  for (Eigen::Index i = 0; i < h_low.size(); ++i) h_low[i] = h_[series.low[i]];
  weighted_hermitian_gram(series.psi_low, h_low.real(), A);
  weighted_hermitian_gram(series.psi_low, h_low.imag(), B);
  Eigen::MatrixXcd G(A.rows(), A.cols());
  G.real() = A.real() - B.imag();
  G.imag() = A.imag() + B.real();
  // Σ_j (s^j / a) C_j as one matrix-vector product over the stacked terms: each term is read
  // once (the sum is bound by memory traffic, not flops).
  Eigen::VectorXcd factors(series.terms.cols());
  Complex factor = 1.0 / a_;
  for (Eigen::Index j = 0; j < factors.size(); ++j, factor *= s_) factors[j] = factor;
  Eigen::Map<Eigen::VectorXcd>(G.data(), G.size()).noalias() += series.terms * factors;
  real = G.real();
  imag = G.imag();
}

}  // namespace

ComplexModalModel complex_modal_model_from_matrices(const Eigen::MatrixXcd& K,
                                                    const Eigen::MatrixXcd& M, double alpha,
                                                    double beta) {
  require(K.rows() == K.cols() && M.rows() == M.cols() && K.rows() == M.rows() && K.rows() > 0,
          "K, M", std::to_string(K.rows()) + " x " + std::to_string(K.cols()), "square, same size");
  require(K.allFinite() && M.allFinite(), "K, M", "non-finite entry", "finite");
  // Jacobi scaling by diag(M)^{-1/2}: physical and modal coordinates of a Craig–Bampton model
  // differ by orders of magnitude in scale.
  const Eigen::VectorXd d = M.diagonal().real();
  require(d.minCoeff() > 0, "M", "a non-positive diagonal entry", "M Hermitian positive definite");
  const Eigen::VectorXd s = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXcd Ks = s.asDiagonal() * K * s.asDiagonal();
  const Eigen::MatrixXcd Ms = s.asDiagonal() * M * s.asDiagonal();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXcd> eig(0.5 * (Ks + Ks.adjoint()),
                                                                       0.5 * (Ms + Ms.adjoint()));
  require(eig.info() == Eigen::Success, "M", "not positive definite",
          "M Hermitian positive definite");
  ComplexModalModel model;
  model.omega2 = eig.eigenvalues().cwiseMax(0.0);
  // Rigid-body modes (a body held only by contacts): exactly 0, not round-off of either sign.
  model.omega2 = model.omega2.cwiseProduct(elastic_modes(model.omega2));
  model.Phi = s.asDiagonal() * eig.eigenvectors();  // Φᴴ M Φ = I
  model.modal_damping = rayleigh_modal_damping(model.omega2, alpha, beta);
  return model;
}

double TravellingWave::phase(int k) const {
  // k·EO mod N first: the phase of large engine orders and harmonics without round-off growth.
  const long long turns = (static_cast<long long>(k) * engine_order) % sectors;
  return 2.0 * std::numbers::pi * static_cast<double>(turns) / sectors;
}

int travelling_wave_nodal_diameter(int k, int engine_order, int sectors, bool* conjugate) {
  const int h = static_cast<int>((static_cast<long long>(k) * engine_order) % sectors);
  const bool conj = 2 * h > sectors;
  if (conjugate) *conjugate = conj;
  return conj ? sectors - h : h;
}

Eigen::Matrix3d sector_rotation(const Eigen::Matrix3d& rotation, int s) {
  if (s == 0) return Eigen::Matrix3d::Identity();
  return s > 0 ? rotation : Eigen::Matrix3d(rotation.transpose());
}

Eigen::MatrixXcd travelling_wave_contact_modes(const std::vector<ContactPair>& pairs,
                                               const std::vector<int>& pair_rows, int rows,
                                               const Eigen::MatrixXcd& Phi,
                                               const TravellingWave& wave, int k) {
  Eigen::MatrixXcd Psi = Eigen::MatrixXcd::Zero(rows, Phi.cols());
  const double sigma = wave.phase(k);
  for (size_t p = 0; p < pairs.size(); ++p) {
    const ContactPair& c = pairs[p];
    const int m = static_cast<int>(c.frame.rows()), r = pair_rows[p];
    for (int i = 0; i < static_cast<int>(c.dofs_a.size()); ++i)
      Psi.middleRows(r, m) += c.frame.col(i).cast<Complex>() * Phi.row(c.dofs_a[i]);
    if (c.dofs_b.empty()) continue;
    // −e^{iσ s} R_p R^s per node of B (its DOFs in x, y, z triples when s ≠ 0).
    const Eigen::Matrix3d Rs = sector_rotation(wave.rotation, c.b_sector);
    const Complex shift = std::polar(1.0, sigma * c.b_sector);
    for (int i = 0; i < static_cast<int>(c.dofs_b.size()); ++i) {
      Eigen::VectorXd column = c.frame.col(i);
      if (c.b_sector != 0) {
        const int node = i / 3, dir = i % 3;
        column.setZero();
        for (int e = 0; e < 3; ++e) column += c.frame.col(3 * node + e) * Rs(e, dir);
      }
      Psi.middleRows(r, m) -= (shift * column.cast<Complex>()) * Phi.row(c.dofs_b[i]);
    }
  }
  return Psi;
}

TravellingWaveFlexibility::TravellingWaveFlexibility(ModalProjection projection,
                                                     const TravellingWave& wave,
                                                     const std::vector<ContactPair>& pairs,
                                                     const std::vector<int>& pair_rows, int rows,
                                                     const std::map<int, Eigen::VectorXcd>& loads)
    : ModalFlexibility(std::move(projection)) {
  for (const auto& [k, model] : wave.harmonics) {
    Model& m = models_[k];
    m.omega2 = model.omega2;
    m.c = model.modal_damping;
    m.Phi = model.Phi;
    m.Psi = travelling_wave_contact_modes(pairs, pair_rows, rows, model.Phi, wave, k);
    const auto load = loads.find(k);
    if (load != loads.end()) m.load = model.Phi.adjoint() * load->second;
    // Rayleigh damping? From the modes of the lowest and highest ω², checked on all.
    const Eigen::Index nm = m.omega2.size();
    if (nm >= 2) {
      Eigen::Index lo = 0, hi = 0;
      m.omega2.minCoeff(&lo);
      m.omega2.maxCoeff(&hi);
      if (m.omega2[hi] > m.omega2[lo]) {
        m.beta = (m.c[hi] - m.c[lo]) / (m.omega2[hi] - m.omega2[lo]);
        m.alpha = m.c[lo] - m.beta * m.omega2[lo];
        const double scale = m.c.cwiseAbs().maxCoeff();
        m.rayleigh = ((m.c.array() - m.alpha - m.beta * m.omega2.array()).abs() <=
                      kRayleighTolerance * scale)
                         .all();
      }
    }
  }
}

std::shared_ptr<const TravellingWaveFlexibility::Series> TravellingWaveFlexibility::series(
    int k, Complex s) const {
  const Model& m = of(k);
  const double size = std::abs(s);
  if (!m.rayleigh || !(size > 0.0) || !std::isfinite(size)) return nullptr;
  const std::lock_guard<std::mutex> lock(series_mutex_);
  const auto it = series_.find(k);
  if (it != series_.end() && it->second && size <= it->second->limit) return it->second;
  const double cutoff = size / kSeriesBuildRatio;
  std::vector<Eigen::Index> low, high;
  for (Eigen::Index r = 0; r < m.omega2.size(); ++r)
    (m.omega2[r] >= cutoff ? high : low).push_back(r);
  // Worth it when the series replaces more modes per Ω than it has terms.
  if (static_cast<int>(high.size()) <= 2 * kSeriesTerms) return nullptr;
  auto out = std::make_shared<Series>();
  out->limit = kSeriesRatio * cutoff;
  out->low = low;
  out->psi_low.resize(m.Psi.rows(), static_cast<Eigen::Index>(low.size()));
  for (size_t i = 0; i < low.size(); ++i)
    out->psi_low.col(static_cast<Eigen::Index>(i)) = m.Psi.col(low[i]);
  Eigen::MatrixXcd psi_high(m.Psi.rows(), static_cast<Eigen::Index>(high.size()));
  Eigen::VectorXd inverse(static_cast<Eigen::Index>(high.size())), weight;
  for (size_t i = 0; i < high.size(); ++i) {
    psi_high.col(static_cast<Eigen::Index>(i)) = m.Psi.col(high[i]);
    inverse[static_cast<Eigen::Index>(i)] = 1.0 / m.omega2[high[i]];
  }
  weight = inverse;
  const Eigen::Index nu = m.Psi.rows();
  out->terms.resize(nu * nu, kSeriesTerms);
  Eigen::MatrixXcd C;
  for (int j = 0; j < kSeriesTerms; ++j) {
    weighted_hermitian_gram(psi_high, weight, C);
    out->terms.col(j) = Eigen::Map<const Eigen::VectorXcd>(C.data(), C.size());
    weight = weight.cwiseProduct(inverse);
  }
  series_[k] = out;
  return out;
}

const TravellingWaveFlexibility::Model& TravellingWaveFlexibility::of(int k) const {
  const auto it = models_.find(k);
  STICKSLIP_VERIFY(it != models_.end(),
                   "TravellingWaveFlexibility: no model for harmonic " + std::to_string(k));
  return it->second;
}

std::unique_ptr<const ModalFlexibility::Harmonic> TravellingWaveFlexibility::dynamic(
    int k, double omega, bool derivative) const {
  const Model& m = of(k);
  const double kw = k * omega;
  const Eigen::Index nm = m.omega2.size();
  Eigen::VectorXcd h(nm), dh;
  for (Eigen::Index r = 0; r < nm; ++r) h[r] = 1.0 / Complex(m.omega2[r] - kw * kw, kw * m.c[r]);
  if (derivative) {
    dh.resize(nm);
    for (Eigen::Index r = 0; r < nm; ++r)
      dh[r] = -h[r] * h[r] * Complex(-2.0 * k * k * omega, k * m.c[r]);
  }
  const Complex a(1.0, kw * m.beta), s = Complex(kw * kw, -kw * m.alpha) / a;
  return std::make_unique<ComplexModesHarmonic>(m.Psi, m.load, std::move(h), std::move(dh),
                                                series(k, s), a, s);
}

Eigen::VectorXcd TravellingWaveFlexibility::master_response(
    int k, double omega, const Eigen::VectorXcd& contact_force) const {
  const Model& m = of(k);
  Eigen::VectorXcd q = -(m.Psi.adjoint() * contact_force);
  if (m.load.size() > 0) q += m.load;
  return m.Phi * dynamic(k, omega, false)->times(q);
}

Eigen::VectorXcd TravellingWaveFlexibility::quasi_static_response(int k) const {
  const Model& m = of(k);
  if (m.load.size() == 0) return Eigen::VectorXcd::Zero(m.Psi.rows());
  // Over the elastic modes (a rigid-body mode has no static flexibility; this is a scale).
  const Eigen::VectorXd elastic = elastic_modes(m.omega2);
  Eigen::VectorXcd h = Eigen::VectorXcd::Zero(m.omega2.size());
  for (Eigen::Index r = 0; r < h.size(); ++r)
    if (elastic[r] > 0) h[r] = 1.0 / m.omega2[r];
  return m.Psi * h.cwiseProduct(m.load);
}

}  // namespace stickslip
