#include "fe/dof_map.h"

#include <string>

#include "core/errors.h"

namespace stickslip {

namespace {
void check_size(const char* what, Eigen::Index got, int expected) {
  if (got != expected) {
    throw InvalidInput(std::string("DofMap::") + what + ": size " + std::to_string(got) +
                       ", expected " + std::to_string(expected));
  }
}
}  // namespace

DofMap::DofMap(int num_dofs, std::span<const int> constrained) {
  require(num_dofs >= 0, "DofMap num_dofs", std::to_string(num_dofs), ">= 0");
  free_index_.assign(num_dofs, 0);
  for (int d : constrained) {
    if (d < 0 || d >= num_dofs) {
      throw InvalidInput("DofMap: constrained DOF " + std::to_string(d) + " out of range [0, " +
                         std::to_string(num_dofs) + ")");
    }
    free_index_[d] = -1;
  }
  for (int d = 0; d < num_dofs; ++d) {
    if (free_index_[d] == 0) {
      free_index_[d] = static_cast<int>(full_dof_.size());
      full_dof_.push_back(d);
    }
  }
}

DofMap DofMap::from_nodes(int num_nodes, std::span<const int> nodes,
                          std::array<bool, 3> directions) {
  std::vector<int> dofs;
  for (int n : nodes) {
    if (n < 0 || n >= num_nodes) {
      throw InvalidInput("DofMap: constrained node index " + std::to_string(n) +
                         " out of range [0, " + std::to_string(num_nodes) + ")");
    }
    for (int d = 0; d < 3; ++d) {
      if (directions[d]) dofs.push_back(dof_of(n, d));
    }
  }
  return DofMap(kDofsPerNode * num_nodes, dofs);
}

SparseMatrix DofMap::restrict(const SparseMatrix& A) const {
  check_size("restrict(matrix) rows", A.rows(), num_dofs());
  check_size("restrict(matrix) cols", A.cols(), num_dofs());
  const int nf = num_free();
  // Count, then fill a compressed matrix directly (row order within a column is preserved
  // because free indices increase with full DOFs).
  std::vector<int> outer(nf + 1, 0);
  for (int f = 0; f < nf; ++f) {
    int count = 0;
    for (SparseMatrix::InnerIterator it(A, full_dof_[f]); it; ++it) {
      if (free_index_[it.row()] >= 0) ++count;
    }
    outer[f + 1] = outer[f] + count;
  }
  SparseMatrix R(nf, nf);
  R.resizeNonZeros(outer[nf]);
  std::copy(outer.begin(), outer.end(), R.outerIndexPtr());
  int p = 0;
  for (int f = 0; f < nf; ++f) {
    for (SparseMatrix::InnerIterator it(A, full_dof_[f]); it; ++it) {
      const int r = free_index_[it.row()];
      if (r >= 0) {
        R.innerIndexPtr()[p] = r;
        R.valuePtr()[p] = it.value();
        ++p;
      }
    }
  }
  return R;
}

namespace {
template <class V>
V restrict_vector(const std::vector<int>& full_dof, const V& x) {
  V y(full_dof.size());
  for (size_t f = 0; f < full_dof.size(); ++f) y(f) = x(full_dof[f]);
  return y;
}
template <class V>
V expand_vector(const std::vector<int>& full_dof, int n, const V& x) {
  V y = V::Zero(n);
  for (size_t f = 0; f < full_dof.size(); ++f) y(full_dof[f]) = x(f);
  return y;
}
}  // namespace

Eigen::VectorXd DofMap::restrict(const Eigen::VectorXd& x) const {
  check_size("restrict(vector)", x.size(), num_dofs());
  return restrict_vector(full_dof_, x);
}
Eigen::VectorXcd DofMap::restrict(const Eigen::VectorXcd& x) const {
  check_size("restrict(vector)", x.size(), num_dofs());
  return restrict_vector(full_dof_, x);
}
Eigen::VectorXd DofMap::expand(const Eigen::VectorXd& x) const {
  check_size("expand(vector)", x.size(), num_free());
  return expand_vector(full_dof_, num_dofs(), x);
}
Eigen::VectorXcd DofMap::expand(const Eigen::VectorXcd& x) const {
  check_size("expand(vector)", x.size(), num_free());
  return expand_vector(full_dof_, num_dofs(), x);
}
Eigen::MatrixXd DofMap::expand(const Eigen::MatrixXd& X) const {
  check_size("expand(matrix) rows", X.rows(), num_free());
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(num_dofs(), X.cols());
  for (int f = 0; f < num_free(); ++f) Y.row(full_dof_[f]) = X.row(f);
  return Y;
}

}  // namespace stickslip
