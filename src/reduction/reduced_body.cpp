#include "reduction/reduced_body.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "core/errors.h"
#include "core/types.h"

namespace stickslip {
namespace {

std::string to_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace

void validate(const ReducedDampingOptions& options) {
  require(std::isfinite(options.alpha) && options.alpha >= 0.0, "ReducedDampingOptions::alpha",
          to_text(options.alpha), "alpha >= 0");
  require(std::isfinite(options.beta) && options.beta >= 0.0, "ReducedDampingOptions::beta",
          to_text(options.beta), "beta >= 0");
  require(std::isfinite(options.modal_damping_ratio) && options.modal_damping_ratio >= 0.0,
          "ReducedDampingOptions::modal_damping_ratio", to_text(options.modal_damping_ratio),
          "modal_damping_ratio >= 0");
}

void assign_node_ids(ReducedBody& body, const std::vector<int>& node_ids) {
  for (ReducedDof& d : body.dofs) {
    if (d.kind != ReducedDof::Kind::kPhysical || d.node_index < 0) continue;
    if (d.node_index >= static_cast<int>(node_ids.size())) {
      throw InvalidInput("assign_node_ids: node index " + std::to_string(d.node_index) +
                         " is outside the " + std::to_string(node_ids.size()) + " node ids");
    }
    d.node_id = node_ids[static_cast<size_t>(d.node_index)];
  }
}

Eigen::MatrixXd reduced_damping(const ReducedBody& body, const ReducedDampingOptions& options) {
  validate(options);
  const int n = body.size();
  if (body.K.rows() != n || body.K.cols() != n || body.M.rows() != n || body.M.cols() != n) {
    throw InvalidInput("reduced_damping: K and M must be " + std::to_string(n) + " x " +
                       std::to_string(n) + " (one row per reduced DOF)");
  }
  Eigen::MatrixXd C = options.alpha * body.M + options.beta * body.K;
  if (options.modal_damping_ratio > 0.0) {
    for (int j = 0; j < n; ++j) {
      const ReducedDof& d = body.dofs[j];
      if (d.kind != ReducedDof::Kind::kModal) continue;
      C(j, j) += 2.0 * options.modal_damping_ratio * hz_to_rad_s(d.frequency_hz) * body.M(j, j);
    }
  }
  return C;
}

}  // namespace stickslip
