#include "cli/recovery_stage.h"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "cli/progress.h"
#include "core/errors.h"
#include "core/types.h"
#include "fe/stress.h"
#include "io/apdl_macro.h"
#include "io/atomic_file.h"
#include "io/calculix_deck.h"
#include "io/vtu_writer.h"
#include "mesh/mesh.h"
#include "recovery/harmonic_response.h"
#include "recovery/stress_envelope.h"

namespace stickslip {
namespace {

const char* kAxes[3] = {"x", "y", "z"};

// Response measure of a point for "peak": the norm of harmonic-1 (first dynamic harmonic)
// amplitudes of the FRF DOFs, or of every physical master DOF when none is listed.
double peak_measure(const CaseDefinition& def, const PreparedModel& model,
                    const FrequencyPoint& p) {
  const int h = p.master.cols() > 1 ? 1 : 0;
  double s = 0;
  if (!def.output.frf.empty()) {
    for (const ResponseDofDefinition& r : def.output.frf) {
      const int b = model.body_index(r.body);
      const int g = b < 0 ? -1 : model.bodies[b].global_dof(r.node, r.direction);
      if (g >= 0) s += std::norm(p.master(g, h));
    }
    return s;
  }
  for (const PreparedBody& body : model.bodies) {
    for (const auto& [key, g] : body.master_dof) s += std::norm(p.master(g, h));
  }
  return s;
}

// The physical (master) DOFs of a body in the order of body.reduced: their full-model DOF and
// their DOF in the assembled reduced model.
struct MasterDofs {
  std::vector<int> full, reduced;
};
MasterDofs master_dofs(const PreparedBody& body) {
  MasterDofs out;
  for (int j = 0; j < body.reduced.size(); ++j) {
    const ReducedDof& d = body.reduced.dofs[j];
    if (d.kind == ReducedDof::Kind::kPhysical) {
      out.full.push_back(d.full_dof);
      out.reduced.push_back(body.offset + j);
    }
  }
  return out;
}

}  // namespace

std::vector<int> recovery_points(const CaseDefinition& def, const PreparedModel& model,
                                 const FrequencyResponse& response) {
  const auto& points = response.points;
  std::vector<int> out;
  const std::string& mode = def.recovery.points;
  if (mode == "none" || points.empty()) return out;
  if (mode == "all") {
    for (size_t i = 0; i < points.size(); ++i) {
      if (points[i].converged) out.push_back(static_cast<int>(i));
    }
    return out;
  }
  if (mode == "peak") {
    int best = -1;
    double best_value = -1;
    for (size_t i = 0; i < points.size(); ++i) {
      if (!points[i].converged) continue;
      const double v = peak_measure(def, model, points[i]);
      if (v > best_value) best_value = v, best = static_cast<int>(i);
    }
    if (best >= 0) out.push_back(best);
    return out;
  }
  // A list of frequencies: the nearest converged point to each.
  for (double hz : def.recovery.frequencies_hz) {
    int best = -1;
    double best_distance = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < points.size(); ++i) {
      const double d = std::abs(rad_s_to_hz(points[i].omega) - hz);
      if (points[i].converged && d < best_distance) best_distance = d, best = static_cast<int>(i);
    }
    if (best >= 0 && (out.empty() || out.back() != best)) out.push_back(best);
  }
  return out;
}

