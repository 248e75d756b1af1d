#include "hbm/modal_flexibility.h"

#include <cmath>
#include <complex>
#include <memory>
#include <string>
#include <utility>

#include <Eigen/LU>

#include "core/errors.h"
#include "hbm/damped_modes.h"
#include "linalg/blas.h"

namespace stickslip {

namespace {

using Complex = std::complex<double>;

// A v for real A and complex v, as two real products (vectorised, no complex casts of A).
template <typename Matrix>
Eigen::VectorXcd real_times(const Matrix& A, const Eigen::VectorXcd& v) {
  Eigen::VectorXcd out(A.rows());
  out.real() = A * v.real();
  out.imag() = A * v.imag();
  return out;
}

// S = Ψ diag(d) Ψᵀ (symmetric, returned full) through BLAS dsyrk (OpenBLAS's kernels are several
// times faster than Eigen's portable ones here): the columns of Ψ scaled by √|d_r| in two groups,
// d_r > 0 added and d_r < 0 subtracted, into the lower triangle, then mirrored.
void weighted_gram(const Eigen::MatrixXd& Psi, const Eigen::VectorXd& d, Eigen::MatrixXd& S) {
  const int n = static_cast<int>(Psi.rows());
  S.setZero(n, n);
  if (n == 0) return;  // no contact rows (BLAS refuses a leading dimension of 0)
  Eigen::MatrixXd scaled;
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
    dsyrk_(&uplo, &trans, &n, &count, &sign, scaled.data(), &n, &beta, S.data(), &n);
  }
  S.triangularView<Eigen::StrictlyUpper>() = S.transpose();
}

// A diagonal H = diag(h) with dH/dΩ = diag(dh): every harmonic of the diagonal implementation and
// harmonic 0 of all three (dh = 0).
class DiagonalHarmonic final : public ModalFlexibility::Harmonic {
 public:
  DiagonalHarmonic(const Eigen::MatrixXd& Psi, const Eigen::VectorXcd* load, Eigen::VectorXcd h,
                   Eigen::VectorXcd dh)
      : Psi_(Psi), load_(load), h_(std::move(h)), dh_(std::move(dh)) {}
  Eigen::MatrixXcd times(const Eigen::MatrixXcd& X) const override { return h_.asDiagonal() * X; }
  void receptance(Eigen::MatrixXd& real, Eigen::MatrixXd& imag) const override {
    weighted_gram(Psi_, h_.real(), real);
    weighted_gram(Psi_, h_.imag(), imag);
  }
  Eigen::VectorXcd load_response() const override {
    if (!load_) return Eigen::VectorXcd::Zero(Psi_.rows());
    return real_times(Psi_, Eigen::VectorXcd(h_.cwiseProduct(*load_)));
  }
  Eigen::VectorXcd load_response_derivative() const override {
    STICKSLIP_VERIFY(dh_.size() == h_.size(), "ModalFlexibility: made without the derivative");
    if (!load_) return Eigen::VectorXcd::Zero(Psi_.rows());
    return real_times(Psi_, Eigen::VectorXcd(dh_.cwiseProduct(*load_)));
  }
  Eigen::VectorXcd receptance_derivative_times(const Eigen::VectorXcd& z) const override {
    STICKSLIP_VERIFY(dh_.size() == h_.size(), "ModalFlexibility: made without the derivative");
    return real_times(Psi_, Eigen::VectorXcd(dh_.cwiseProduct(real_times(Psi_.transpose(), z))));
  }

 private:
  const Eigen::MatrixXd& Psi_;
  const Eigen::VectorXcd* load_;
  Eigen::VectorXcd h_, dh_;  // dh_ empty: no derivative
};

class DiagonalFlexibility final : public ModalFlexibility {
 public:
  DiagonalFlexibility(ModalProjection projection, Eigen::VectorXd c)
      : ModalFlexibility(std::move(projection)), c_(std::move(c)) {
    require(c_.size() == projection_size(), "ModalFlexibility.modal_damping",
            "size " + std::to_string(c_.size()), "one per mode");
  }
  ModalFlexibilityMethod method() const override { return ModalFlexibilityMethod::kDiagonal; }

