#include "fe/dof_map.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
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

DofMap::DofMap(int num_dofs, std::span<const int> constrained,
               std::span<const LinearConstraint> equations) {
  require(num_dofs >= 0, "DofMap num_dofs", std::to_string(num_dofs), ">= 0");
  std::vector<char> clamped(num_dofs, 0);
  for (int d : constrained) {
    if (d < 0 || d >= num_dofs) {
      throw InvalidInput("DofMap: constrained DOF " + std::to_string(d) + " out of range [0, " +
                         std::to_string(num_dofs) + ")");
    }
    clamped[d] = 1;
  }
  // Raw expressions u_s = Σ a u_j of the dependent DOFs (one equation each).
  std::vector<int> equation_of(num_dofs, -1);
  for (size_t e = 0; e < equations.size(); ++e) {
    const LinearConstraint& c = equations[e];
    if (c.dofs.empty() || c.dofs.size() != c.coefficients.size() || c.coefficients[0] == 0.0) {
      throw InvalidInput("DofMap: the equation at " + c.origin +
                         " is empty or its first coefficient is 0");
    }
    for (int d : c.dofs) {
      if (d < 0 || d >= num_dofs) {
        throw InvalidInput("DofMap: the equation at " + c.origin + " names DOF " +
                           std::to_string(d) + ", out of range [0, " + std::to_string(num_dofs) +
                           ")");
      }
    }
    const int s = c.dofs[0];
    if (equation_of[s] >= 0) {
      throw InvalidInput("DofMap: node index " + std::to_string(s / 3) + " direction " +
                         std::to_string(s % 3 + 1) +
                         " is the dependent (first) DOF of two equations, at " +
                         equations[equation_of[s]].origin + " and " + c.origin);
    }
    equation_of[s] = static_cast<int>(e);
  }
  free_index_.assign(num_dofs, -1);
  dependent_row_.assign(num_dofs, -1);
  for (int d = 0; d < num_dofs; ++d) {
    if (!clamped[d] && equation_of[d] < 0) {
      free_index_[d] = static_cast<int>(full_dof_.size());
      full_dof_.push_back(d);
    }
  }
  if (equations.empty()) return;

  // Resolve every dependent DOF down to free DOFs (memoised; state 1 = being resolved).
  std::vector<std::vector<std::pair<int, double>>> resolved(num_dofs);
  std::vector<char> state(num_dofs, 0);
  std::function<void(int)> resolve = [&](int s) {
    if (state[s] == 2) return;
    if (state[s] == 1) {
      throw InvalidInput("DofMap: the equations at " + equations[equation_of[s]].origin +
                         " and the ones it refers to form a cycle (a dependent DOF depends on "
                         "itself)");
    }
    state[s] = 1;
    const LinearConstraint& c = equations[equation_of[s]];
    std::vector<std::pair<int, double>> row;
    for (size_t k = 1; k < c.dofs.size(); ++k) {
      const int j = c.dofs[k];
      const double a = -c.coefficients[k] / c.coefficients[0];
      if (clamped[j] || a == 0.0) continue;
      if (free_index_[j] >= 0) {
        row.emplace_back(free_index_[j], a);
      } else {
        resolve(j);
        for (const auto& [f, b] : resolved[j]) row.emplace_back(f, a * b);
      }
    }
    std::sort(row.begin(), row.end());
    std::vector<std::pair<int, double>> merged;
    for (const auto& [f, a] : row) {
      if (!merged.empty() && merged.back().first == f) {
        merged.back().second += a;
      } else {
        merged.emplace_back(f, a);
      }
    }
    std::erase_if(merged, [](const auto& t) { return t.second == 0.0; });
    resolved[s] = std::move(merged);
    state[s] = 2;
  };
  for (int s = 0; s < num_dofs; ++s) {
    if (equation_of[s] < 0) continue;
    if (clamped[s]) {
      // A clamped dependent: its equation must then say 0 = 0.
      const LinearConstraint& c = equations[equation_of[s]];
      for (size_t k = 1; k < c.dofs.size(); ++k) {
        if (!clamped[c.dofs[k]] && c.coefficients[k] != 0.0) {
          throw InvalidInput(
              "DofMap: node index " + std::to_string(s / 3) + " direction " +
              std::to_string(s % 3 + 1) + " is clamped and is the dependent (first) DOF of the "
              "equation at " + c.origin + ", whose other DOFs are not all clamped: clamp them "
              "too, or write the equation with an unclamped DOF first");
        }
      }
      continue;
    }
    resolve(s);
    dependent_row_[s] = static_cast<int>(rows_.size());
    rows_.push_back(resolved[s]);
    origins_.push_back(equations[equation_of[s]].origin);
  }
}

