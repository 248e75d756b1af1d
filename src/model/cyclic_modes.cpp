#include "model/cyclic_modes.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <fmt/core.h>

#include "core/errors.h"
#include "core/types.h"
#include "fe/assembly.h"
#include "fe/cyclic.h"
#include "model/rotation_case.h"

namespace stickslip {
namespace {

// Real forms up to this many rows are solved densely (every eigenpair, O(n³): 0.1 s at 500);
// larger ones by shift-invert Lanczos on the sparse factor.
constexpr int kDenseRows = 500;
// Vectors per Lanczos step for the doubled real form, whose eigenvalues are all double: a block
// of at least 2 finds both copies (a single-vector Krylov space sees one in exact arithmetic).
constexpr int kPairBlockSize = 4;
// The two copies of a double eigenvalue of the real form agree to the eigen-solve's accuracy
// (tolerance 1e-10 on the Ritz values); 1e-6 relative leaves room for round-off and still
// separates genuinely distinct modes of the sector. Rigid-body modes (ω² ≈ 0) are compared
// against kRigidScale times the largest eigenvalue found instead.
constexpr double kPairTolerance = 1e-6;
constexpr double kRigidScale = 1e-9;

// Every eigenvalue of the real form once: for the doubled form, consecutive pairs must agree.
// Returns the frequencies (Hz) of `wanted` modes at most, and fails the summary when a pair does
// not match (a copy missed by the eigen-solve: the table would skip or repeat a mode).
Eigen::VectorXd distinct_frequencies(const ModalResult& r, bool doubled, int wanted,
                                     ModalSummary* summary, int h) {
  const Eigen::VectorXd& l = r.eigenvalues;
  const double largest = l.size() > 0 ? l.cwiseAbs().maxCoeff() : 0.0;
  std::vector<double> out;
  const Eigen::Index step = doubled ? 2 : 1;
  for (Eigen::Index j = 0; j + step <= l.size() && static_cast<int>(out.size()) < wanted;
       j += step) {
    if (doubled) {
      const double scale = std::max(std::abs(l(j + 1)), kRigidScale * largest);
      if (std::abs(l(j + 1) - l(j)) > kPairTolerance * scale) {
        summary->termination = ModalTermination::kNotConverged;
        summary->message = fmt::format(
            "nodal diameter {}: the eigenvalues {} and {} of its real form should be one double "
            "eigenvalue (the two waves of one mode) but differ: the eigen-solve missed a copy",
            h, l(j), l(j + 1));
        break;
      }
    }
    out.push_back(std::sqrt(std::max(l(j), 0.0)) / (2 * kPi));
  }
  return Eigen::Map<const Eigen::VectorXd>(out.data(), static_cast<Eigen::Index>(out.size()));
}

NodalDiameterModes diameter_modes(const CyclicSectorProblem& p, int modes_per_diameter) {
  NodalDiameterModes out;
  out.nodal_diameter = p.nodal_diameter;
  out.doubled = p.doubled;
  const int size = static_cast<int>(p.K.rows());
  const int per_mode = p.doubled ? 2 : 1;
  const int wanted = std::min(modes_per_diameter * per_mode, size);
  ModalResult r;
  if (size <= kDenseRows || wanted >= size) {
    r = dense_modes(p.K, p.M);
  } else {
    ModalOptions options;
    options.num_modes = wanted;
    options.block_size = p.doubled ? kPairBlockSize : 0;
    r = solve_modes(p.K, p.M, options);
  }
  out.summary = r.summary;
  if (!r.summary.ok()) return out;
  out.frequencies_hz =
      distinct_frequencies(r, p.doubled, wanted / per_mode, &out.summary, p.nodal_diameter);
  return out;
}

}  // namespace

CyclicModes cyclic_modes(const CaseDefinition& def, int modes_per_diameter,
                         const ProgressFn& progress, ModelCache* cache) {
  require(modes_per_diameter >= 1, "modes_per_diameter", std::to_string(modes_per_diameter),
          "must be >= 1");
  std::string cyclic_name;
  for (const auto& [name, bd] : def.bodies) {
    if (bd.cyclic) cyclic_name = name;
  }
  if (cyclic_name.empty()) throw InvalidInput("cyclic modes: the case has no cyclic body");
  for (const auto& [name, bd] : def.bodies) {
    if (name == cyclic_name) continue;
    throw InvalidInput(def.where("bodies." + name),
                       "body " + name + ": a case with a cyclic sector (body " + cyclic_name +
                           ") holds that body only, for now (sectors made of several bodies come "
                           "with the forced response)");
  }
  if (!def.contacts.empty()) {
    throw InvalidInput(def.where("contacts." + def.contacts.front().name),
                       "contact " + def.contacts.front().name +
                           ": the modes per nodal diameter of cyclic body " + cyclic_name +
                           " take no contacts yet (contacts of a sector, with itself or with its "
                           "neighbour, come with the forced response)");
  }
  CaseBodies resolved = resolve_case_bodies(def, progress, cache);
  const CaseBody& body = resolved.bodies.front();
  const BodyDefinition& bd = def.bodies.at(cyclic_name);
  const std::string key = "bodies." + cyclic_name;
  DofMap constraints;
  try {
    constraints = body_constraints(body, body.mesh);
  } catch (const InvalidInput& e) {
    throw InvalidInput(def.where(key + (body.supports.empty() ? ".clamp" : ".supports")),
                       "body " + cyclic_name + ": " + e.message());
  }
  if (constraints.has_dependents()) {
    throw InvalidInput(def.where(key + (body.supports.empty() ? ".cyclic" : ".supports")),
                       "body " + cyclic_name +
                           ": a cyclic sector takes clamps and supports along the global axes "
                           "only, for now (an *EQUATION or a support in a local frame would have "
                           "to be repeated in every sector)");
  }
  std::vector<int> clamped;
  for (int d = 0; d < constraints.num_dofs(); ++d) {
    if (constraints.is_clamped(d)) clamped.push_back(d);
  }
  SparseMatrix K, M;
  if (progress) progress("assembling body " + cyclic_name);
  assemble_stiffness_mass(body.mesh, body.material,
                          AssemblyOptions{.mass_integration = bd.mass_rule}, &K, &M);
  if (def.rotation) {  // the spinning sector's stiffness (model/rotation_case.h)
    const SectorBoundary sector{body.cyclic_pairs, clamped, *body.cyclic};
    add_rotation_stiffness(def, cyclic_name, body.mesh, body.material, constraints, &sector, M, K);
  }

  CyclicModes out;
  out.body = cyclic_name;
  out.sectors = body.cyclic->sectors;
  for (int h = 0; 2 * h <= out.sectors; ++h) {
    CyclicSectorProblem problem;
    try {
      problem = cyclic_sector_problem(K, M, body.cyclic_pairs, clamped, *body.cyclic, h);
    } catch (const InvalidInput& e) {
      throw InvalidInput(def.where(key + ".cyclic"), "body " + cyclic_name + ": " + e.message());
    }
    out.sector_dofs = static_cast<int>(problem.independent.size());
    if (progress) {
      progress(fmt::format("nodal diameter {} of {}: {} DOFs{}", h, out.sectors / 2,
                           problem.K.rows(),
                           problem.doubled ? " (real form of the complex field)" : ""));
    }
    out.diameters.push_back(diameter_modes(problem, modes_per_diameter));
  }
  return out;
}

}  // namespace stickslip
