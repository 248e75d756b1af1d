// Memoryless one-component springs (m = 1), u = R (x_A − x_B) along the element direction:
//   UnilateralSpring  f = max(0, N0 + k (u − g0))   (gap g0, < 0 an interference, and/or N0 ≥ 0;
//                     u is the approach, so f > 0 pushes B away from A)
//   CubicSpring       f = k1 u + k3 u³              (Duffing; k3 < 0 softening)
#pragma once

#include "contact/nonlinear_element.h"

namespace stickslip {

struct UnilateralSpringParameters {
  double k = 0.0;        // N/m (> 0)
  double gap = 0.0;      // g0, m (finite; < 0: initial interference)
  double preload = 0.0;  // N0, N (≥ 0)
};
void validate(const UnilateralSpringParameters& parameters);

class UnilateralSpring final : public NonlinearElement {
 public:
  explicit UnilateralSpring(UnilateralSpringParameters parameters);
  int dimension() const override { return 1; }
  std::string name() const override { return "unilateral_spring"; }
  CycleStatistics march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp, Eigen::MatrixXd& f,
                        Eigen::MatrixXd* df_dp) const override;
  const UnilateralSpringParameters& parameters() const { return parameters_; }

 private:
  UnilateralSpringParameters parameters_;
};

struct CubicSpringParameters {
  double k1 = 0.0;  // linear part, N/m
  double k3 = 0.0;  // cubic coefficient, N/m³
};
void validate(const CubicSpringParameters& parameters);

class CubicSpring final : public NonlinearElement {
 public:
  explicit CubicSpring(CubicSpringParameters parameters);
  int dimension() const override { return 1; }
  std::string name() const override { return "cubic_spring"; }
  CycleStatistics march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp, Eigen::MatrixXd& f,
                        Eigen::MatrixXd* df_dp) const override;

 private:
  CubicSpringParameters parameters_;
};

}  // namespace stickslip