SupportConstraints support_constraints(int num_nodes, std::span<const NodeSupport> supports) {
  // Rows (unit directions) and origins per node, in the order given.
  std::map<int, std::vector<std::pair<Eigen::Vector3d, std::string>>> rows;
  for (const NodeSupport& s : supports) {
    if (s.node < 0 || s.node >= num_nodes) {
      throw InvalidInput("support at " + s.origin + ": node index " + std::to_string(s.node) +
                         " out of range [0, " + std::to_string(num_nodes) + ")");
    }
    for (const Eigen::Vector3d& d : s.directions) {
      const double norm = d.norm();
      if (!(norm > 0.0) || !std::isfinite(norm)) {
        throw InvalidInput("support at " + s.origin + ": a direction must be a non-zero vector");
      }
      rows[s.node].emplace_back(d / norm, s.origin);
    }
  }
  SupportConstraints out;
  for (auto& [node, list] : rows) {
    // Gauss–Jordan elimination with partial pivoting over the columns x, y, z; the rows are unit
    // vectors, so a remaining row below kRankTolerance lies in the span of the pivots found.
    constexpr double kRankTolerance = 1e-9;
    Eigen::MatrixXd A(static_cast<Eigen::Index>(list.size()), 3);
    for (size_t i = 0; i < list.size(); ++i) A.row(static_cast<Eigen::Index>(i)) = list[i].first;
    std::vector<std::pair<int, int>> pivots;  // (row, column)
    std::vector<char> used_row(list.size(), 0);
    for (int col = 0; col < 3; ++col) {
      int best = -1;
      for (int r = 0; r < A.rows(); ++r) {
        if (!used_row[r] && (best < 0 || std::abs(A(r, col)) > std::abs(A(best, col)))) best = r;
      }
      if (best < 0 || std::abs(A(best, col)) <= kRankTolerance) continue;
      used_row[best] = 1;
      A.row(best) /= A(best, col);
      for (int r = 0; r < A.rows(); ++r) {
        if (r != best) A.row(r) -= A(r, col) * A.row(best);
      }
      pivots.emplace_back(best, col);
    }
    for (const auto& [r, p] : pivots) {
      LinearConstraint c;
      c.dofs.push_back(dof_of(node, p));
      c.coefficients.push_back(1.0);
      for (int d = 0; d < 3; ++d) {
        if (d != p && std::abs(A(r, d)) > kSupportAxisTolerance) {
          c.dofs.push_back(dof_of(node, d));
          c.coefficients.push_back(A(r, d));
        }
      }
      if (c.dofs.size() == 1) {
        out.clamped.push_back(c.dofs[0]);
      } else {
        c.origin = list[r].second;
        out.equations.push_back(std::move(c));
      }
    }
  }
  std::sort(out.clamped.begin(), out.clamped.end());
  return out;
}

DofMap DofMap::from_supports(int num_nodes, std::span<const int> clamped_nodes,
                             std::span<const NodeSupport> supports,
                             std::span<const LinearConstraint> equations) {
  const SupportConstraints sc = support_constraints(num_nodes, supports);
  std::vector<int> dofs = sc.clamped;
  for (int n : clamped_nodes) {
    if (n < 0 || n >= num_nodes) {
      throw InvalidInput("DofMap: constrained node index " + std::to_string(n) +
                         " out of range [0, " + std::to_string(num_nodes) + ")");
    }
    for (int d = 0; d < 3; ++d) dofs.push_back(dof_of(n, d));
  }
  std::vector<LinearConstraint> all(equations.begin(), equations.end());
  all.insert(all.end(), sc.equations.begin(), sc.equations.end());
  return DofMap(kDofsPerNode * num_nodes, dofs, all);
}

std::vector<LinearConstraint> DofMap::resolved_equations() const {
  std::vector<LinearConstraint> out;
  for (int s = 0; s < num_dofs(); ++s) {
    if (dependent_row_[s] < 0) continue;
    LinearConstraint c;
    c.dofs.push_back(s);
    c.coefficients.push_back(1.0);
    for (const auto& [f, a] : rows_[dependent_row_[s]]) {
      c.dofs.push_back(full_dof_[f]);
      c.coefficients.push_back(-a);
    }
    c.origin = origins_[dependent_row_[s]];
    out.push_back(std::move(c));
  }
  return out;
}

