#include "model/body_recovery.h"

#include <algorithm>
#include <complex>
#include <stdexcept>
#include <string>

#include "core/errors.h"
#include "fe/rotation.h"
#include "model/recovery_loads.h"
#include "model/rotation_case.h"

namespace stickslip {

BodyRecovery::BodyRecovery(const CaseDefinition& def, const PreparedModel& model, int body,
                           BodyRecoveryOptions options)
    : model_(model),
      body_(model.bodies.at(static_cast<size_t>(body))),
      method_(def.recovery.method),
      damping_{def.damping.alpha, def.damping.beta} {
  if (!body_.from_mesh) {
    throw std::invalid_argument("BodyRecovery: body " + body_.name + " is not given by a mesh");
  }
  // A mesh body whose reduction kept no full matrices (GivenReduction: reduced matrices given in
  // memory) cannot be recovered on its mesh.
  if (!body_.K || !body_.M || (method_ == RecoveryMethod::kExpansion && !body_.T)) {
    throw InvalidInput(
        def.where("bodies." + body_.name),
        "body " + body_.name + " has no full " +
            (body_.K && body_.M ? std::string("Craig-Bampton basis (recovery.method: expansion)")
                                : std::string("stiffness and mass matrices")) +
            ": its reduced model was given without them, so it cannot be recovered on its "
            "mesh (recovery.points: none)");
  }
  if (model.wave && body_.cyclic && !body_.cyclic_pairs.empty()) {
    // A cyclic sector: each harmonic on its nodal diameter (recovery/cyclic_recovery.h). A body
    // of the sector without boundaries (a damper) is the same for every diameter: below.
    if (method_ != RecoveryMethod::kDirect) {
      throw InvalidInput(def.where("recovery.method"),
                         "body " + body_.name +
                             " is a cyclic sector: its recovery is the direct solve of each "
                             "harmonic's nodal diameter (recovery.method: direct)");
    }
    std::vector<int> clamped, harmonics{0};
    for (int d = 0; d < body_.constraints.num_dofs(); ++d) {
      if (body_.constraints.is_clamped(d)) clamped.push_back(d);
    }
    for (int k : def.analysis.harmonics) harmonics.push_back(k);
    cyclic_ = std::make_unique<CyclicSectorRecovery>(*body_.K, *body_.M, body_.cyclic_pairs,
                                                     clamped, *body_.cyclic,
                                                     model.wave->engine_order, damping_, harmonics);
    if (!cyclic_->ok()) {
      throw InvalidInput(
          def.where("bodies." + body_.name + ".cyclic"),
          "recovery of cyclic body " + body_.name + " failed: " + cyclic_->message());
    }
    elements_at_node_ = elements_at_nodes(body_.mesh);
  } else if (method_ == RecoveryMethod::kDirect) {
    solver_ = std::make_unique<DirectRecovery>(*body_.K, *body_.M, body_.constraints, damping_);
  } else if (method_ == RecoveryMethod::kModal) {
    ModalRecoveryOptions o;
    o.num_modes = std::min(def.recovery.modes, body_.constraints.num_free() - 1);
    solver_ = std::make_unique<ModalRecovery>(*body_.K, *body_.M, body_.constraints, damping_, o);
  }
  if (solver_ && !solver_->ok()) {
    throw InvalidInput(def.where("recovery.method"),
                       "recovery of body " + body_.name + " failed: " + solver_->message());
  }
  rigid_ = solver_ ? solver_->rigid_modes() : Eigen::MatrixXd();
  // The physical (master) DOFs in the order of body.reduced: full-model and assembled-reduced.
  for (int j = 0; j < body_.reduced.size(); ++j) {
    const ReducedDof& d = body_.reduced.dofs[j];
    if (d.kind == ReducedDof::Kind::kPhysical) {
      full_dofs_.push_back(d.full_dof);
      reduced_dofs_.push_back(body_.offset + j);
    }
  }
  for (int node = 0; node < body_.mesh.num_nodes(); ++node) {
    if (cyclic_ && cyclic_->is_high(node)) continue;  // the next sector's low node
    for (int d = 0; d < 3; ++d) {
      if (body_.constraints.is_constrained(dof_of(node, d))) {
        held_nodes_.push_back(node);
        break;
      }
    }
  }
  // A spinning body: its centrifugal body force on every node replaces the condensed one that
  // the reduced model carried at its master rows (the excitation's harmonic 0, recovery_loads).
  if (def.rotation && case_rotation_speed(def) != 0.0) {
    const double omega = case_rotation_speed(def);
    rotation_load_ = (omega * omega) * centrifugal_force_per_speed_squared(*body_.M, body_.mesh,
                                                                           case_rotation_axis(def));
    std::optional<SectorBoundary> sector;
    if (body_.cyclic) {
      sector = SectorBoundary{body_.cyclic_pairs, {}, *body_.cyclic};
      for (int d = 0; d < body_.constraints.num_dofs(); ++d) {
        if (body_.constraints.is_clamped(d)) sector->clamped_dofs.push_back(d);
      }
    }
    const Eigen::VectorXd condensed =
        reduced_centrifugal_load(def, body_, sector ? &*sector : nullptr);
    for (int j = 0; j < body_.reduced.size(); ++j) {
      const ReducedDof& d = body_.reduced.dofs[j];
      if (d.kind == ReducedDof::Kind::kPhysical) rotation_load_(d.full_dof) -= condensed(j);
    }
  }
  // Nodal stresses as one sparse operator, built once per body (element by element per point
  // would re-condense every C3D8I at every call).
  if (options.stresses) stress_operator_.emplace(body_.mesh, body_.material, AssemblyOptions{});
}

BodyRecovery::~BodyRecovery() = default;

RecoveredPoint BodyRecovery::recover(const FrequencyPoint& p,
                                     const std::vector<int>& harmonics) const {
  const int nh = static_cast<int>(harmonics.size());
  const int n = body_.mesh.num_dofs();
  RecoveredPoint out;
  out.loads = recovery_loads(model_, body_, harmonics, p);
  for (int h = 0; h < nh && rotation_load_.size() > 0; ++h) {
    if (harmonics[h] == 0) out.loads.col(h) += rotation_load_.cast<std::complex<double>>();
  }
  out.displacement = cyclic_ ? cyclic_->solve(out.loads, harmonics, p.omega, &out.summary)
                     : method_ == RecoveryMethod::kExpansion
                         ? expand_reduced_response(
                               *body_.T, p.master.middleRows(body_.offset, body_.reduced.size()))
                         : harmonic_response(*solver_, out.loads, harmonics, p.omega, &out.summary);
  Eigen::MatrixXcd& x = out.displacement;
  // A body its clamps and supports do not hold: the static solve has no rigid motion; the
  // reduced solution knows what the springs and contacts did with it (at the master DOFs).
  for (int h = 0; h < nh && rigid_.cols() > 0; ++h) {
    if (harmonics[h] != 0) continue;
    Eigen::VectorXcd target(static_cast<Eigen::Index>(full_dofs_.size()));
    for (size_t i = 0; i < full_dofs_.size(); ++i) target(i) = p.master(reduced_dofs_[i], h);
    add_rigid_motion(rigid_, full_dofs_, target, x.col(h));
  }
  // Check against the reduced nonlinear response at the master DOFs.
  Eigen::MatrixXcd reduced = Eigen::MatrixXcd::Zero(n, nh);
  for (size_t i = 0; i < full_dofs_.size(); ++i)
    reduced.row(full_dofs_[i]) = p.master.row(reduced_dofs_[i]);
  out.check = compare_responses(x, reduced, full_dofs_);
  out.reduced_max.assign(static_cast<size_t>(nh), 0.0);
  for (int h = 0; h < nh; ++h) {
    for (int dof : full_dofs_) {
      out.reduced_max[h] = std::max(out.reduced_max[h], std::abs(reduced(dof, h)));
    }
  }
  // Reactions at the held nodes (zero at free DOFs to the solver's round-off).
  out.reactions.resize(3 * static_cast<Eigen::Index>(held_nodes_.size()), nh);
  if (!held_nodes_.empty()) {
    const Eigen::MatrixXd xr = x.real(), xi = x.imag();
    const Eigen::MatrixXd Kr = *body_.K * xr, Ki = *body_.K * xi;
    const Eigen::MatrixXd Mr = *body_.M * xr, Mi = *body_.M * xi;
    const std::complex<double> i1(0, 1);
    Eigen::MatrixXcd residual(n, nh);
    for (int h = 0; h < nh; ++h) {
      const double w = harmonics[h] * p.omega;
      const Eigen::VectorXcd Kx = Kr.col(h).cast<std::complex<double>>() + i1 * Ki.col(h);
      const Eigen::VectorXcd Mx = Mr.col(h).cast<std::complex<double>>() + i1 * Mi.col(h);
      residual.col(h) = Kx - w * w * Mx +
                        std::complex<double>(0, w) * (damping_.alpha * Mx + damping_.beta * Kx) -
                        out.loads.col(h);
    }
    // A sector's low node is shared with the previous sector, whose share is its high node's.
    if (cyclic_) cyclic_->fold_boundary_residual(residual, harmonics);
    for (int h = 0; h < nh; ++h) {
      for (size_t i = 0; i < held_nodes_.size(); ++i) {
        for (int d = 0; d < 3; ++d) {
          out.reactions(3 * i + d, h) = residual(dof_of(held_nodes_[i], d), h);
        }
      }
    }
  }
  return out;
}

std::vector<ComplexStressMatrix> BodyRecovery::stresses(const Eigen::MatrixXcd& displacement,
                                                        std::span<const int> harmonics) const {
  if (!stress_operator_) {
    throw std::logic_error("BodyRecovery::stresses: built without options.stresses");
  }
  std::vector<ComplexStressMatrix> S = stress_operator_->apply(displacement);
  if (cyclic_) {
    if (static_cast<Eigen::Index>(harmonics.size()) != displacement.cols()) {
      throw std::logic_error("BodyRecovery::stresses: a cyclic sector needs the harmonics");
    }
    cyclic_->average_boundary_stresses(S, harmonics, elements_at_node_);
  }
  return S;
}

}  // namespace stickslip
