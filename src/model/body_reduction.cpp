#include "model/body_reduction.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <utility>

#include <fmt/core.h>
#include <Eigen/Cholesky>

#include "core/errors.h"
#include "fe/assembly.h"
#include "io/abaqus_matrix.h"
#include "io/ansys_mapping.h"
#include "io/matrix_market.h"
#include "mesh/mesh_tools.h"
#include "model/petsc_reduction.h"
#include "model/rotation_case.h"
#include "reduction/craig_bampton.h"

namespace stickslip {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A body given by Matrix Market stiffness and mass plus an ANSYS mapping file: the same reduced
// body read_ansys_reduced_body builds from Harwell–Boeing files (io/ansys_mapping.h).
ReducedBody read_matrix_market_body(const ReducedMatricesDefinition& r) {
  // Symmetry of a "general" file: the tolerance of the Harwell–Boeing importer for RUA files.
  constexpr double kSymmetryTolerance = 1e-10;
  const AnsysMapping mapping = read_ansys_mapping(r.mapping);
  check_reduced_body_size(mapping, r.mapping);  // bounds the dense matrices below
  const int n = static_cast<int>(mapping.entries.size());
  Eigen::MatrixXd K, M;
  for (const std::string* path : {&r.stiffness, &r.mass}) {
    const MatrixMarketMatrix m = read_matrix_market(*path);  // sparse: what its data backs
    if (m.matrix.rows() != n || m.matrix.cols() != n) {
      throw InvalidInput({*path, m.size_line, "rows columns"},
                         fmt::format("matrix is {} x {} but the mapping {} has {} equations",
                                     m.matrix.rows(), m.matrix.cols(), r.mapping, n));
    }
    Eigen::MatrixXd dense(m.matrix);
    const double scale = dense.cwiseAbs().maxCoeff();
    const double asym = (dense - dense.transpose()).cwiseAbs().maxCoeff();
    if (asym > kSymmetryTolerance * scale) {
      throw InvalidInput({*path, 1, ""},
                         fmt::format("a body matrix must be symmetric: max |a_ij - a_ji| = {:g}, "
                                     "max |a_ij| = {:g}",
                                     asym, scale));
    }
    (path == &r.stiffness ? K : M) = 0.5 * (dense + dense.transpose());
  }
  return reduced_body_from_mapping(std::move(K), std::move(M), mapping, r.mapping);
}

// Craig–Bampton reduction of a mesh body onto its master nodes (masters: node indices).
void reduce_mesh_body(const CaseDefinition& def, const std::string& name, const BodyDefinition& bd,
                      const CaseBody& resolved, const std::vector<int>& masters,
                      PreparedBody& body) {
  const std::string key = "bodies." + name;
  const auto t0 = Clock::now();
  SparseMatrix K, M;
  assemble_stiffness_mass(body.mesh, body.material,
                          AssemblyOptions{.mass_integration = bd.mass_rule}, &K, &M);
  try {
    body.constraints = body_constraints(resolved, body.mesh);
  } catch (const InvalidInput& e) {
    throw InvalidInput(def.where(key + (resolved.supports.empty() ? ".clamp" : ".supports")),
                       "body " + name + ": " + e.message());
  }
  // A spinning body is reduced with its stiffness at the case's speed (model/rotation_case.h).
  add_rotation_stiffness(def, name, body.mesh, body.material, body.constraints, nullptr, M, K);
  std::vector<int> constrained;
  for (int d = 0; d < body.constraints.num_dofs(); ++d) {
    if (body.constraints.is_constrained(d)) constrained.push_back(d);
  }
  std::vector<int> boundary;
  for (int n : masters) {
    for (int dir = 0; dir < 3; ++dir) {
      if (body.constraints.is_dependent(dof_of(n, dir))) {
        throw InvalidInput(
            def.where(key),
            fmt::format("node {} of body {} is a master (contact, forced or listed) node, but its "
                        "direction {} is the dependent (first) DOF of the equation or support at "
                        "{}: write that equation with another DOF first (a master node cannot "
                        "have a support in a local frame)",
                        body.mesh.node_ids[n], name, "xyz"[dir],
                        body.constraints.dependent_origin(dof_of(n, dir))));
      }
      if (body.constraints.is_constrained(dof_of(n, dir))) {
        throw InvalidInput(
            def.where(key + (resolved.supports.empty() ? ".clamp" : ".supports")),
            fmt::format("node {} of body {} is both clamped or supported (direction {}) and a "
                        "master (contact, forced or listed) node",
                        body.mesh.node_ids[n], name, "xyz"[dir]));
      }
      boundary.push_back(dof_of(n, dir));
    }
  }
  std::sort(boundary.begin(), boundary.end());
  const int interior = body.constraints.num_free() - static_cast<int>(boundary.size());
  CraigBamptonOptions options;
  options.num_modes = std::min(bd.modes, std::max(0, interior));  // every interior mode at most
  const long long reduced_dofs = static_cast<long long>(boundary.size()) + options.num_modes;
  if (reduced_dofs > kMaxReducedBodyDofs) {  // the limit of imported bodies (io/ansys_mapping.h)
    throw InvalidInput(
        def.where(key),
        fmt::format("body {}: {} master nodes x 3 + {} modes = {}: {}", name, masters.size(),
                    options.num_modes, reduced_dofs, reduced_body_size_message(reduced_dofs)));
  }
  // Equations (*EQUATION): reduce TᵀKT, TᵀMT with the dependent DOFs among the constrained ones,
  // then give the basis its dependent rows (x = T x_f).
  const bool dependents = body.constraints.has_dependents();
  // reduction_solver: petsc: the same reduction by PETSc/SLEPc (model/petsc_reduction.h).
  const auto reduce = [&](const SparseMatrix& Kc, const SparseMatrix& Mc) {
    return bd.reduction_solver == ReductionSolver::kPetsc
               ? craig_bampton_petsc(Kc, Mc, constrained, boundary, options)
               : craig_bampton(Kc, Mc, constrained, boundary, options);
  };
  CraigBamptonResult cb =
      dependents ? reduce(body.constraints.condense(K), body.constraints.condense(M)) : reduce(K, M);
  if (dependents && cb.summary.ok()) body.constraints.fill_dependent_rows(cb.T);
  if (!cb.summary.ok()) {
    throw InvalidInput(def.where(key), "Craig–Bampton reduction of body " + name +
                                           " failed: " + cb.summary.message);
  }
  assign_node_ids(cb.body, body.mesh.node_ids);
  body.reduced = std::move(cb.body);
  body.T = std::make_shared<const Eigen::MatrixXd>(std::move(cb.T));
  body.K = std::make_shared<const SparseMatrix>(std::move(K));
  body.M = std::make_shared<const SparseMatrix>(std::move(M));
  body.seconds_reduction = seconds_since(t0);
}


}  // namespace

