#include "fe/springs.h"

#include <cmath>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/format.h"

namespace stickslip {

namespace {
constexpr double kOrthonormalTolerance = 1e-9;  // frames built in double precision

void check(const NodePairSpring& s, size_t i, int num_nodes) {
  const std::string name = "springs[" + std::to_string(i) + "]";
  auto in_range = [&](int n) { return n >= 0 && n < num_nodes; };
  require(in_range(s.node_a), name + ".node_a", std::to_string(s.node_a),
          "a node index in [0, " + std::to_string(num_nodes) + ")");
  require(s.node_b == -1 || in_range(s.node_b), name + ".node_b", std::to_string(s.node_b),
          "-1 (ground) or a node index in [0, " + std::to_string(num_nodes) + ")");
  require(s.node_b != s.node_a, name + ".node_b", std::to_string(s.node_b), "node_b != node_a");
  const double err = (s.frame * s.frame.transpose() - Eigen::Matrix3d::Identity()).norm();
  require(std::isfinite(err) && err <= kOrthonormalTolerance, name + ".frame",
          "|R R^T - I| = " + format_number(err, 3), "rows t1, t2, n unit and orthonormal");
  require(s.k_t1 >= 0.0, name + ".k_t1", format_number(s.k_t1), ">= 0");
  require(s.k_t2 >= 0.0, name + ".k_t2", format_number(s.k_t2), ">= 0");
  require(s.k_n >= 0.0, name + ".k_n", format_number(s.k_n), ">= 0");
}

Eigen::Matrix3d local_to_global(const NodePairSpring& s) {
  return s.frame.transpose() * Eigen::Vector3d(s.k_t1, s.k_t2, s.k_n).asDiagonal() * s.frame;
}
}  // namespace

Eigen::Matrix<double, 6, 6> spring_stiffness(const NodePairSpring& spring) {
  const Eigen::Matrix3d S = local_to_global(spring);
  Eigen::Matrix<double, 6, 6> K;
  K << S, -S, -S, S;
  return K;
}

void add_springs(std::span<const NodePairSpring> springs, SparseMatrix& K) {
  if (K.rows() != K.cols() || K.rows() % kDofsPerNode != 0) {
    throw InvalidInput("add_springs: K is " + std::to_string(K.rows()) + " x " +
                       std::to_string(K.cols()) + ", expected square 3 num_nodes");
  }
  const int num_nodes = static_cast<int>(K.rows() / kDofsPerNode);
  std::vector<Triplet> t;
  t.reserve(springs.size() * 36);
  for (size_t i = 0; i < springs.size(); ++i) {
    const NodePairSpring& s = springs[i];
    check(s, i, num_nodes);
    const Eigen::Matrix3d S = local_to_global(s);
    const int a = s.node_a, b = s.node_b;
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) {
        t.emplace_back(dof_of(a, r), dof_of(a, c), S(r, c));
        if (b >= 0) {
          t.emplace_back(dof_of(b, r), dof_of(b, c), S(r, c));
          t.emplace_back(dof_of(a, r), dof_of(b, c), -S(r, c));
          t.emplace_back(dof_of(b, r), dof_of(a, c), -S(r, c));
        }
      }
    }
  }
  SparseMatrix Ks(K.rows(), K.cols());
  Ks.setFromTriplets(t.begin(), t.end());
  K += Ks;
}

}  // namespace stickslip