Eigen::MatrixXcd recovery_loads(const PreparedModel& model, const PreparedBody& body,
                                const std::vector<int>& harmonics, const FrequencyPoint& p) {
  const int nh = static_cast<int>(harmonics.size());
  const auto [full_dofs, reduced_dofs] = master_dofs(body);
  // Loads: excitation (and preload loads) on the master DOFs, plus contact forces.
  Eigen::MatrixXcd F = Eigen::MatrixXcd::Zero(body.mesh.num_dofs(), nh);
  for (int h = 0; h < nh; ++h) {
    const auto it = model.excitation.harmonics.find(harmonics[h]);
    if (it == model.excitation.harmonics.end()) continue;
    for (size_t i = 0; i < full_dofs.size(); ++i) {
      F(full_dofs[i], h) += it->second(reduced_dofs[i]);
    }
  }
  for (size_t q = 0; q < model.pairs.size(); ++q) {
    const ContactPair& pair = model.pairs[q];
    const Eigen::MatrixXcd& fg = p.pairs[q].force_global;  // force on B, 3 x nh
    for (int d = 0; d < 3; ++d) {
      for (int side = 0; side < 2; ++side) {
        const std::vector<int>& dofs = side == 0 ? pair.dofs_a : pair.dofs_b;
        if (dofs.empty() || dofs[d] < body.offset || dofs[d] >= body.offset + body.reduced.size()) {
          continue;
        }
        const int full = body.reduced.dofs[dofs[d] - body.offset].full_dof;
        const double sign = side == 0 ? -1.0 : 1.0;  // A receives the negative
        F.row(full) += sign * fg.row(d);
      }
    }
  }
  // Harmonic 0 is real by construction; drop round-off in its imaginary part.
  for (int h = 0; h < nh; ++h) {
    if (harmonics[h] == 0) F.col(h) = F.col(h).real().cast<std::complex<double>>();
  }
  return F;
}

std::string write_apdl_loads(const std::filesystem::path& dir, const CaseDefinition& def,
                             const PreparedBody& body, int point, double f_hz,
                             const std::vector<int>& harmonics, const Eigen::MatrixXcd& F) {
  ApdlMacroOptions o;
  o.frequency_hz = f_hz;
  o.harmonics = harmonics;
  o.alpha = def.damping.alpha;
  o.beta = def.damping.beta;
  const std::string path = (dir / fmt::format("loads_p{}_{}.mac", point, body.name)).string();
  write_apdl_macro(path, body.mesh, F, o);
  return path;
}

std::string write_calculix_loads(const std::filesystem::path& dir, const CaseDefinition& def,
                                 const PreparedBody& body, int point, double f_hz,
                                 const std::vector<int>& harmonics, const Eigen::MatrixXcd& F) {
  CalculixDeckOptions o;
  o.youngs_modulus = body.material.youngs_modulus;
  o.poisson_ratio = body.material.poisson_ratio;
  o.density = body.material.density;
  for (int node = 0; node < body.mesh.num_nodes(); ++node) {
    if (body.constraints.is_clamped(dof_of(node, 0))) o.clamped_nodes.push_back(node);
  }
  o.alpha = def.damping.alpha;
  o.beta = def.damping.beta;
  o.frequency_hz = f_hz;
  o.harmonics = harmonics;
  o.num_modes = std::min(def.recovery.modes, body.constraints.num_free() - 1);
  const std::string path = (dir / fmt::format("recovery_p{}_{}.inp", point, body.name)).string();
  write_calculix_deck(path, body.mesh, F, o);
  return path;
}

