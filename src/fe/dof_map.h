// Dirichlet constraints u_c = 0 and linear multi-point constraints (Mesh::equations, *EQUATION)
// by elimination. The DOFs of the full model (0 .. num_dofs-1, DOF 3*node + direction) split into
// clamped ones (u = 0), dependent ones (the first DOF of each equation Σ c_k u_k = 0, expressed
// through the others) and free ones, which keep their increasing order: free index f <-> full DOF
// full_dof(f). With the transformation u = T u_f (num_dofs x num_free: identity rows for free
// DOFs, zero rows for clamped ones, u_s = Σ_j a_sj u_f(j) for a dependent s):
//   restrict(K) = TᵀKT,  restrict_load(f) = Tᵀf,  restrict(x) = x_f (values at the free DOFs),
//   expand(x_f) = T x_f.
// Without equations T is a selection and restrict(K) = K_ff.
//
// Equations are resolved once at construction: a term on a clamped DOF drops out, a term on
// another equation's dependent DOF is replaced by that DOF's own expression (chains are followed;
// a cycle is InvalidInput). A dependent DOF that is also clamped is accepted only when its
// equation then reads 0 = 0 (every other term clamped too); otherwise InvalidInput naming the
// equation's origin. A DOF that is the dependent of two equations is InvalidInput.
#pragma once

#include <array>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/types.h"
#include "mesh/mesh.h"

namespace stickslip {

// A support of one node (node index): its displacement along each of `directions` (global axes,
// non-zero; normalised here) is zero: a symmetry plane (its normal), a roller, a 3-2-1 support, a
// direction of a local frame. `origin` names where it was asked for ("file:line"), for messages.
struct NodeSupport {
  int node = 0;
  std::vector<Eigen::Vector3d> directions;
  std::string origin;
};

// The supports as DOF constraints. Per node the directions of all its supports are merged and
// reduced to an independent set (a direction in the span of the node's others adds nothing; three
// independent ones hold the node in x, y and z), written in reduced row-echelon form over the
// node's x, y, z with the largest pivot first: a row that is a global axis (other entries below
// kSupportAxisTolerance, relative) clamps that DOF; every other row is an equation
// u_p + Σ c_d u_d = 0 over the node's own DOFs whose dependent DOF p (the pivot) appears in no
// other equation of the node. Node indices outside [0, num_nodes) and zero directions:
// InvalidInput naming the origin.
struct SupportConstraints {
  std::vector<int> clamped;                 // DOFs, sorted
  std::vector<LinearConstraint> equations;  // origin: the support's
};
inline constexpr double kSupportAxisTolerance = 1e-12;
SupportConstraints support_constraints(int num_nodes, std::span<const NodeSupport> supports);

class DofMap {
 public:
  DofMap() = default;
  // `constrained` (clamped) may be unsorted and repeat; every DOF must lie in [0, num_dofs) (else
  // InvalidInput naming the offending DOF).
  DofMap(int num_dofs, std::span<const int> constrained,
         std::span<const LinearConstraint> equations = {});

  // Constrains directions (x, y, z flags) of every node in `nodes` (node indices).
  static DofMap from_nodes(int num_nodes, std::span<const int> nodes,
                           std::array<bool, 3> directions = {true, true, true},
                           std::span<const LinearConstraint> equations = {});

  // Clamped nodes (x, y, z), supports (support_constraints) and equations (Mesh::equations), in
  // one map: the supports' clamped DOFs join the clamp, their equations follow `equations`.
  static DofMap from_supports(int num_nodes, std::span<const int> clamped_nodes,
                              std::span<const NodeSupport> supports,
                              std::span<const LinearConstraint> equations = {});

  int num_dofs() const { return static_cast<int>(free_index_.size()); }
  int num_free() const { return static_cast<int>(full_dof_.size()); }
  int num_constrained() const { return num_dofs() - num_free(); }  // clamped + dependent
  // Free index of a full DOF, -1 if clamped or dependent.
  int free_index(int dof) const { return free_index_[dof]; }
  // Not free: clamped or dependent.
  bool is_constrained(int dof) const { return free_index_[dof] < 0; }
  bool is_dependent(int dof) const { return dependent_row_[dof] >= 0; }
  bool is_clamped(int dof) const { return is_constrained(dof) && !is_dependent(dof); }
  bool has_dependents() const { return !rows_.empty(); }
  // The origin ("file:line") of the equation that made `dof` dependent (is_dependent(dof)).
  const std::string& dependent_origin(int dof) const { return origins_[dependent_row_[dof]]; }
  // Every dependent DOF's resolved equation u_s − Σ_j a_sj u_full_dof(j) = 0 (free DOFs only on
  // the right; origin: the equation's): with the clamped DOFs, the same constraints as the
  // equations given, in a form any FE code takes (*EQUATION).
  std::vector<LinearConstraint> resolved_equations() const;
  // Full DOF of a free index.
  int full_dof(int free) const { return full_dof_[free]; }
  const std::vector<int>& free_dofs() const { return full_dof_; }
  // T (num_dofs x num_free).
  SparseMatrix transformation() const;

  // Sizes are checked (InvalidInput on mismatch).
  SparseMatrix restrict(const SparseMatrix& A) const;  // TᵀAT
  Eigen::VectorXd restrict(const Eigen::VectorXd& x) const;
  Eigen::VectorXcd restrict(const Eigen::VectorXcd& x) const;
  Eigen::VectorXd restrict_load(const Eigen::VectorXd& f) const;  // Tᵀf
  Eigen::MatrixXcd restrict_load(const Eigen::MatrixXcd& F) const;  // column by column
  Eigen::VectorXd expand(const Eigen::VectorXd& x_free) const;
  Eigen::VectorXcd expand(const Eigen::VectorXcd& x_free) const;
  Eigen::MatrixXd expand(const Eigen::MatrixXd& X_free) const;  // column by column

  // TᵀAT placed back in the full numbering (num_dofs square; rows and columns of clamped and
  // dependent DOFs empty): for code that partitions full-numbered matrices itself (Craig–Bampton
  // with every non-free DOF in its constrained set).
  SparseMatrix condense(const SparseMatrix& A) const;
  // X (num_dofs rows, full numbering) with the rows of dependent DOFs set from the rows of the
  // free DOFs: X ← T X_f where X_f are X's free rows (clamped rows are left as they are).
  void fill_dependent_rows(Eigen::MatrixXd& X) const;

 private:
  template <class V>
  V expand_vector(const V& x) const;
  template <class V>
  V restrict_load_vector(const V& f) const;

  std::vector<int> free_index_;     // size num_dofs
  std::vector<int> full_dof_;       // size num_free
  std::vector<int> dependent_row_;  // size num_dofs: index into rows_, -1 if not dependent
  std::vector<std::vector<std::pair<int, double>>> rows_;  // per dependent: (free index, a)
  std::vector<std::string> origins_;                       // per dependent
};

}  // namespace stickslip
