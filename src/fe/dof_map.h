// Dirichlet constraints u_c = 0 by elimination. The DOFs of the full model (0 .. num_dofs-1,
// DOF 3*node + direction) split into constrained ones and free ones; free DOFs keep their
// increasing order: free index f <-> full DOF full_dof(f).
//   restrict(K) = K_ff (free x free),   restrict(x) = x_f,   expand(x_f) = x with x_c = 0.
#pragma once

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"

namespace stickslip {

class DofMap {
 public:
  DofMap() = default;
  // `constrained` may be unsorted and repeat; every DOF must lie in [0, num_dofs) (else
  // InvalidInput naming the offending DOF).
  DofMap(int num_dofs, std::span<const int> constrained);

  // Constrains directions (x, y, z flags) of every node in `nodes` (node indices).
  static DofMap from_nodes(int num_nodes, std::span<const int> nodes,
                           std::array<bool, 3> directions = {true, true, true});

  int num_dofs() const { return static_cast<int>(free_index_.size()); }
  int num_free() const { return static_cast<int>(full_dof_.size()); }
  int num_constrained() const { return num_dofs() - num_free(); }
  // Free index of a full DOF, -1 if constrained.
  int free_index(int dof) const { return free_index_[dof]; }
  bool is_constrained(int dof) const { return free_index_[dof] < 0; }
  // Full DOF of a free index.
  int full_dof(int free) const { return full_dof_[free]; }
  const std::vector<int>& free_dofs() const { return full_dof_; }

  // Sizes are checked (InvalidInput on mismatch).
  SparseMatrix restrict(const SparseMatrix& A) const;
  Eigen::VectorXd restrict(const Eigen::VectorXd& x) const;
  Eigen::VectorXcd restrict(const Eigen::VectorXcd& x) const;
  Eigen::VectorXd expand(const Eigen::VectorXd& x_free) const;
  Eigen::VectorXcd expand(const Eigen::VectorXcd& x_free) const;
  Eigen::MatrixXd expand(const Eigen::MatrixXd& X_free) const;  // column by column

 private:
  std::vector<int> free_index_;  // size num_dofs
  std::vector<int> full_dof_;    // size num_free
};

}  // namespace stickslip
