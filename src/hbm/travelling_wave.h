// Travelling-wave response of a tuned cyclic structure seen from its sector 0 (issue 13, item 3;
// docs/cyclic.md): the linear model per harmonic that the condensed harmonic balance
// (hbm/harmonic_balance.h) takes in place of its one real LinearModel for the dynamic harmonics.
//
// N identical sectors; sector j is sector 0 rotated by R^j (R: `rotation`, 3 x 3, the map of
// sector j to sector j + 1). Engine order EO: the force on sector j at harmonic k is sector 0's
// rotated by R^j with the phase e^{iσ_k j}, σ_k = 2π k EO / N, and so is the response (tuned
// system, travelling-wave steady state). Harmonic k therefore lives in the nodal diameter
// h' = k·EO mod N, whose sector model (K_h', M_h', Hermitian; for h' > N/2 the conjugate of
// diameter N − h') gives its complex modes Φ_k (ndof x nm_k, Φ_kᴴ M Φ_k = I):
//   D_k⁻¹ = Φ_k diag(h_k) Φ_kᴴ,  h_{k,r}(Ω) = 1 / (ω_r² − (kΩ)² + i kΩ c_r),
// the i of the time harmonic not conjugated. Harmonic 0 is diameter 0: real, the LinearModel.
//
// Contact pairs: a pair whose node B sits in sector s = ContactPair::b_sector (−1, 0 or +1) sees
// B's displacement R^s x_B e^{iσ_k s} at harmonic k, x_B its sector-0 DOFs, so its map is
//   u_p = R_p (x_A − e^{iσ_k s} R^s x_B)                         (complex for k ≥ 1, real for 0)
// and its force goes back to sector 0 through the adjoint map, −B_kᴴ f_k: on B, the force of the
// pair of sector −s (the same pair, rotated back, R^{−s} = (R^s)ᵀ, with the conjugate phase).
// With Ψ_k = B_k Φ_k the receptance is G_k = Ψ_k diag(h_k) Ψ_kᴴ: complex and not symmetric.
// The AFT sees the real signals u_p(t) and is unchanged.
#pragma once

#include <complex>
#include <map>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "hbm/modal_flexibility.h"

namespace stickslip {

struct ContactPair;

// The complex modal model of one dynamic harmonic.
struct ComplexModalModel {
  Eigen::VectorXd omega2{};         // ω_r², (rad/s)², ≥ 0 (0: rigid-body mode), size nm
  Eigen::MatrixXcd Phi{};           // ndof x nm, Φᴴ M Φ = I (rows: the LinearModel's DOFs)
  Eigen::VectorXd modal_damping{};  // c_r, 1/s, ≥ 0, size nm
};

// All modes of a dense Hermitian pair (K, M), M positive definite; c_r = α + β ω_r²; ω² at or
// below kRigidModeRatio · max ω² (rigid-body modes) exactly 0.
// InvalidInput when M is not positive definite.
ComplexModalModel complex_modal_model_from_matrices(const Eigen::MatrixXcd& K,
                                                    const Eigen::MatrixXcd& M, double alpha,
                                                    double beta);

struct TravellingWave {
  int sectors = 0;                                         // N ≥ 2
  int engine_order = 0;                                    // EO ≥ 0
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // R (orthogonal, det 1)
  std::map<int, ComplexModalModel> harmonics{};  // k ≥ 1 -> model of diameter k·EO mod N
  // σ_k = 2π k EO / N (rad).
  double phase(int k) const;
};

// The nodal diameter 0..N/2 harmonic k lives in under engine order EO, and whether its model is
// the conjugate of that diameter's (k·EO mod N > N/2).
int travelling_wave_nodal_diameter(int k, int engine_order, int sectors, bool* conjugate);

// The modal flexibility of a travelling wave: harmonic 0 from `projection` (the real diameter-0
// model, as every ModalFlexibility), harmonic k ≥ 1 from the wave's model of k with the complex
// contact modes Ψ_k = B_k Φ_k and loads q_k = Φ_kᴴ F_k. Its Harmonic's receptance is Ψ_k diag(h_k)
// Ψ_kᴴ (not symmetric). `pairs`/`pair_rows` give B_k; `loads`: k ≥ 1 -> F_k (ndof).
class TravellingWaveFlexibility final : public ModalFlexibility {
 public:
  TravellingWaveFlexibility(ModalProjection projection, const TravellingWave& wave,
                            const std::vector<ContactPair>& pairs,
                            const std::vector<int>& pair_rows, int rows,
                            const std::map<int, Eigen::VectorXcd>& loads);
  ModalFlexibilityMethod method() const override { return ModalFlexibilityMethod::kDiagonal; }
  // Master DOFs of harmonic k ≥ 1: x_k = Φ_k diag(h_k) (q_k − Ψ_kᴴ f_k), f_k the complex contact
  // forces (nu).
  Eigen::VectorXcd master_response(int k, double omega,
                                   const Eigen::VectorXcd& contact_force) const;
  // Ψ_k diag(1/ω²) q_k over the elastic modes: the quasi-static contact response to the load of
  // harmonic k (a scale).
  Eigen::VectorXcd quasi_static_response(int k) const;
  const Eigen::MatrixXcd& contact_modes(int k) const { return of(k).Psi; }

 protected:
  std::unique_ptr<const Harmonic> dynamic(int k, double omega, bool derivative) const override;

 private:
  struct Model {
    Eigen::VectorXd omega2, c;
    Eigen::MatrixXcd Phi, Psi;  // ndof x nm, nu x nm
    Eigen::VectorXcd load;      // q_k, empty without a load
  };
  const Model& of(int k) const;
  std::map<int, Model> models_;
};

// B_k Φ for the pairs (rows stacked as the harmonic balance's contact rows): sector-0 nodes with
// the frame, neighbour nodes with frame R^s and the phase e^{iσ s} (σ = wave.phase(k), k ≥ 0).
Eigen::MatrixXcd travelling_wave_contact_modes(const std::vector<ContactPair>& pairs,
                                               const std::vector<int>& pair_rows, int rows,
                                               const Eigen::MatrixXcd& Phi,
                                               const TravellingWave& wave, int k);
// R^s for s = −1, 0, 1 (the frame of a neighbour node: R_p R^s).
Eigen::Matrix3d sector_rotation(const Eigen::Matrix3d& rotation, int s);

}  // namespace stickslip
