#include "model/recovery_loads.h"

#include <cmath>
#include <complex>
#include <limits>
#include <map>

#include "core/errors.h"
#include "core/types.h"
#include "hbm/travelling_wave.h"

namespace stickslip {
namespace {

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

}  // namespace

std::vector<int> recovery_points(const CaseDefinition& def, const PreparedModel& model,
                                 const FrequencyResponse& response) {
  const auto& points = response.points;
  std::vector<int> out;
  const RecoveryPoints mode = def.recovery.points;
  if (mode == RecoveryPoints::kNone || points.empty()) return out;
  if (mode == RecoveryPoints::kAll) {
    for (size_t i = 0; i < points.size(); ++i) {
      if (points[i].converged) out.push_back(static_cast<int>(i));
    }
    return out;
  }
  if (mode == RecoveryPoints::kPeak) {
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

Eigen::MatrixXcd master_loads(const PreparedModel& model, const PreparedBody& body,
                              const std::vector<int>& harmonics, const FrequencyPoint& p) {
  const int nh = static_cast<int>(harmonics.size());
  const int n = body.reduced.size();
  // Excitation (and preload loads) on the master DOFs.
  Eigen::MatrixXcd F = Eigen::MatrixXcd::Zero(n, nh);
  for (int h = 0; h < nh; ++h) {
    const auto it = model.excitation.harmonics.find(harmonics[h]);
    if (it == model.excitation.harmonics.end()) continue;
    for (int j = 0; j < n; ++j) {
      if (body.reduced.dofs[j].kind == ReducedDof::Kind::kPhysical) {
        F(j, h) += it->second(body.offset + j);
      }
    }
  }
  // Contact forces.
  for (size_t q = 0; q < model.pairs.size(); ++q) {
    const ContactPair& pair = model.pairs[q];
    // Per frame column, Rᵀ f: the force on B for node B's (and, negated, node A's) DOFs; for a
    // mortar point's B columns −Φ_k times it, so node k of B receives +Φ_k times the force on B.
    // From force_local (force_global read back from contact_forces.csv has 3 rows only).
    const Eigen::MatrixXcd fg =
        pair.frame.transpose().cast<std::complex<double>>() * p.pairs[q].force_local;
    // A cyclic sector's pair with the neighbour sector s (model.wave): this sector's node B
    // receives the force of the pair of sector −s, rotated back, with the conjugate phase,
    // e^{−iσ_k s} (R^s)ᵀ Rᵀf (hbm/travelling_wave.h: −B_kᴴ f).
    Eigen::MatrixXcd fg_b = fg;
    if (pair.b_sector != 0 && model.wave) {
      fg_b = sector_rotation(model.wave->rotation, pair.b_sector)
                 .transpose()
                 .cast<std::complex<double>>() *
             fg;
      for (int h = 0; h < nh; ++h) {
        fg_b.col(h) *= std::polar(1.0, -model.wave->phase(harmonics[h]) * pair.b_sector);
      }
    }
    for (int d = 0; d < static_cast<int>(fg.rows()); ++d) {
      for (int side = 0; side < 2; ++side) {
        const std::vector<int>& dofs = side == 0 ? pair.dofs_a : pair.dofs_b;
        if (dofs.empty() || dofs[d] < body.offset || dofs[d] >= body.offset + n) continue;
        const double sign = side == 0 ? -1.0 : 1.0;  // A receives the negative
        F.row(dofs[d] - body.offset) += sign * (side == 0 ? fg : fg_b).row(d);
      }
    }
  }
  // Harmonic 0 is real by construction; drop round-off in its imaginary part.
  for (int h = 0; h < nh; ++h) {
    if (harmonics[h] == 0) F.col(h) = F.col(h).real().cast<std::complex<double>>();
  }
  return F;
}

Eigen::MatrixXcd recovery_loads(const PreparedModel& model, const PreparedBody& body,
                                const std::vector<int>& harmonics, const FrequencyPoint& p) {
  const Eigen::MatrixXcd reduced = master_loads(model, body, harmonics, p);
  Eigen::MatrixXcd F = Eigen::MatrixXcd::Zero(body.mesh.num_dofs(), reduced.cols());
  for (int j = 0; j < body.reduced.size(); ++j) {
    const ReducedDof& d = body.reduced.dofs[j];
    if (d.kind == ReducedDof::Kind::kPhysical) F.row(d.full_dof) += reduced.row(j);
  }
  return F;
}

std::pair<Mesh, Eigen::MatrixXcd> mapped_master_loads(const PreparedModel& model,
                                                      const PreparedBody& body,
                                                      const std::vector<int>& harmonics,
                                                      const FrequencyPoint& p) {
  const Eigen::MatrixXcd reduced = master_loads(model, body, harmonics, p);
  std::map<int, int> node_of_id;  // mapping node number -> node index (ascending numbers)
  for (const ReducedDof& d : body.reduced.dofs) {
    if (d.kind == ReducedDof::Kind::kPhysical) node_of_id.emplace(d.node_id, 0);
  }
  Mesh mesh;
  for (auto& [id, index] : node_of_id) index = mesh.add_node(id, Eigen::Vector3d::Zero());
  Eigen::MatrixXcd F = Eigen::MatrixXcd::Zero(mesh.num_dofs(), reduced.cols());
  for (int j = 0; j < body.reduced.size(); ++j) {
    const ReducedDof& d = body.reduced.dofs[j];
    if (d.kind != ReducedDof::Kind::kPhysical) continue;
    F.row(3 * node_of_id.at(d.node_id) + d.direction) += reduced.row(j);
  }
  return {std::move(mesh), std::move(F)};
}

}  // namespace stickslip