 protected:
  std::unique_ptr<const Harmonic> dynamic(int k, double omega, bool derivative) const override {
    const Eigen::VectorXd& w2 = projection().omega2;
    const double kw = k * omega;
    Eigen::VectorXcd h(w2.size()), dh;
    for (Eigen::Index r = 0; r < w2.size(); ++r) h[r] = 1.0 / Complex(w2[r] - kw * kw, kw * c_[r]);
    if (derivative) {
      dh.resize(h.size());
      for (Eigen::Index r = 0; r < h.size(); ++r) {
        dh[r] = -h[r] * h[r] * Complex(-2.0 * k * k * omega, k * c_[r]);
      }
    }
    return std::make_unique<DiagonalHarmonic>(projection().Psi, load(k), std::move(h),
                                              std::move(dh));
  }

 private:
  Eigen::Index projection_size() const { return projection().omega2.size(); }
  Eigen::VectorXd c_;
};

class ImpedanceLuHarmonic final : public ModalFlexibility::Harmonic {
 public:
  ImpedanceLuHarmonic(const Eigen::MatrixXd& Psi, const Eigen::MatrixXd& C_m,
                      const Eigen::VectorXd& omega2, const Eigen::VectorXcd* load, int k,
                      double omega, bool derivative)
      : Psi_(Psi), C_m_(C_m), k_(k), omega_(omega), derivative_(derivative) {
    const double kw = k * omega;
    Eigen::MatrixXcd Z(omega2.size(), omega2.size());
    Z.real() = (omega2.array() - kw * kw).matrix().asDiagonal();
    Z.imag() = kw * C_m;
    lu_.compute(Z);
    if (load) load_response_ = lu_.solve(*load);  // H q (modal), kept for the derivative
  }
  Eigen::MatrixXcd times(const Eigen::MatrixXcd& X) const override { return lu_.solve(X); }
  void receptance(Eigen::MatrixXd& real, Eigen::MatrixXd& imag) const override {
    const Eigen::MatrixXcd X = lu_.solve(Psi_.transpose().cast<Complex>());  // H Ψᵀ, nm x nu
    Eigen::MatrixXcd G(Psi_.rows(), Psi_.rows());
    G.real().noalias() = Psi_ * X.real();
    G.imag().noalias() = Psi_ * X.imag();
    G = (0.5 * (G + G.transpose())).eval();  // complex symmetric; exact against round-off
    real = G.real();
    imag = G.imag();
  }
  Eigen::VectorXcd load_response() const override {
    if (load_response_.size() == 0) return Eigen::VectorXcd::Zero(Psi_.rows());
    return real_times(Psi_, load_response_);
  }
  Eigen::VectorXcd load_response_derivative() const override {
    STICKSLIP_VERIFY(derivative_, "ModalFlexibility: made without the derivative");
    if (load_response_.size() == 0) return Eigen::VectorXcd::Zero(Psi_.rows());
    return real_times(Psi_, derivative_times_response(load_response_));
  }
  Eigen::VectorXcd receptance_derivative_times(const Eigen::VectorXcd& z) const override {
    STICKSLIP_VERIFY(derivative_, "ModalFlexibility: made without the derivative");
    const Eigen::VectorXcd y = lu_.solve(real_times(Psi_.transpose(), z));
    return real_times(Psi_, derivative_times_response(y));
  }