void run_recovery(const std::filesystem::path& dir, const CaseDefinition& def,
                  const PreparedModel& model, const FrequencyResponse& response,
                  const std::vector<int>& points,
                  const std::function<void(const std::string&)>& progress,
                  std::vector<PlotSeries>* full_frf) {
  if (points.empty()) return;
  const std::vector<int>& harmonics = response.harmonics;
  const int nh = static_cast<int>(harmonics.size());
  const std::string& method = def.recovery.method;
  const RayleighDamping damping{def.damping.alpha, def.damping.beta};
  const bool want_stress = std::find(def.recovery.fields.begin(), def.recovery.fields.end(),
                                     "stress") != def.recovery.fields.end();

  struct Row {
    int point, body, harmonic;
    double max_rel, rms_rel, reference_max, max_abs;
  };
  std::vector<Row> check;
  std::string nodes_csv = "point,body,node,dof,harmonic,real,imag\n";

  const int h1 = nh > 1 ? 1 : 0;  // column of the first dynamic harmonic
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const PreparedBody& body = model.bodies[b];
    if (!body.from_mesh) continue;
    // FRF DOFs of this body: full-model amplitude per recovered point (plotted against the
    // reduced nonlinear curve: the thesis's validation plot).
    std::vector<std::pair<int, int>> frf_dofs;  // (full DOF, index into full_frf)
    if (full_frf) {
      const auto by_id = node_index_by_id(body.mesh);
      for (const ResponseDofDefinition& r : def.output.frf) {
        if (r.body != body.name || !by_id.count(r.node)) continue;
        frf_dofs.emplace_back(dof_of(by_id.at(r.node), r.direction),
                              static_cast<int>(full_frf->size()));
        full_frf->push_back(
            {fmt::format("full model: {} node {} {}", r.body, r.node, kAxes[r.direction]),
             {},
             {},
             "points pt 6 ps 1.3"});
      }
    }
    // Envelope over the recovered points.
    Eigen::VectorXd sweep_vm_max, sweep_vm_alt, sweep_p_max;
    progress(fmt::format("recovery of {} ({} DOFs, {})", body.name, body.mesh.num_dofs(), method));
    std::unique_ptr<HarmonicSolver> solver;
    if (method == "direct") {
      solver = std::make_unique<DirectRecovery>(body.K, body.M, body.constraints, damping);
    } else if (method == "modal") {
      ModalRecoveryOptions o;
      o.num_modes = std::min(def.recovery.modes, body.constraints.num_free() - 1);
      solver = std::make_unique<ModalRecovery>(body.K, body.M, body.constraints, damping, o);
    }
    if (solver && !solver->ok()) {
      throw InvalidInput(def.where("recovery.method"),
                         "recovery of body " + body.name + " failed: " + solver->message());
    }
    const auto [full_dofs, reduced_dofs] = master_dofs(body);
    const int n = body.mesh.num_dofs();
    // Nodal stresses as one sparse operator, built once per body (element by element per point
    // would re-condense every C3D8I at every call).
    std::optional<NodalStressOperator> stress_operator;
    if (want_stress && def.output.vtu) {
      stress_operator.emplace(body.mesh, body.material, AssemblyOptions{});
    }
    RecoverySummary summary;
    for (int pi : points) {
      const FrequencyPoint& p = response.points[pi];
      const Eigen::MatrixXcd F = recovery_loads(model, body, harmonics, p);
      const double f_hz = rad_s_to_hz(p.omega);
      if (def.output.apdl_macro) write_apdl_loads(dir, def, body, pi, f_hz, harmonics, F);
      if (def.output.calculix_deck) {
        write_calculix_loads(dir, def, body, pi, f_hz, harmonics, F);
      }
      const Eigen::MatrixXcd x =
          method == "expansion" ? expand_reduced_response(
                                      body.T, p.master.middleRows(body.offset, body.reduced.size()))
                                : harmonic_response(*solver, F, harmonics, p.omega, &summary);
      if (!summary.ok()) {
        // A singular dynamic stiffness (undamped, exactly at a natural frequency): those
        // harmonics are NaN in every output of this point; the other harmonics are valid.
        stderr_warning(fmt::format("recovery of {} at point {} ({:.6g} Hz): {}", body.name, pi,
                                   rad_s_to_hz(p.omega), summary.message));
      }
      for (const auto& [dof, series] : frf_dofs) {
        (*full_frf)[series].x.push_back(rad_s_to_hz(p.omega));
        (*full_frf)[series].y.push_back(std::abs(x(dof, h1)));
      }
      // Check against the reduced nonlinear response at the master DOFs.
      Eigen::MatrixXcd reduced = Eigen::MatrixXcd::Zero(n, nh);
      for (size_t i = 0; i < full_dofs.size(); ++i)
        reduced.row(full_dofs[i]) = p.master.row(reduced_dofs[i]);
      const ResponseDifference diff = compare_responses(x, reduced, full_dofs);
      for (int h = 0; h < nh; ++h) {
        double ref = 0;
        for (int dof : full_dofs) ref = std::max(ref, std::abs(reduced(dof, h)));
        check.push_back({pi, static_cast<int>(b), harmonics[h], diff.max_relative[h],
                         diff.rms_relative[h], ref, diff.max_absolute[h]});
      }
      // Listed nodes.
      for (int id : def.recovery.nodes) {
        const auto it = std::find(body.mesh.node_ids.begin(), body.mesh.node_ids.end(), id);
        if (it == body.mesh.node_ids.end()) continue;
        const int node = static_cast<int>(it - body.mesh.node_ids.begin());
        for (int d = 0; d < 3; ++d) {
          for (int h = 0; h < nh; ++h) {
            const std::complex<double> v = x(dof_of(node, d), h);
            nodes_csv += fmt::format("{},{},{},{},{},{},{}\n", pi, body.name, id,
                                     kAxes[d], harmonics[h], v.real(), v.imag());
          }
        }
      }
      if (!def.output.vtu) continue;
      VtuData data;
      for (int h = 0; h < nh; ++h) {
        const Eigen::VectorXcd xh = x.col(h);
        const Eigen::MatrixXd re = Eigen::Map<const Eigen::MatrixXd>(
            Eigen::VectorXd(xh.real()).data(), 3, body.mesh.num_nodes());
        const Eigen::MatrixXd im = Eigen::Map<const Eigen::MatrixXd>(
            Eigen::VectorXd(xh.imag()).data(), 3, body.mesh.num_nodes());
        data.point_data.push_back({fmt::format("displacement_h{}_real", harmonics[h]), re});
        data.point_data.push_back({fmt::format("displacement_h{}_imag", harmonics[h]), im});
      }
      if (stress_operator) {
        const std::vector<ComplexStressMatrix> S = stress_operator->apply(x);
        for (int h = 0; h < nh; ++h) {
          // VTU tensors are in ParaView order xx, yy, zz, xy, yz, xz; ours xx, yy, zz, xy, xz, yz.
          Eigen::MatrixXd re = S[h].real(), im = S[h].imag();
          re.row(4).swap(re.row(5));
          im.row(4).swap(im.row(5));
          data.point_data.push_back({fmt::format("stress_h{}_real", harmonics[h]), re});
          data.point_data.push_back({fmt::format("stress_h{}_imag", harmonics[h]), im});
        }
        const StressEnvelope env = stress_envelope(S, harmonics, StressEnvelopeOptions{});
        data.point_data.push_back({"von_mises_max", env.von_mises_max.transpose()});
        data.point_data.push_back({"von_mises_alternating", env.von_mises_alternating.transpose()});
        data.point_data.push_back({"von_mises_mean", env.von_mises_mean.transpose()});
        data.point_data.push_back({"max_principal_max", env.max_principal_max.transpose()});
        if (sweep_vm_max.size() == 0) {
          sweep_vm_max = env.von_mises_max;
          sweep_vm_alt = env.von_mises_alternating;
          sweep_p_max = env.max_principal_max;
        } else {
          sweep_vm_max = sweep_vm_max.cwiseMax(env.von_mises_max);
          sweep_vm_alt = sweep_vm_alt.cwiseMax(env.von_mises_alternating);
          sweep_p_max = sweep_p_max.cwiseMax(env.max_principal_max);
        }
      }
      data.field_data.emplace_back("frequency_hz", rad_s_to_hz(p.omega));
      write_vtu((dir / fmt::format("recovery_p{}_{}.vtu", pi, body.name)).string(), body.mesh,
                data);
    }
    if (points.size() > 1 && sweep_vm_max.size() > 0) {
      VtuData data;
      data.point_data.push_back({"von_mises_max", sweep_vm_max.transpose()});
      data.point_data.push_back({"von_mises_alternating", sweep_vm_alt.transpose()});
      data.point_data.push_back({"max_principal_max", sweep_p_max.transpose()});
      data.field_data.emplace_back("recovered_points", static_cast<double>(points.size()));
      write_vtu((dir / fmt::format("recovery_envelope_{}.vtu", body.name)).string(), body.mesh,
                data);
    }
  }
  write_file_atomically((dir / "recovery_check.csv").string(), [&](std::ostream& out) {
    out << "point,frequency_hz,body,harmonic,reduced_max_m,max_relative,rms_relative,"
           "max_absolute_m\n";
    for (const Row& r : check) {
      fmt::print(out, "{},{:.10g},{},{},{:.6e},{:.6e},{:.6e},{:.6e}\n", r.point,
                 rad_s_to_hz(response.points[r.point].omega), model.bodies[r.body].name, r.harmonic,
                 r.reference_max, r.max_rel, r.rms_rel, r.max_abs);
    }
  });
  if (!def.recovery.nodes.empty()) {
    write_file_atomically((dir / "recovered_nodes.csv").string(),
                          [&](std::ostream& out) { out << nodes_csv; });
  }
}

}  // namespace stickslip