void check_reduced_matrices(const CaseDefinition& def, const std::string& name,
                            const ReducedBody& body, const std::string& stiffness_file,
                            const std::string& mass_file) {
  // An imported body must be a physical one: M positive definite (else it has no modes) and K
  // positive semi-definite (a negative eigenvalue is a negative stiffness: the body would buckle
  // away, and the harmonic balance would return a meaningless response). By the inertia of the
  // LDLᵀ factors (Sylvester), relative to the largest pivot.
  const std::string key = "bodies." + name + ".reduced";
  if (Eigen::LLT<Eigen::MatrixXd> llt(body.M); llt.info() != Eigen::Success) {
    throw InvalidInput(def.where(key + ".mass"),
                       "the mass matrix of " + mass_file + " is not positive definite");
  }
  // Pivots below this fraction of the largest are zero (rigid-body modes of a free body, round-off
  // of the exported digits), not negative stiffness.
  constexpr double kPivotTolerance = 1e-9;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(body.K);
  const Eigen::VectorXd d = ldlt.vectorD();
  const double largest = d.cwiseAbs().maxCoeff();
  Eigen::Index worst = 0;
  if (ldlt.info() != Eigen::Success || d.minCoeff(&worst) < -kPivotTolerance * largest) {
    throw InvalidInput(def.where(key + ".stiffness"),
                       "the stiffness matrix of " + stiffness_file +
                           " is not positive semi-definite (a negative stiffness: pivot " +
                           fmt::format("{:.3e}", d(worst)) + " against a largest " +
                           fmt::format("{:.3e}", largest) + ")");
  }
}

