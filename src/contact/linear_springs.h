// Independent linear springs on the m local rows of a contact point, f_d = k_d u_d (k in N/m,
// u in m, f in N), e.g. (kt, kt, kn) on (t1, t2, n): a stuck friction contact, or the 3D form of
// the case file's law `linear`. Elastic: no memory, no dissipation; march() returns stick
// fraction 1 after one period, and the exact derivative ∂f_d(t_j)/∂p = k_d ∂u_d(t_j)/∂p (row
// j·m + d of the NonlinearElement layout).
#pragma once

#include <Eigen/Core>

#include "contact/nonlinear_element.h"

namespace stickslip {

class LinearSprings final : public NonlinearElement {
 public:
  // k: one stiffness per local row (m = k.size() ≥ 1), each finite and ≥ 0; InvalidInput else.
  explicit LinearSprings(Eigen::VectorXd k);
  int dimension() const override { return static_cast<int>(k_.size()); }
  std::string name() const override { return "linear_springs"; }
  CycleStatistics march(const Eigen::MatrixXd& u, const Eigen::MatrixXd* du_dp, Eigen::MatrixXd& f,
                        Eigen::MatrixXd* df_dp) const override;
  const Eigen::VectorXd& stiffness() const { return k_; }

 private:
  Eigen::VectorXd k_;
};

ElementPtr make_linear_springs(const Eigen::VectorXd& k);

}  // namespace stickslip
