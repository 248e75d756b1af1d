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

namespace stickslip {

namespace {

using Complex = std::complex<double>;

// H = diag(h) on complex modes: G = Ψ diag(h) Ψᴴ, u_lin = Ψ diag(h) q, dG/dΩ z = Ψ diag(dh) Ψᴴ z.
class ComplexModesHarmonic final : public ModalFlexibility::Harmonic {
 public:
  ComplexModesHarmonic(const Eigen::MatrixXcd& Psi, const Eigen::VectorXcd& load,
                       Eigen::VectorXcd h, Eigen::VectorXcd dh)
      : Psi_(Psi), load_(load), h_(std::move(h)), dh_(std::move(dh)) {}
  Eigen::MatrixXcd times(const Eigen::MatrixXcd& X) const override { return h_.asDiagonal() * X; }
  void receptance(Eigen::MatrixXd& real, Eigen::MatrixXd& imag) const override {
    const Eigen::MatrixXcd G = (Psi_ * h_.asDiagonal()) * Psi_.adjoint();
    real = G.real();
    imag = G.imag();
  }
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
};

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
  }
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
  return std::make_unique<ComplexModesHarmonic>(m.Psi, m.load, std::move(h), std::move(dh));
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