ReducedBody read_matrix_body(const CaseDefinition& def, const std::string& name) {
  const ReducedMatricesDefinition& r = def.bodies.at(name).reduced;
  ReducedBody body =
      r.format == ReducedFileFormat::kMatrixMarket   ? read_matrix_market_body(r)
      : r.format == ReducedFileFormat::kAbaqusMatrix ? read_abaqus_reduced_body(r.stiffness, r.mass)
                                                     : read_ansys_reduced_body(r.stiffness, r.mass,
                                                                               r.mapping);
  check_reduced_matrices(def, name, body, r.stiffness, r.mass);
  return body;
}

void attach_reduced_dofs_to_mesh(PreparedBody& body) {
  const auto by_id = node_index_by_id(body.mesh);
  for (ReducedDof& d : body.reduced.dofs) {
    if (d.kind != ReducedDof::Kind::kPhysical) continue;
    const auto it = by_id.find(d.node_id);
    if (it == by_id.end()) {
      throw InvalidInput(fmt::format("body {}: node {} of its reduced matrices is not in its mesh",
                                     body.name, d.node_id));
    }
    d.node_index = it->second;
    d.full_dof = 3 * d.node_index + d.direction;
  }
}

CraigBamptonReduction::CraigBamptonReduction(ModelCache* cache,
                                             std::vector<std::string> fingerprints)
    : cache_(cache), fingerprints_(std::move(fingerprints)) {}

void CraigBamptonReduction::reduce(const CaseDefinition& def, const CaseBody& resolved,
                                   PreparedBody& body, const ProgressFn& progress) const {
  const auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  const std::string& name = body.name;
  if (!body.from_mesh) {
    body.reduced = read_matrix_body(def, name);
    return;
  }
  const BodyDefinition& bd = def.bodies.at(name);
  const std::vector<int>& m = resolved.masters;
  ModelCache::Body* cached = nullptr;
  if (cache_ != nullptr) {
    // The body's fingerprint: its position in the resolved case is its position in def.bodies.
    const auto it = def.bodies.find(name);
    const size_t b = static_cast<size_t>(std::distance(def.bodies.begin(), it));
    STICKSLIP_VERIFY(b < fingerprints_.size(), "CraigBamptonReduction: no fingerprint for body");
    cached = &cache_->body(name, fingerprints_[b]);
    if (cached->reduced_here) {
      say(fmt::format("reduce {}: the reduction already made (same mesh, element set, material, "
                      "clamps, masters and modes)",
                      name));
      body.constraints = cached->constraints;
      body.K = cached->K;
      body.M = cached->M;
      body.reduced = cached->reduced;
      body.T = cached->T;
      body.seconds_reduction = 0.0;
      return;
    }
  }
  say(fmt::format("reduce {} ({} nodes, {} masters, {} modes)", name, body.mesh.num_nodes(),
                  m.size(), bd.modes));
  reduce_mesh_body(def, name, bd, resolved, m, body);
  say(fmt::format("reduce {}: {} reduced DOFs in {:.1f} s", name, body.reduced.size(),
                  body.seconds_reduction));
  if (cached != nullptr) {
    cached->constraints = body.constraints;
    cached->reduced = body.reduced;
    cached->K = body.K;
    cached->M = body.M;
    cached->T = body.T;
    cached->reduced_here = true;
  }
}

GivenReduction::GivenReduction(std::map<std::string, std::shared_ptr<const ReducedBody>> bodies)
    : bodies_(std::move(bodies)) {}

void GivenReduction::reduce(const CaseDefinition& def, const CaseBody& resolved,
                            PreparedBody& body, const ProgressFn& progress) const {
  const auto it = bodies_.find(body.name);
  if (it == bodies_.end() || it->second == nullptr) {
    CraigBamptonReduction().reduce(def, resolved, body, progress);
    return;
  }
  const ReducedBody& given = *it->second;
  const std::string key = "bodies." + body.name;
  if (given.K.rows() != given.size() || given.K.cols() != given.size() ||
      given.M.rows() != given.size() || given.M.cols() != given.size()) {
    throw InvalidInput(def.where(key),
                       fmt::format("body {}: the given K and M must be {} x {} (its DOFs)",
                                   body.name, given.size(), given.size()));
  }
  body.reduced = given;
  check_reduced_matrices(def, body.name, body.reduced, "body " + body.name + " (given)",
                         "body " + body.name + " (given)");
  if (body.from_mesh) {
    body.constraints = body_constraints(resolved, body.mesh);
    try {
      attach_reduced_dofs_to_mesh(body);
    } catch (const InvalidInput& e) {
      throw InvalidInput(def.where(key), e.message());
    }
  }
}

}  // namespace stickslip
