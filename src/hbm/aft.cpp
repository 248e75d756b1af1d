#include "hbm/aft.h"

#include "core/errors.h"

namespace stickslip {

namespace {

Eigen::MatrixXd build_sample_derivative(const FourierBasis& basis, int m) {
  const int n = basis.time_samples();
  const int nc = basis.coefficient_count();
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(m * n, m * nc);
  for (int j = 0; j < n; ++j) {
    for (int c = 0; c < m; ++c) d.block(j * m + c, c * nc, 1, nc) = basis.synthesis().row(j);
  }
  return d;
}

}  // namespace

Aft::Aft(FourierBasis basis) : basis_(std::move(basis)) {
  for (int m = 1; m <= 3; ++m) sample_derivatives_.push_back(build_sample_derivative(basis_, m));
}

const Eigen::MatrixXd& Aft::sample_derivative(int m) const {
  STICKSLIP_VERIFY(m >= 1 && m <= static_cast<int>(sample_derivatives_.size()),
                   "Aft: element dimension must be 1..3");
  return sample_derivatives_[m - 1];
}

CycleStatistics Aft::evaluate(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                              const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                              Eigen::MatrixXd* jacobian, AftSamples* samples) const {
  const int m = element.dimension();
  const int n = basis_.time_samples();
  const int nc = basis_.coefficient_count();
  STICKSLIP_VERIFY(coefficients.size() == m * nc, "Aft: coefficients must have m*nc entries");
  STICKSLIP_VERIFY(offset.size() == 0 || offset.size() == m, "Aft: offset must be empty or m");

  // u (m x N): row d = (E c_d)ᵀ + u0_d.
  const Eigen::Map<const Eigen::MatrixXd> c(coefficients.data(), nc, m);  // column d = c_d
  Eigen::MatrixXd u = (basis_.synthesis() * c).transpose();
  if (offset.size() == m) u.colwise() += offset;

  Eigen::MatrixXd f;
  Eigen::MatrixXd df_dc;
  const CycleStatistics stats = jacobian ? element.march(u, &sample_derivative(m), f, &df_dc)
                                         : element.march(u, nullptr, f, nullptr);

  forces.resize(m * nc);
  Eigen::Map<Eigen::MatrixXd>(forces.data(), nc, m) = basis_.analysis() * f.transpose();
  if (jacobian) {
    jacobian->resize(m * nc, m * nc);
    const int np = m * nc;
    for (int d = 0; d < m; ++d) {
      // Rows j·m + d of df_dc (j = 0..N−1): an N x np view with row stride m.
      const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>>
          rows(df_dc.data() + d, n, np, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>(m * n, m));
      jacobian->middleRows(d * nc, nc).noalias() = basis_.analysis() * rows;
    }
  }
  if (samples) {
    samples->u = std::move(u);
    samples->f = std::move(f);
  }
  return stats;
}

}  // namespace stickslip
