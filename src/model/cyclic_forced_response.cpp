#include "model/cyclic_forced_response.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <string>
#include <utility>

#include <fmt/core.h>

#include "core/errors.h"
#include "core/types.h"
#include "fe/assembly.h"
#include "model/rotation_case.h"

namespace stickslip {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::optional<CyclicForcedResponse> cyclic_forced_response(const CaseDefinition& def) {
  // The body named in messages: the first with boundaries (the blade, the disk), else the first.
  std::string name;
  for (const auto& [body, bd] : def.bodies) {
    if (bd.cyclic &&
        (name.empty() || (!bd.cyclic->low.empty() && def.bodies.at(name).cyclic->low.empty())))
      name = body;
  }
  for (size_t i = 0; i < def.excitation.size(); ++i) {
    const ExcitationDefinition& e = def.excitation[i];
    if (e.engine_order >= 0 && !(def.bodies.count(e.body) && def.bodies.at(e.body).cyclic)) {
      throw InvalidInput(def.where(fmt::format("excitation[{}].engine_order", i)),
                         "body " + e.body +
                             " is not a cyclic sector: an engine order is the "
                             "travelling wave of a cyclic body (bodies.B.cyclic)");
    }
  }
  for (const ContactDefinition& c : def.contacts) {
    for (const std::string& b : {c.body_a, c.body_b}) {
      if (c.neighbour != 0 && !(def.bodies.count(b) && def.bodies.at(b).cyclic)) {
        throw InvalidInput(def.where("contacts." + c.name + ".neighbour"),
                           "contact " + c.name + ": body " + b +
                               " is not a cyclic sector (bodies." + b +
                               ".cyclic): it has no neighbour sector");
      }
    }
  }
  if (def.recovery.annulus && name.empty()) {
    throw InvalidInput(def.where("recovery.annulus"),
                       "the annulus is recovered from a cyclic sector (bodies.B.cyclic), and "
                       "this case has none");
  }
  if (name.empty()) return std::nullopt;
  const BodyDefinition& bd = def.bodies.at(name);
  // Every body is a body of the sector (a blade, a disk, a damper): the same N and axis.
  const Eigen::Vector3d direction(bd.cyclic->axis_direction[0], bd.cyclic->axis_direction[1],
                                  bd.cyclic->axis_direction[2]);
  const Eigen::Vector3d point(bd.cyclic->axis_point[0], bd.cyclic->axis_point[1],
                              bd.cyclic->axis_point[2]);
  std::vector<std::string> bodies;
  for (const auto& [other, obd] : def.bodies) {
    bodies.push_back(other);
    if (!obd.cyclic) {
      throw InvalidInput(def.where("bodies." + other),
                         "body " + other + ": in a case with a cyclic sector (body " + name +
                             ") every body is a body of the sector: give it `cyclic: {sectors: " +
                             std::to_string(bd.cyclic->sectors) +
                             ", axis}` (without low and high when it crosses no sector "
                             "boundary, e.g. a damper between two blades)");
    }
    if (other == name) continue;
    const CyclicDefinition& oc = *obd.cyclic;
    if (oc.sectors != bd.cyclic->sectors) {
      throw InvalidInput(def.where("bodies." + other + ".cyclic.sectors"),
                         fmt::format("body {} is one of {} sectors, body {} of {}: the bodies of "
                                     "a sector share N",
                                     other, oc.sectors, name, bd.cyclic->sectors));
    }
    // The same axis: parallel, same sense, and through the same line (a point within the
    // matching tolerance; the directions are unit vectors, checked to round-off).
    constexpr double kParallel = 1e-9;
    const Eigen::Vector3d d(oc.axis_direction[0], oc.axis_direction[1], oc.axis_direction[2]);
    const Eigen::Vector3d x(oc.axis_point[0], oc.axis_point[1], oc.axis_point[2]);
    const Eigen::Vector3d off = (x - point) - (x - point).dot(direction) * direction;
    if ((d - direction).norm() > kParallel ||
        off.norm() > std::min(oc.tolerance, bd.cyclic->tolerance)) {
      throw InvalidInput(
          def.where("bodies." + other + ".cyclic.axis"),
          fmt::format("body {}'s cyclic axis (point ({:.6g}, {:.6g}, {:.6g}), "
                      "direction ({:.6g}, {:.6g}, {:.6g})) is not body {}'s (point "
                      "({:.6g}, {:.6g}, {:.6g}), direction ({:.6g}, {:.6g}, "
                      "{:.6g})): the bodies of a sector share the axis",
                      other, x.x(), x.y(), x.z(), d.x(), d.y(), d.z(), name, point.x(), point.y(),
                      point.z(), direction.x(), direction.y(), direction.z()));
    }
  }
  int first = -1, engine_order = 0;
  for (size_t i = 0; i < def.excitation.size(); ++i) {
    const ExcitationDefinition& e = def.excitation[i];
    const std::string where = fmt::format("excitation[{}]", i);
    if (e.engine_order < 0) {
      throw InvalidInput(def.where(where),
                         "body " + name +
                             " is a cyclic sector: give the excitation's "
                             "engine_order (EO: sector j is loaded with this force "
                             "times e^{+ik EO 2πj/N}; docs/cyclic.md)");
    }
    if (first >= 0 && e.engine_order != def.excitation[static_cast<size_t>(first)].engine_order) {
      throw InvalidInput(def.where(where + ".engine_order"),
                         fmt::format("engine order {} differs from excitation[{}]'s {}: one "
                                     "travelling wave at a time",
                                     e.engine_order, first,
                                     def.excitation[static_cast<size_t>(first)].engine_order));
    }
    if (first < 0) first = static_cast<int>(i);
    engine_order = e.engine_order;
  }
  for (const std::string& b : bodies) {
    if (def.bodies.at(b).modal_damping_ratio > 0.0) {
      throw InvalidInput(def.where("bodies." + b + ".modal_damping_ratio"),
                         "body " + b +
                             ": a cyclic sector takes Rayleigh damping only "
                             "(damping.alpha, damping.beta), for now");
    }
  }
  const AnalysisDefinition& an = def.analysis;
  if (an.method == SweepMethod::kNonlinearMode) {
    throw InvalidInput(def.where("analysis.method"),
                       "the nonlinear mode of a cyclic sector is not computed yet");
  }
  if (an.frequency.kind == FrequencyDefinition::Kind::kAroundMode) {
    throw InvalidInput(def.where("analysis.frequency.around_mode"),
                       "a cyclic sector's window is given in Hz (start_hz, stop_hz): the stuck "
                       "modes of a nodal diameter are not computed yet (`stickslip modes` lists "
                       "the free sector's modes per nodal diameter)");
  }
  if (an.stability) {
    throw InvalidInput(def.where("analysis.stability"),
                       "Hill's stability of a cyclic sector's travelling wave is not computed yet");
  }
  const RecoveryDefinition& rec = def.recovery;
  if (rec.points != RecoveryPoints::kNone) {
    if (rec.method != RecoveryMethod::kDirect) {
      throw InvalidInput(def.where("recovery.method"),
                         "body " + name +
                             " is a cyclic sector: its recovery is the direct solve of each "
                             "harmonic's nodal diameter (recovery.method: direct)");
    }
    for (const auto& [key, on] : {std::pair<const char*, bool>{"apdl_macro", def.output.apdl_macro},
                                  {"calculix_deck", def.output.calculix_deck}}) {
      if (on) {
        throw InvalidInput(def.where(std::string("output.") + key),
                           "body " + name +
                               " is a cyclic sector: its loads alone, without the cyclic "
                               "constraint of each harmonic's nodal diameter, would not "
                               "reproduce its response in another program");
      }
    }
  }
  if (rec.annulus && rec.points == RecoveryPoints::kNone) {
    throw InvalidInput(def.where("recovery.annulus"),
                       "the annulus is built from the recovered points, and recovery.points is "
                       "none");
  }
  if (rec.annulus && !def.output.vtu) {
    throw InvalidInput(def.where("recovery.annulus"),
                       "the annulus is written as a ParaView file (output.vtu: true), and "
                       "output.vtu is false");
  }
  CyclicForcedResponse out;
  out.body = name;
  out.bodies = bodies;
  out.engine_order = engine_order;
  out.symmetry.sectors = bd.cyclic->sectors;
  out.symmetry.axis_point = {bd.cyclic->axis_point[0], bd.cyclic->axis_point[1],
                             bd.cyclic->axis_point[2]};
  out.symmetry.axis_direction = {bd.cyclic->axis_direction[0], bd.cyclic->axis_direction[1],
                                 bd.cyclic->axis_direction[2]};
  return out;
}

std::vector<int> reached_nodal_diameters(const CaseDefinition& def, int engine_order, int sectors) {
  std::set<int> h{0};
  for (int k : def.analysis.harmonics)
    h.insert(travelling_wave_nodal_diameter(k, engine_order, sectors, nullptr));
  return {h.begin(), h.end()};
}

std::map<int, CyclicReducedSector> reduce_cyclic_body(const CaseDefinition& def,
                                                      const CaseBody& resolved, PreparedBody& body,
                                                      const std::vector<int>& diameters,
                                                      const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string& name = body.name;
  const BodyDefinition& bd = def.bodies.at(name);
  const std::string key = "bodies." + name;
  STICKSLIP_VERIFY(resolved.cyclic.has_value(), "reduce_cyclic_body: not a cyclic body");
  try {
    body.constraints = body_constraints(resolved, body.mesh);
  } catch (const InvalidInput& e) {
    throw InvalidInput(def.where(key + (resolved.supports.empty() ? ".clamp" : ".supports")),
                       "body " + name + ": " + e.message());
  }
  if (body.constraints.has_dependents()) {
    throw InvalidInput(def.where(key + (resolved.supports.empty() ? ".cyclic" : ".supports")),
                       "body " + name +
                           ": a cyclic sector takes clamps and supports along the global axes "
                           "only, for now (an *EQUATION or a support in a local frame would have "
                           "to be repeated in every sector)");
  }
  std::vector<int> clamped;
  for (int d = 0; d < body.constraints.num_dofs(); ++d) {
    if (body.constraints.is_clamped(d)) clamped.push_back(d);
  }
  std::set<int> high;
  for (const auto& [lo, hi] : resolved.cyclic_pairs) high.insert(hi);
  std::vector<int> masters;  // full DOFs, node by node (x, y, z)
  for (int n : resolved.masters) {
    const auto asked = resolved.master_keys.find(n);
    const std::string master_key = asked == resolved.master_keys.end() ? key : asked->second;
    if (high.count(n)) {
      throw InvalidInput(def.where(master_key),
                         fmt::format("node {} of cyclic body {} is on its high boundary, which "
                                     "is the next sector's low boundary: name its low partner "
                                     "instead (the sector's own copy of that node)",
                                     body.mesh.node_ids[n], name));
    }
    for (int dir = 0; dir < 3; ++dir) {
      if (body.constraints.is_constrained(dof_of(n, dir))) {
        throw InvalidInput(
            def.where(key + (resolved.supports.empty() ? ".clamp" : ".supports")),
            fmt::format("node {} of body {} is both clamped or supported (direction {}) and a "
                        "master (contact, forced or listed) node",
                        body.mesh.node_ids[n], name, "xyz"[dir]));
      }
      masters.push_back(dof_of(n, dir));
    }
  }
  SparseMatrix K, M;
  assemble_stiffness_mass(body.mesh, body.material,
                          AssemblyOptions{.mass_integration = bd.mass_rule}, &K, &M);
  if (def.rotation) {  // the spinning sector's stiffness (model/rotation_case.h)
    const SectorBoundary sector{resolved.cyclic_pairs, clamped, *resolved.cyclic};
    add_rotation_stiffness(def, name, body.mesh, body.material, body.constraints, &sector, M, K);
  }
  std::map<int, CyclicReducedSector> out;
  for (int h : diameters) {
    CyclicSectorProblem p;
    try {
      p = cyclic_sector_problem(K, M, resolved.cyclic_pairs, clamped, *resolved.cyclic, h);
    } catch (const InvalidInput& e) {
      throw InvalidInput(def.where(key + ".cyclic"), "body " + name + ": " + e.message());
    }
    std::vector<int> b;
    for (int d : masters) b.push_back(p.independent_index(d));
    const int interior = static_cast<int>(p.independent.size() - b.size());
    CraigBamptonOptions options;
    options.num_modes = std::min(bd.modes, std::max(0, interior));
    options.keep_basis = false;
    if (progress) {
      progress(fmt::format("reduce {}: nodal diameter {} ({} masters, {} modes)", name, h,
                           resolved.masters.size(), options.num_modes));
    }
    CyclicReducedSector r = cyclic_craig_bampton(p.K, p.M, p.doubled, h, b, options);
    if (!r.summary.ok()) {
      throw InvalidInput(def.where(key), fmt::format("Craig–Bampton reduction of cyclic body {} "
                                                     "for nodal diameter {} failed: {}",
                                                     name, h, r.summary.message));
    }
    out.emplace(h, std::move(r));
  }
  // Diameter 0 is the body's ordinary reduced model: masters, then the modal coordinates.
  const CyclicReducedSector& r0 = out.at(0);
  body.reduced.K = r0.K.real();
  body.reduced.M = r0.M.real();
  body.reduced.dofs.clear();
  for (int d : masters) {
    ReducedDof dof;
    dof.kind = ReducedDof::Kind::kPhysical;
    dof.node_index = d / 3;
    dof.direction = d % 3;
    dof.full_dof = d;
    dof.node_id = body.mesh.node_ids[d / 3];
    body.reduced.dofs.push_back(dof);
  }
  for (Eigen::Index j = 0; j < r0.mode_eigenvalues.size(); ++j) {
    ReducedDof dof;
    dof.kind = ReducedDof::Kind::kModal;
    dof.mode = static_cast<int>(j);
    dof.frequency_hz = std::sqrt(std::max(r0.mode_eigenvalues[j], 0.0)) / (2 * kPi);
    body.reduced.dofs.push_back(dof);
  }
  body.K = std::make_shared<const SparseMatrix>(std::move(K));
  body.M = std::make_shared<const SparseMatrix>(std::move(M));
  body.T = nullptr;
  body.cyclic = resolved.cyclic;
  body.cyclic_pairs = resolved.cyclic_pairs;
  body.seconds_reduction = seconds_since(t0);
  return out;
}

TravellingWave cyclic_travelling_wave(
    const CaseDefinition& def, const CyclicForcedResponse& cyclic, const PreparedModel& model,
    const std::map<std::string, std::map<int, CyclicReducedSector>>& reductions) {
  TravellingWave w;
  w.sectors = cyclic.symmetry.sectors;
  w.engine_order = cyclic.engine_order;
  w.rotation = cyclic.symmetry.rotation();
  // The assembled model of diameter h: each body with boundaries by its reduction of h, each
  // body without by its ordinary reduced model (the same for every diameter), block diagonal in
  // the bodies' order of the assembled reduced model.
  const auto assembled = [&](int h) {
    const int n = model.num_dofs;
    Eigen::MatrixXcd K = Eigen::MatrixXcd::Zero(n, n), M = Eigen::MatrixXcd::Zero(n, n);
    for (const PreparedBody& body : model.bodies) {
      const int m = body.reduced.size();
      const auto it = reductions.find(body.name);
      if (it == reductions.end()) {
        K.block(body.offset, body.offset, m, m) = body.reduced.K.cast<std::complex<double>>();
        M.block(body.offset, body.offset, m, m) = body.reduced.M.cast<std::complex<double>>();
        continue;
      }
      const CyclicReducedSector& r = it->second.at(h);
      STICKSLIP_VERIFY(r.K.rows() == m && r.M.rows() == m,
                       fmt::format("cyclic_travelling_wave: body {}'s model of diameter {} has "
                                   "{} DOFs, its diameter-0 model {}",
                                   body.name, h, r.K.rows(), m));
      K.block(body.offset, body.offset, m, m) = r.K;
      M.block(body.offset, body.offset, m, m) = r.M;
    }
    return complex_modal_model_from_matrices(K, M, def.damping.alpha, def.damping.beta);
  };
  std::map<int, ComplexModalModel> by_diameter;
  for (int k : def.analysis.harmonics) {
    bool conjugate = false;
    const int h = travelling_wave_nodal_diameter(k, w.engine_order, w.sectors, &conjugate);
    auto it = by_diameter.find(h);
    if (it == by_diameter.end()) it = by_diameter.emplace(h, assembled(h)).first;
    ComplexModalModel m = it->second;
    if (conjugate) m.Phi = m.Phi.conjugate().eval();
    w.harmonics[k] = std::move(m);
  }
  return w;
}

}  // namespace stickslip
