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

Aft::Aft(FourierBasis basis, AftMethod method)
    : basis_(std::move(basis)), method_(method), analysis_t_(basis_.analysis().transpose()) {
  for (int m = 1; m <= 3; ++m) sample_derivatives_.push_back(build_sample_derivative(basis_, m));
}

const Eigen::MatrixXd& Aft::sample_derivative(int m) const {
  STICKSLIP_VERIFY(m >= 1 && m <= static_cast<int>(sample_derivatives_.size()),
                   "Aft: element dimension must be 1..3");
  return sample_derivatives_[m - 1];
}

namespace {

// Per-thread scratch space of Aft::evaluate: the sampled cycle and its derivative keep their sizes
// from call to call, so a sweep allocates them once per thread instead of once per pair and call.
struct AftWorkspace {
  Eigen::MatrixXd u, f, df_dc;
  Eigen::MatrixXd ft, rows;  // fᵀ (N x m); rows j·m + d of df_dc for one d (N x m·nc)
};

AftWorkspace& workspace() {
  thread_local AftWorkspace w;
  return w;
}

}  // namespace

CycleStatistics Aft::evaluate(const NonlinearElement& element, const Eigen::VectorXd& coefficients,
                              const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                              Eigen::MatrixXd* jacobian, AftSamples* samples,
                              AftWarmStart* warm) const {
  if (method_ != AftMethod::kSampled) {
    CycleStatistics stats;
    if (evaluate_events(element, coefficients, offset, forces, jacobian, samples, warm, stats))
      return stats;
    stats = evaluate_sampled(element, coefficients, offset, forces, jacobian, samples);
    stats.aft_fallback = true;
    return stats;
  }
  return evaluate_sampled(element, coefficients, offset, forces, jacobian, samples);
}

CycleStatistics Aft::evaluate_sampled(const NonlinearElement& element,
                                      const Eigen::VectorXd& coefficients,
                                      const Eigen::VectorXd& offset, Eigen::VectorXd& forces,
                                      Eigen::MatrixXd* jacobian, AftSamples* samples) const {
  const int m = element.dimension();
  const int n = basis_.time_samples();
  const int nc = basis_.coefficient_count();
  STICKSLIP_VERIFY(coefficients.size() == m * nc, "Aft: coefficients must have m*nc entries");
  STICKSLIP_VERIFY(offset.size() == 0 || offset.size() == m, "Aft: offset must be empty or m");
  AftWorkspace& w = workspace();

  // u (m x N): row d = (E c_d)ᵀ + u0_d.
  const Eigen::Map<const Eigen::MatrixXd> c(coefficients.data(), nc, m);  // column d = c_d
  Eigen::MatrixXd& u = w.u;
  u.resize(m, n);
  u.noalias() = c.transpose().lazyProduct(basis_.synthesis().transpose());
  if (offset.size() == m) u.colwise() += offset;

  Eigen::MatrixXd& f = w.f;
  const CycleStatistics stats = jacobian ? element.march(u, &sample_derivative(m), f, &w.df_dc)
                                         : element.march(u, nullptr, f, nullptr);

  // F (nc x m) = P fᵀ and ∂F/∂c = P ∂f/∂c per component, as contiguous dot products of the
  // columns of Pᵀ with the samples (gathered per component).
  forces.resize(m * nc);
  w.ft = f.transpose();
  for (int d = 0; d < m; ++d) {
    for (int i = 0; i < nc; ++i) forces[d * nc + i] = analysis_t_.col(i).dot(w.ft.col(d));
  }
  if (jacobian) {
    const int np = m * nc;
    jacobian->resize(np, np);
    const Eigen::MatrixXd& df = w.df_dc;
    for (int d = 0; d < m; ++d) {
      // Rows j·m + d of df_dc (j = 0..N−1): an N x np view with row stride m.
      w.rows = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>>(
          df.data() + d, n, np, Eigen::Stride<Eigen::Dynamic, Eigen::Dynamic>(df.rows(), m));
      for (int q = 0; q < np; ++q) {
        for (int i = 0; i < nc; ++i)
          (*jacobian)(d * nc + i, q) = analysis_t_.col(i).dot(w.rows.col(q));
      }
    }
  }
  if (samples) {
    samples->u = u;
    samples->f = f;
  }
  return stats;
}

}  // namespace stickslip