DofMap DofMap::from_nodes(int num_nodes, std::span<const int> nodes,
                          std::array<bool, 3> directions,
                          std::span<const LinearConstraint> equations) {
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
  return DofMap(kDofsPerNode * num_nodes, dofs, equations);
}

SparseMatrix DofMap::transformation() const {
  std::vector<Triplet> t;
  t.reserve(full_dof_.size());
  for (int f = 0; f < num_free(); ++f) t.emplace_back(full_dof_[f], f, 1.0);
  for (int d = 0; d < num_dofs(); ++d) {
    if (dependent_row_[d] < 0) continue;
    for (const auto& [f, a] : rows_[dependent_row_[d]]) t.emplace_back(d, f, a);
  }
  SparseMatrix T(num_dofs(), num_free());
  T.setFromTriplets(t.begin(), t.end());
  return T;
}

SparseMatrix DofMap::condense(const SparseMatrix& A) const {
  const SparseMatrix R = restrict(A);
  std::vector<Triplet> t;
  t.reserve(static_cast<size_t>(R.nonZeros()));
  for (int c = 0; c < R.outerSize(); ++c) {
    for (SparseMatrix::InnerIterator it(R, c); it; ++it) {
      t.emplace_back(full_dof_[it.row()], full_dof_[c], it.value());
    }
  }
  SparseMatrix out(num_dofs(), num_dofs());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

void DofMap::fill_dependent_rows(Eigen::MatrixXd& X) const {
  check_size("fill_dependent_rows rows", X.rows(), num_dofs());
  for (int d = 0; d < num_dofs(); ++d) {
    if (dependent_row_[d] < 0) continue;
    X.row(d).setZero();
    for (const auto& [f, a] : rows_[dependent_row_[d]]) X.row(d) += a * X.row(full_dof_[f]);
  }
}

SparseMatrix DofMap::restrict(const SparseMatrix& A) const {
  check_size("restrict(matrix) rows", A.rows(), num_dofs());
  check_size("restrict(matrix) cols", A.cols(), num_dofs());
  if (has_dependents()) {
    const SparseMatrix T = transformation();
    const SparseMatrix Tt = T.transpose();
    SparseMatrix R = Tt * A * T;
    R.makeCompressed();
    return R;
  }
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
}  // namespace

template <class V>
V DofMap::expand_vector(const V& x) const {
  V y = V::Zero(num_dofs());
  for (size_t f = 0; f < full_dof_.size(); ++f) y(full_dof_[f]) = x(f);
  for (int d = 0; d < num_dofs(); ++d) {
    if (dependent_row_[d] < 0) continue;
    for (const auto& [f, a] : rows_[dependent_row_[d]]) y(d) += a * x(f);
  }
  return y;
}

template <class V>
V DofMap::restrict_load_vector(const V& f) const {
  V y = restrict_vector(full_dof_, f);
  for (int d = 0; d < num_dofs(); ++d) {
    if (dependent_row_[d] < 0) continue;
    for (const auto& [k, a] : rows_[dependent_row_[d]]) y(k) += a * f(d);
  }
  return y;
}

Eigen::VectorXd DofMap::restrict_load(const Eigen::VectorXd& f) const {
  check_size("restrict_load(vector)", f.size(), num_dofs());
  return restrict_load_vector(f);
}
Eigen::MatrixXcd DofMap::restrict_load(const Eigen::MatrixXcd& F) const {
  check_size("restrict_load(matrix) rows", F.rows(), num_dofs());
  Eigen::MatrixXcd out(num_free(), F.cols());
  for (Eigen::Index c = 0; c < F.cols(); ++c) {
    out.col(c) = restrict_load_vector(Eigen::VectorXcd(F.col(c)));
  }
  return out;
}

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
  return expand_vector(x);
}
Eigen::VectorXcd DofMap::expand(const Eigen::VectorXcd& x) const {
  check_size("expand(vector)", x.size(), num_free());
  return expand_vector(x);
}
Eigen::MatrixXd DofMap::expand(const Eigen::MatrixXd& X) const {
  check_size("expand(matrix) rows", X.rows(), num_free());
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(num_dofs(), X.cols());
  for (int f = 0; f < num_free(); ++f) Y.row(full_dof_[f]) = X.row(f);
  fill_dependent_rows(Y);
  return Y;
}

}  // namespace stickslip
