// The modal flexibility of the linear model of the condensed harmonic balance
// (hbm/harmonic_balance.h), per harmonic k and frequency Ω:
//   H_0     = diag(1/ω_r²) over the elastic modes (0 on rigid-body modes; undamped),
//   H_k(Ω) = (diag(ω_r²) − (kΩ)² I + i kΩ C_m)⁻¹   (k ≥ 1; nm x nm, complex symmetric),
//   dH_k/dΩ = −H_k (−2k²Ω I + i k C_m) H_k,
// with the products the harmonic balance needs on the contact rows: the contact modes Ψ = BΦ
// (nu x nm) and the modal loads q_k = Φᵀ F_k are fixed at construction. One interface, three
// implementations, chosen once when the system is built (make_modal_flexibility):
//   diagonal      C_m = diag(c_r) (Rayleigh or modal-ratio damping): h_r = 1/(ω_r² − κ² + iκ c_r),
//                 O(nm) per (k, Ω) and a weighted Gram product for G_k;
//   state space   dense C_m through its damped complex modes, computed once (damped_modes.h):
//                 H_k = X diag(w(kΩ)) Xᵀ, about twice the diagonal's work per (k, Ω);
//   impedance LU  dense C_m through a complex LU of Z_k = H_k⁻¹ per (k, Ω), O(nm³).
// Where all three apply (a diagonal C_m) they agree to round-off. The held rigid-body modes'
// shifted static flexibility is not here (a property of the contacts, harmonic_balance.h).
#pragma once

#include <map>
#include <memory>
#include <string>

#include <Eigen/Core>

namespace stickslip {

// Rigid-body modes: ω_r² ≤ kRigidModeRatio · max ω². Mass-normalised rigid modes of an assembled
// body come out of the eigen-solver with |ω²| at the round-off of K's largest eigenvalue
// (≈ 1e-16 · max ω² times the conditioning of the shift-invert solves, observed up to 1e-14);
// the lowest elastic mode of a real structure is far above 1e-12 max ω² (a frequency ratio
// of 1e-6).
inline constexpr double kRigidModeRatio = 1e-12;
// 1 for the elastic modes, 0 for the rigid-body ones (size nm).
Eigen::VectorXd elastic_modes(const Eigen::VectorXd& omega2);

// How H_k is applied with a dense modal damping matrix (harmonic_balance.h). kStateSpace falls
// back to kImpedanceLu (with a note) when the damped modes are (nearly) defective.
enum class DampingMatrixMethod { kStateSpace, kImpedanceLu };
enum class ModalFlexibilityMethod { kDiagonal, kStateSpace, kImpedanceLu };

// What every implementation sees: ω² (nm, ≥ 0), Ψ (nu x nm) and q_k = Φᵀ F_k (k ≥ 0 -> nm).
struct ModalProjection {
  Eigen::VectorXd omega2{};
  Eigen::MatrixXd Psi{};
  std::map<int, Eigen::VectorXcd> loads{};
};

class ModalFlexibility {
 public:
  // H_k at one (k, Ω), evaluated once. It refers to its ModalFlexibility, which must outlive it.
  class Harmonic {
   public:
    virtual ~Harmonic() = default;
    // H_k X for a complex nm x c X.
    virtual Eigen::MatrixXcd times(const Eigen::MatrixXcd& X) const = 0;
    // The receptance G_k = Ψ H_k Ψᵀ (nu x nu, symmetric; a travelling wave's complex modes give
    // Ψ_k H_k Ψ_kᴴ, not symmetric: hbm/travelling_wave.h): its real and imaginary parts.
    virtual void receptance(Eigen::MatrixXd& real, Eigen::MatrixXd& imag) const = 0;
    // u_lin,k = Ψ H_k q_k (nu; zero without a load at k).
    virtual Eigen::VectorXcd load_response() const = 0;
    // Only when made with the derivative (k = 0: zero): du_lin,k/dΩ = Ψ (dH_k/dΩ) q_k and
    // (dG_k/dΩ) z = Ψ (dH_k/dΩ) Ψᵀ z for a complex z (nu).
    virtual Eigen::VectorXcd load_response_derivative() const = 0;
    virtual Eigen::VectorXcd receptance_derivative_times(const Eigen::VectorXcd& z) const = 0;
  };

  explicit ModalFlexibility(ModalProjection projection);
  virtual ~ModalFlexibility() = default;
  ModalFlexibility(const ModalFlexibility&) = delete;
  ModalFlexibility& operator=(const ModalFlexibility&) = delete;

  // k ≥ 0, Ω ≥ 0 (k ≥ 1 with Ω = 0 and a rigid-body mode: infinite entries). derivative: the
  // dH_k/dΩ products are prepared as well.
  std::unique_ptr<const Harmonic> at(int k, double omega, bool derivative) const;
  virtual ModalFlexibilityMethod method() const = 0;
  const ModalProjection& projection() const { return projection_; }
  const Eigen::VectorXd& elastic() const { return elastic_; }  // elastic_modes(ω²)

 protected:
  virtual std::unique_ptr<const Harmonic> dynamic(int k, double omega, bool derivative) const = 0;
  // The load q_k, or null.
  const Eigen::VectorXcd* load(int k) const;

 private:
  ModalProjection projection_;
  Eigen::VectorXd elastic_;
};

// The three implementations. c: c_r (nm, 1/s, ≥ 0); C_m: nm x nm, symmetric PSD (validated by
// the caller: harmonic_balance.h's validate(LinearModel)).
std::unique_ptr<const ModalFlexibility> diagonal_modal_flexibility(ModalProjection projection,
                                                                   Eigen::VectorXd c);
std::unique_ptr<const ModalFlexibility> impedance_lu_modal_flexibility(ModalProjection projection,
                                                                       Eigen::MatrixXd C_m);
// Null with `failure` saying why when the damped modes cannot be used (damped_modes.h).
std::unique_ptr<const ModalFlexibility> state_space_modal_flexibility(ModalProjection projection,
                                                                      const Eigen::MatrixXd& C_m,
                                                                      std::string& failure);

// The choice: diagonal when C_m is empty (c then given), else the state space when `method` asks
// for it and it is usable (`note` says why not when it is not), else the impedance LU.
std::unique_ptr<const ModalFlexibility> make_modal_flexibility(ModalProjection projection,
                                                               const Eigen::VectorXd& c,
                                                               const Eigen::MatrixXd& C_m,
                                                               DampingMatrixMethod method,
                                                               std::string& note);

}  // namespace stickslip