 private:
  // dH/dΩ v from y = H v: −H (−2k²Ω I + i k C_m) y.
  Eigen::VectorXcd derivative_times_response(const Eigen::VectorXcd& y) const {
    return -lu_.solve(
        Eigen::VectorXcd(-2.0 * k_ * k_ * omega_ * y + Complex(0, k_) * real_times(C_m_, y)));
  }
  const Eigen::MatrixXd& Psi_;
  const Eigen::MatrixXd& C_m_;
  int k_;
  double omega_;
  bool derivative_;
  Eigen::PartialPivLU<Eigen::MatrixXcd> lu_;
  Eigen::VectorXcd load_response_;
};

class ImpedanceLuFlexibility final : public ModalFlexibility {
 public:
  ImpedanceLuFlexibility(ModalProjection projection, Eigen::MatrixXd C_m)
      : ModalFlexibility(std::move(projection)), C_m_(std::move(C_m)) {
    const Eigen::Index nm = this->projection().omega2.size();
    require(C_m_.rows() == nm && C_m_.cols() == nm, "ModalFlexibility.modal_damping_matrix",
            std::to_string(C_m_.rows()) + " x " + std::to_string(C_m_.cols()), "nm x nm");
  }
  ModalFlexibilityMethod method() const override { return ModalFlexibilityMethod::kImpedanceLu; }

 protected:
  std::unique_ptr<const Harmonic> dynamic(int k, double omega, bool derivative) const override {
    return std::make_unique<ImpedanceLuHarmonic>(projection().Psi, C_m_, projection().omega2,
                                                 load(k), k, omega, derivative);
  }

 private:
  Eigen::MatrixXd C_m_;
};

class StateSpaceHarmonic final : public ModalFlexibility::Harmonic {
 public:
  StateSpaceHarmonic(const DampedModalExpansion& d, const Eigen::VectorXcd* load, int k,
                     double omega, bool derivative)
      : d_(d), load_(load), w_(d.weights(k * omega)) {
    if (derivative) dw_ = d.weight_derivatives(k, omega);
  }
  Eigen::MatrixXcd times(const Eigen::MatrixXcd& X) const override {
    return d_.X * (w_.asDiagonal() * (d_.X.transpose() * X));
  }
  void receptance(Eigen::MatrixXd& real, Eigen::MatrixXd& imag) const override {
    damped_gram(d_, w_, real, imag);
  }
  Eigen::VectorXcd load_response() const override {
    if (!load_) return Eigen::VectorXcd::Zero(d_.P.rows());
    return d_.P * w_.cwiseProduct(*load_);
  }
  Eigen::VectorXcd load_response_derivative() const override {
    STICKSLIP_VERIFY(dw_.size() == w_.size(), "ModalFlexibility: made without the derivative");
    if (!load_) return Eigen::VectorXcd::Zero(d_.P.rows());
    return d_.P * dw_.cwiseProduct(*load_);
  }
  Eigen::VectorXcd receptance_derivative_times(const Eigen::VectorXcd& z) const override {
    STICKSLIP_VERIFY(dw_.size() == w_.size(), "ModalFlexibility: made without the derivative");
    return d_.P * dw_.cwiseProduct(d_.P.transpose() * z);  // ∂H/∂Ω = X diag(dw/dΩ) Xᵀ
  }

 private:
  const DampedModalExpansion& d_;
  const Eigen::VectorXcd* load_;  // Xᵀ q_k, or null
  Eigen::VectorXcd w_, dw_;
};

class StateSpaceFlexibility final : public ModalFlexibility {
 public:
  StateSpaceFlexibility(ModalProjection projection, std::shared_ptr<DampedModalExpansion> d)
      : ModalFlexibility(std::move(projection)), d_(std::move(d)) {
    const Eigen::MatrixXd& Psi = this->projection().Psi;
    d_->P = Psi.cast<Complex>() * d_->X;
    const int nr = d_->rigid + d_->real, np = static_cast<int>(d_->X.cols() - nr) / 2;
    d_->Preal = d_->P.leftCols(nr).real();
    d_->U.resize(Psi.rows(), np);
    d_->V.resize(Psi.rows(), np);
    for (int g = 0; g < np; ++g) {
      d_->U.col(g) = d_->P.col(nr + 2 * g).real();
      d_->V.col(g) = d_->P.col(nr + 2 * g).imag();
    }
    for (const auto& [k, q] : this->projection().loads) d_->load[k] = d_->X.transpose() * q;
  }
  ModalFlexibilityMethod method() const override { return ModalFlexibilityMethod::kStateSpace; }

