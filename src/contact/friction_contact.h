// Friction elements (docs/conventions.md contact law). Both start from the virgin state (τ = 0 at
// u_t = 0) and march the sampled period until τ repeats (see nonlinear_element.h);
// FrictionContact3D closes a 2D partial-slip cycle that has not repeated after two periods by
// Newton on the start state τ_s of P(τ_s) = τ_s (unique when the cycle slips; the same cycle
// marching tends to).
//
// FrictionContact3D, m = 3, u = (u_t1, u_t2, w), f = (τ1, τ2, N):
//   normal   N = max(0, N0 + kn (w − g0))        (preload N0 ≥ 0 and/or initial gap g0: > 0 open,
//                                                 < 0 an initial interference)
//   tangent  τ_pred = τ_prev + kt (u_t − u_t,prev)                 (2D elastic predictor)
//            |τ_pred| ≤ μN: stick, τ = τ_pred; else slip, τ = μN τ_pred/|τ_pred|
//            (circular Coulomb limit, the radial return); N = 0: separation, τ = 0.
// Jenkins1D, m = 1: the same tangential law along one direction with a fixed normal load
//   N (limit μN): τ = clamp(τ_prev + kt (u − u_prev), −μN, μN).
#pragma once

#include "contact/nonlinear_element.h"

namespace stickslip {

struct FrictionContactParameters {
  double kt = 0.0;              // tangential contact stiffness, both directions, N/m (> 0)
  double kn = 0.0;              // normal contact stiffness, N/m (> 0)
  double mu = 0.0;              // friction coefficient (≥ 0)
  double normal_preload = 0.0;  // N0, N (≥ 0; compression positive)
  double gap = 0.0;             // g0, m (any finite value; < 0: initial interference)
};
void validate(const FrictionContactParameters& parameters);

class FrictionContact3D final : public NonlinearElement {
 public:
  explicit FrictionContact3D(FrictionContactParameters parameters, MarchOptions march = {});
  int dimension() const override { return 3; }
  std::string name() const override { return "friction_contact_3d"; }
  CycleStatistics march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp, Eigen::MatrixXd& f,
                        Eigen::MatrixXd* df_dp) const override;
  const FrictionContactParameters& parameters() const { return parameters_; }

 private:
  FrictionContactParameters parameters_;
  MarchOptions march_;
};

struct JenkinsParameters {
  double kt = 0.0;           // tangential stiffness, N/m (> 0)
  double mu = 0.0;           // friction coefficient (≥ 0)
  double normal_load = 0.0;  // fixed N, N (≥ 0); slip limit μN
};
void validate(const JenkinsParameters& parameters);

class Jenkins1D final : public NonlinearElement {
 public:
  explicit Jenkins1D(JenkinsParameters parameters, MarchOptions march = {});
  int dimension() const override { return 1; }
  std::string name() const override { return "jenkins_1d"; }
  CycleStatistics march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp, Eigen::MatrixXd& f,
                        Eigen::MatrixXd* df_dp) const override;
  const JenkinsParameters& parameters() const { return parameters_; }

 private:
  JenkinsParameters parameters_;
  MarchOptions march_;
};

}  // namespace stickslip
