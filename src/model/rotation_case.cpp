#include "model/rotation_case.h"

#include <algorithm>
#include <random>

#include <fmt/core.h>

#include "core/errors.h"
#include "fe/assembly.h"
#include "linalg/sparse_cholesky.h"

namespace stickslip {
namespace {

// A static problem K x = f counts as held when its factor gives back a test vector: the same
// check as the Craig–Bampton's floating interiors (craig_bampton.h), since CHOLMOD may factorise
// a singular positive semi-definite matrix with round-off pivots.
constexpr double kHeldTolerance = 1e-6;

bool factor_holds(const SparseMatrix& A, const SparseCholesky& factor) {
  if (!factor.ok()) return false;
  std::mt19937 rng(12345u);
  std::uniform_real_distribution<double> dist(-1.0, 1.0);
  Eigen::VectorXd v(A.rows());
  for (Eigen::Index i = 0; i < v.size(); ++i) v(i) = dist(rng);
  const Eigen::VectorXd back = factor.solve(Eigen::MatrixXd(A * v));
  return (back - v).norm() <= kHeldTolerance * v.norm();
}

// The static problem of a body: its free DOFs (a DofMap), or a cyclic sector's diameter-0
// independent DOFs. restrict(f), expand(x) and the restricted matrix.
struct StaticProblem {
  SparseMatrix K;
  SparseMatrix P;  // sector: full x n, real (empty otherwise)
  const DofMap* constraints = nullptr;
  Eigen::VectorXd restrict(const Eigen::VectorXd& f) const {
    return constraints ? constraints->restrict_load(f) : Eigen::VectorXd(P.transpose() * f);
  }
  Eigen::VectorXd expand(const Eigen::VectorXd& x) const {
    return constraints ? constraints->expand(x) : Eigen::VectorXd(P * x);
  }
};

StaticProblem static_problem(const SparseMatrix& K, const SparseMatrix& M,
                             const DofMap& constraints, const SectorBoundary* sector,
                             std::vector<int>* independent_of_full = nullptr) {
  StaticProblem s;
  if (sector == nullptr) {
    s.K = constraints.restrict(K);
    s.constraints = &constraints;
    if (independent_of_full) {
      independent_of_full->resize(static_cast<size_t>(constraints.num_dofs()));
      for (int d = 0; d < constraints.num_dofs(); ++d)
        (*independent_of_full)[static_cast<size_t>(d)] = constraints.free_index(d);
    }
    return s;
  }
  const CyclicSectorProblem p =
      cyclic_sector_problem(K, M, sector->pairs, sector->clamped_dofs, sector->symmetry, 0);
  s.K = p.K;
  s.P = p.T.real();  // diameter 0: T is real
  if (independent_of_full) {
    independent_of_full->resize(static_cast<size_t>(K.rows()));
    for (int d = 0; d < K.rows(); ++d)
      (*independent_of_full)[static_cast<size_t>(d)] = p.independent_index(d);
  }
  return s;
}

}  // namespace

RotationAxis case_rotation_axis(const CaseDefinition& def) {
  if (!def.rotation) throw InvalidInput(def.where("rotation"), "the case has no rotation");
  const RotationDefinition& r = *def.rotation;
  RotationAxis axis;
  if (r.axis_given) {
    axis.point = Eigen::Vector3d(r.axis_point[0], r.axis_point[1], r.axis_point[2]);
    axis.direction = Eigen::Vector3d(r.axis_direction[0], r.axis_direction[1], r.axis_direction[2]);
    return axis;
  }
  for (const auto& [name, bd] : def.bodies) {
    if (!bd.cyclic) continue;
    axis.point = Eigen::Vector3d(bd.cyclic->axis_point[0], bd.cyclic->axis_point[1],
                                 bd.cyclic->axis_point[2]);
    axis.direction = Eigen::Vector3d(bd.cyclic->axis_direction[0], bd.cyclic->axis_direction[1],
                                     bd.cyclic->axis_direction[2]);
    return axis;
  }
  throw InvalidInput(def.where("rotation"), "rotation: no axis (give rotation.axis)");
}

double case_rotation_speed(const CaseDefinition& def) {
  return def.rotation ? rpm_to_rad_per_s(def.rotation->speed_rpm) : 0.0;
}

void add_rotation_stiffness(const CaseDefinition& def, const std::string& name, const Mesh& mesh,
                            const IsotropicMaterial& material, const DofMap& constraints,
                            const SectorBoundary* sector, const SparseMatrix& M, SparseMatrix& K) {
  if (!def.rotation) return;
  const RotationDefinition& r = *def.rotation;
  const double omega = case_rotation_speed(def);
  if (omega == 0.0 || (!r.stress_stiffening && !r.spin_softening)) return;
  const RotationAxis axis = case_rotation_axis(def);
  SparseMatrix added(K.rows(), K.cols());
  if (r.spin_softening) added = -spin_softening_matrix(M, axis);
  if (r.stress_stiffening) {
    const StaticProblem s = static_problem(K, M, constraints, sector);
    SparseCholesky factor(s.K);
    if (!factor_holds(s.K, factor)) {
      model_warning(fmt::format(
          "rotation: body {} is not held by its own clamps, supports and equations (its contacts "
          "hold it): its centrifugal prestress is not known without them, so it gets no stress "
          "stiffening (spin softening {})",
          name, r.spin_softening ? "still applies" : "is off too"));
    } else {
      const Eigen::VectorXd f1 = centrifugal_force_per_speed_squared(M, mesh, axis);
      const Eigen::VectorXd u1 = s.expand(factor.solve(Eigen::MatrixXd(s.restrict(f1))).col(0));
      const auto& bd = def.bodies.at(name);
      added = added + geometric_stiffness(mesh, material,
                                          AssemblyOptions{.mass_integration = bd.mass_rule}, u1);
    }
  }
  K = K + (omega * omega) * added;
}

Eigen::VectorXd reduced_centrifugal_load(const CaseDefinition& def, const PreparedBody& body,
                                         const SectorBoundary* sector) {
  const int n = body.reduced.size();
  Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
  if (!def.rotation || !body.from_mesh) return out;
  const double omega = case_rotation_speed(def);
  if (omega == 0.0) return out;
  if (!body.M || (!body.T && !body.K)) {
    throw InvalidInput(def.where("rotation"),
                       "the full matrices of body " + body.name +
                           " are not at hand here (a stage command reading stored reduced "
                           "matrices): the centrifugal load needs them; use `stickslip run`");
  }
  const Eigen::VectorXd f = (omega * omega) * centrifugal_force_per_speed_squared(
                                                  *body.M, body.mesh, case_rotation_axis(def));
  if (body.T) return body.T->transpose() * f;
  // Static condensation on the masters: f_b − K_bi K_ii⁻¹ f_i.
  std::vector<int> index;
  const StaticProblem s = static_problem(*body.K, *body.M, body.constraints, sector, &index);
  const Eigen::VectorXd fs = s.restrict(f);
  std::vector<int> boundary;  // rows of s.K, in reduced order
  std::vector<int> reduced_row;
  for (int j = 0; j < n; ++j) {
    const ReducedDof& d = body.reduced.dofs[static_cast<size_t>(j)];
    if (d.kind != ReducedDof::Kind::kPhysical) continue;
    const int i = index[static_cast<size_t>(d.full_dof)];
    STICKSLIP_VERIFY(i >= 0, "reduced_centrifugal_load: a master is not independent");
    boundary.push_back(i);
    reduced_row.push_back(j);
  }
  const DofMap held(static_cast<int>(s.K.rows()), boundary);
  const SparseMatrix Kii = held.restrict(s.K);
  SparseCholesky factor(Kii);
  if (!factor_holds(Kii, factor)) {
    throw InvalidInput(def.where("rotation"),
                       "the interior of body " + body.name +
                           " is not held by its masters, clamps and supports: its centrifugal "
                           "load cannot be condensed onto the masters");
  }
  const Eigen::VectorXd ui =
      held.expand(Eigen::VectorXd(factor.solve(Eigen::MatrixXd(held.restrict_load(fs))).col(0)));
  const Eigen::VectorXd reaction = s.K * ui;  // K_bi u_i on the boundary rows
  for (size_t k = 0; k < boundary.size(); ++k)
    out(reduced_row[k]) = fs(boundary[k]) - reaction(boundary[k]);
  return out;
}

}  // namespace stickslip