 protected:
  std::unique_ptr<const Harmonic> dynamic(int k, double omega, bool derivative) const override {
    const auto it = d_->load.find(k);
    return std::make_unique<StateSpaceHarmonic>(*d_, it == d_->load.end() ? nullptr : &it->second,
                                                k, omega, derivative);
  }

 private:
  std::shared_ptr<DampedModalExpansion> d_;
};

}  // namespace

Eigen::VectorXd elastic_modes(const Eigen::VectorXd& omega2) {
  if (omega2.size() == 0) return Eigen::VectorXd();
  const double max_w2 = omega2.maxCoeff();
  return (omega2.array() > kRigidModeRatio * max_w2).cast<double>().matrix();
}

ModalFlexibility::ModalFlexibility(ModalProjection projection)
    : projection_(std::move(projection)), elastic_(elastic_modes(projection_.omega2)) {
  const Eigen::Index nm = projection_.omega2.size();
  require(projection_.Psi.cols() == nm, "ModalFlexibility.Psi",
          std::to_string(projection_.Psi.cols()) + " columns", "one per mode");
  for (const auto& [k, q] : projection_.loads) {
    require(k >= 0 && q.size() == nm, "ModalFlexibility.loads[" + std::to_string(k) + "]",
            "size " + std::to_string(q.size()), "k >= 0, one entry per mode");
  }
}

const Eigen::VectorXcd* ModalFlexibility::load(int k) const {
  const auto it = projection_.loads.find(k);
  return it == projection_.loads.end() ? nullptr : &it->second;
}

std::unique_ptr<const ModalFlexibility::Harmonic> ModalFlexibility::at(int k, double omega,
                                                                       bool derivative) const {
  STICKSLIP_VERIFY(k >= 0, "ModalFlexibility::at: k >= 0");
  if (k > 0) return dynamic(k, omega, derivative);
  const Eigen::Index nm = projection_.omega2.size();
  Eigen::VectorXcd h(nm);
  for (Eigen::Index r = 0; r < nm; ++r) {
    h[r] = elastic_[r] > 0 ? 1.0 / projection_.omega2[r] : 0.0;
  }
  return std::make_unique<DiagonalHarmonic>(
      projection_.Psi, load(0), std::move(h),
      derivative ? Eigen::VectorXcd(Eigen::VectorXcd::Zero(nm)) : Eigen::VectorXcd());
}

std::unique_ptr<const ModalFlexibility> diagonal_modal_flexibility(ModalProjection projection,
                                                                   Eigen::VectorXd c) {
  return std::make_unique<DiagonalFlexibility>(std::move(projection), std::move(c));
}

std::unique_ptr<const ModalFlexibility> impedance_lu_modal_flexibility(ModalProjection projection,
                                                                       Eigen::MatrixXd C_m) {
  return std::make_unique<ImpedanceLuFlexibility>(std::move(projection), std::move(C_m));
}

std::unique_ptr<const ModalFlexibility> state_space_modal_flexibility(ModalProjection projection,
                                                                      const Eigen::MatrixXd& C_m,
                                                                      std::string& failure) {
  const Eigen::VectorXd elastic = elastic_modes(projection.omega2);
  std::shared_ptr<DampedModalExpansion> d =
      damped_modal_expansion(projection.omega2, C_m, elastic, failure);
  if (!d) return nullptr;
  return std::make_unique<StateSpaceFlexibility>(std::move(projection), std::move(d));
}

std::unique_ptr<const ModalFlexibility> make_modal_flexibility(ModalProjection projection,
                                                               const Eigen::VectorXd& c,
                                                               const Eigen::MatrixXd& C_m,
                                                               DampingMatrixMethod method,
                                                               std::string& note) {
  note.clear();
  if (C_m.size() == 0) return diagonal_modal_flexibility(std::move(projection), c);
  if (method == DampingMatrixMethod::kStateSpace) {
    std::unique_ptr<const ModalFlexibility> state_space =
        state_space_modal_flexibility(projection, C_m, note);
    if (state_space) return state_space;
  }
  return impedance_lu_modal_flexibility(std::move(projection), C_m);
}

}  // namespace stickslip
