#include "cli/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <unordered_map>

#include <fmt/core.h>
#include <Eigen/Eigenvalues>

#include "contact/friction_contact.h"
#include "contact/springs.h"
#include "core/errors.h"
#include "core/frame.h"
#include "core/types.h"
#include "fe/assembly.h"
#include "io/ansys_mapping.h"
#include "io/gmsh_mesh.h"
#include "io/inp_reader.h"
#include "io/two_beam_model.h"
#include "mesh/mesh_tools.h"
#include "reduction/craig_bampton.h"

namespace stickslip {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

Eigen::Vector3d vec3(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

Mesh load_mesh(const CaseDefinition& def, const std::string& name, const MeshDefinition& m) {
  const SourceLocation where = def.where("meshes." + name);
  try {
    if (m.source == MeshDefinition::Source::kGenerate) {
      TwoBeamOptions o;
      const TwoBeamDefinition& t = m.two_beam;
      o.arrangement = t.arrangement == "lap" ? TwoBeamOptions::Arrangement::kLap
                                             : TwoBeamOptions::Arrangement::kButt;
      o.beam_length = t.beam_length;
      o.width = t.width;
      o.thickness = t.thickness;
      o.end_length = t.end_length;
      o.box = {t.box[0], t.box[1], t.box[2]};
      o.end_block = {t.end_block[0], t.end_block[1], t.end_block[2]};
      o.thesis_coarse = t.coarse;
      if (!parse_element_type(t.element, &o.element_type)) {
        throw InvalidInput(where, "unknown element type " + t.element);
      }
      return make_two_beam_model(o).mesh;
    }
    if (m.format == "msh") {
      GmshReadOptions o;
      if (!parse_element_type(m.hexahedron8, &o.hexahedron8) ||
          !parse_element_type(m.hexahedron20, &o.hexahedron20)) {
        throw InvalidInput(where, "unknown hexahedron element type");
      }
      return read_gmsh(m.file, o);
    }
    return read_inp(m.file);
  } catch (const InvalidInput& e) {
    if (!e.where().file.empty()) throw;  // a mesh file's own error names its file and line
    throw InvalidInput(where, e.message());
  }
}

// Node indices of a selection in a body's mesh (sets first, then ids, duplicates removed while
// keeping the order).
std::vector<int> resolve_nodes(const CaseDefinition& def, const std::string& key,
                               const PreparedBody& body, const NodeSelection& selection) {
  const SourceLocation where = def.where(key);
  std::vector<int> nodes;
  if (!body.from_mesh) {
    if (!selection.sets.empty()) {
      throw InvalidInput(where, "body " + body.name +
                                    " is given by reduced matrices: select its nodes by id, "
                                    "not by node set");
    }
    return selection.ids;  // node ids stand for themselves
  }
  for (const std::string& set : selection.sets) {
    const auto it = body.mesh.node_sets.find(set);
    if (it == body.mesh.node_sets.end()) {
      std::string known;
      for (const auto& [n, s] : body.mesh.node_sets) known += (known.empty() ? "" : ", ") + n;
      throw InvalidInput(where, "body " + body.name + " has no node set " + set +
                                    " (its node sets: " + known + ")");
    }
    nodes.insert(nodes.end(), it->second.begin(), it->second.end());
  }
  if (!selection.ids.empty()) {
    const auto by_id = node_index_by_id(body.mesh);
    for (int id : selection.ids) {
      const auto it = by_id.find(id);
      if (it == by_id.end()) {
        throw InvalidInput(where, "node " + std::to_string(id) + " is not in body " + body.name);
      }
      nodes.push_back(it->second);
    }
  }
  std::vector<int> unique;
  std::set<int> seen;
  for (int n : nodes) {
    if (seen.insert(n).second) unique.push_back(n);
  }
  return unique;
}

int node_id_of(const PreparedBody& body, int node) {
  return body.from_mesh ? body.mesh.node_ids[node] : node;
}

struct ResolvedContact {
  int body_a = -1, body_b = -1;                 // -1 = ground
  std::vector<std::pair<int, int>> node_pairs;  // node indices (ids for reduced bodies), -1 ground
};

ResolvedContact resolve_contact(const CaseDefinition& def, int c,
                                const std::vector<PreparedBody>& bodies,
                                const std::map<std::string, int>& body_index) {
  const ContactDefinition& cd = def.contacts[c];
  const std::string key = "contacts." + cd.name;
  ResolvedContact rc;
  const auto find_body = [&](const std::string& name) {
    if (name == "ground") return -1;
    const auto it = body_index.find(name);
    if (it == body_index.end()) throw InvalidInput(def.where(key), "unknown body " + name);
    return it->second;
  };
  rc.body_a = find_body(cd.body_a);
  rc.body_b = find_body(cd.body_b);
  if (rc.body_a < 0)
    throw InvalidInput(def.where(key), "the first body of a contact cannot be ground");
  const PreparedBody& A = bodies[rc.body_a];
  if (!cd.pairs.empty() || !cd.pairs_file.empty()) {
    const auto& listed = cd.pairs;  // pairs_file was read into `pairs` by the parser
    for (const auto& p : listed) {
      NodeSelection sa{{}, {p[0]}};
      const int a = resolve_nodes(def, key + ".pairs", A, sa)[0];
      int b = -1;
      if (rc.body_b >= 0) {
        NodeSelection sb{{}, {p[1]}};
        b = resolve_nodes(def, key + ".pairs", bodies[rc.body_b], sb)[0];
      }
      rc.node_pairs.emplace_back(a, b);
    }
    return rc;
  }
  const std::vector<int> nodes_a = resolve_nodes(def, key + ".between", A, cd.nodes_a);
  if (rc.body_b < 0) {
    for (int a : nodes_a) rc.node_pairs.emplace_back(a, -1);
    return rc;
  }
  const PreparedBody& B = bodies[rc.body_b];
  if (!A.from_mesh || !B.from_mesh) {
    throw InvalidInput(def.where(key + ".between"),
                       "pairs between bodies given by matrices must be listed (pairs or "
                       "pairs_file): there are no coordinates to match");
  }
  const std::vector<int> nodes_b = resolve_nodes(def, key + ".between", B, cd.nodes_b);
  try {
    rc.node_pairs = match_coincident_nodes(A.mesh, nodes_a, B.mesh, nodes_b, cd.tolerance);
  } catch (const InvalidInput& e) {
    throw InvalidInput(def.where(key + ".between"),
                       "contact nodes are not coincident within tolerance " +
                           fmt::format("{:g}", cd.tolerance) + " m: " + e.message());
  }
  if (rc.node_pairs.empty()) {
    throw InvalidInput(def.where(key + ".between"), "the contact has no node pairs");
  }
  return rc;
}

// Per-pair parameters (totals divided equally over the pairs).
ContactParametersDefinition per_pair_parameters(const CaseDefinition& def,
                                                const ContactDefinition& cd, int num_pairs) {
  ContactParametersDefinition p = cd.parameters;
  if (cd.parameters_given == ContactDefinition::Parameters::kTotal) {
    if (cd.split != "equal") {
      throw InvalidInput(def.where("contacts." + cd.name + ".total.split"),
                         "split: " + cd.split + " is not supported yet; use split: equal");
    }
    const double n = num_pairs;
    p.kt /= n;
    p.kn /= n;
    p.preload /= n;
    p.k /= n;
    p.k1 /= n;
    p.k3 /= n;
  }
  return p;
}

void reduce_mesh_body(const CaseDefinition& def, const std::string& name, const BodyDefinition& bd,
                      const std::vector<int>& masters, PreparedBody& body) {
  const std::string key = "bodies." + name;
  const auto t0 = Clock::now();
  SparseMatrix K, M;
  assemble_stiffness_mass(body.mesh, body.material, AssemblyOptions{}, &K, &M);
  const std::vector<int> clamp = resolve_nodes(def, key + ".clamp", body, bd.clamp);
  body.constraints = DofMap::from_nodes(body.mesh.num_nodes(), clamp);
  std::vector<int> constrained;
  for (int d = 0; d < body.constraints.num_dofs(); ++d) {
    if (body.constraints.is_constrained(d)) constrained.push_back(d);
  }
  std::vector<int> boundary;
  for (int n : masters) {
    for (int dir = 0; dir < 3; ++dir) {
      if (body.constraints.is_constrained(dof_of(n, dir))) {
        throw InvalidInput(def.where(key + ".clamp"),
                           "node " + std::to_string(body.mesh.node_ids[n]) + " of body " + name +
                               " is both clamped and a master (contact, forced or listed) node");
      }
      boundary.push_back(dof_of(n, dir));
    }
  }
  std::sort(boundary.begin(), boundary.end());
  const int interior = body.constraints.num_free() - static_cast<int>(boundary.size());
  CraigBamptonOptions options;
  options.num_modes = std::min(bd.modes, std::max(0, interior - 1));
  CraigBamptonResult cb = craig_bampton(K, M, constrained, boundary, options);
  if (!cb.summary.ok()) {
    throw InvalidInput(def.where(key), "Craig–Bampton reduction of body " + name +
                                           " failed: " + cb.summary.message);
  }
  assign_node_ids(cb.body, body.mesh.node_ids);
  body.reduced = std::move(cb.body);
  body.T = std::move(cb.T);
  body.K = std::move(K);
  body.M = std::move(M);
  body.seconds_reduction = seconds_since(t0);
}

}  // namespace

int PreparedBody::global_dof(int node_id, int direction) const {
  const auto it = master_dof.find({node_id, direction});
  return it == master_dof.end() ? -1 : it->second;
}

int PreparedModel::body_index(const std::string& name) const {
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

PreparedModel prepare_model(const CaseDefinition& def,
                            const std::function<void(const std::string&)>& progress) {
  const auto t0 = Clock::now();
  const auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  PreparedModel model;

  // Meshes.
  std::map<std::string, Mesh> meshes;
  for (const auto& [name, md] : def.meshes) {
    say("mesh " + name);
    meshes.emplace(name, load_mesh(def, name, md));
  }

  // Bodies (mesh part or matrices), without reduction yet.
  std::map<std::string, int> body_index;
  for (const auto& [name, bd] : def.bodies) {
    PreparedBody body;
    body.name = name;
    const std::string key = "bodies." + name;
    if (bd.source == BodyDefinition::Source::kMesh) {
      body.from_mesh = true;
      const Mesh& mesh = meshes.at(bd.mesh);
      body.mesh = bd.element_set.empty() ? mesh : [&] {
        try {
          return extract_element_set(mesh, bd.element_set).mesh;
        } catch (const InvalidInput& e) {
          throw InvalidInput(def.where(key + ".element_set"), e.message());
        }
      }();
      const MaterialDefinition& m = def.materials.at(bd.material);
      body.material = {m.youngs_modulus, m.poisson_ratio, m.density};
    } else {
      if (bd.reduced.format != "harwell_boeing") {
        throw InvalidInput(
            def.where(key + ".reduced.format"),
            "format " + bd.reduced.format + " is not supported by run yet; use harwell_boeing");
      }
      body.reduced =
          read_ansys_reduced_body(bd.reduced.stiffness, bd.reduced.mass, bd.reduced.mapping);
    }
    if (bd.modal_damping_ratio != 0.0) {
      throw InvalidInput(def.where(key + ".modal_damping_ratio"),
                         "modal damping of fixed-interface modes is not supported by run yet "
                         "(the harmonic balance needs proportional damping C = αM + βK)");
    }
    body_index[name] = static_cast<int>(model.bodies.size());
    model.bodies.push_back(std::move(body));
  }

  // Contacts: node pairs, which also name master nodes.
  std::vector<std::vector<int>> masters(model.bodies.size());
  std::vector<ResolvedContact> contacts;
  for (size_t c = 0; c < def.contacts.size(); ++c) {
    contacts.push_back(resolve_contact(def, static_cast<int>(c), model.bodies, body_index));
    for (const auto& [a, b] : contacts.back().node_pairs) {
      masters[contacts.back().body_a].push_back(a);
      if (contacts.back().body_b >= 0) masters[contacts.back().body_b].push_back(b);
    }
  }
  for (size_t e = 0; e < def.excitation.size(); ++e) {
    const ExcitationDefinition& ed = def.excitation[e];
    const int b = body_index.at(ed.body);
    const auto nodes =
        resolve_nodes(def, fmt::format("excitation[{}]", e), model.bodies[b], ed.nodes);
    masters[b].insert(masters[b].end(), nodes.begin(), nodes.end());
  }
  for (const auto& [name, bd] : def.bodies) {
    const int b = body_index.at(name);
    const auto nodes =
        resolve_nodes(def, "bodies." + name + ".masters", model.bodies[b], bd.masters);
    masters[b].insert(masters[b].end(), nodes.begin(), nodes.end());
  }
  for (size_t i = 0; i < def.output.frf.size(); ++i) {
    const ResponseDofDefinition& r = def.output.frf[i];
    const auto it = body_index.find(r.body);
    if (it == body_index.end()) {
      throw InvalidInput(def.where(fmt::format("output.frf[{}]", i)), "unknown body " + r.body);
    }
    const auto nodes = resolve_nodes(def, fmt::format("output.frf[{}]", i),
                                     model.bodies[it->second], NodeSelection{{}, {r.node}});
    masters[it->second].push_back(nodes[0]);
  }

  // Reduction, then the assembled reduced model.
  for (auto& [name, bd] : def.bodies) {
    const int b = body_index.at(name);
    PreparedBody& body = model.bodies[b];
    std::vector<int>& m = masters[b];
    std::sort(m.begin(), m.end());
    m.erase(std::unique(m.begin(), m.end()), m.end());
    if (body.from_mesh) {
      say(fmt::format("reduce {} ({} nodes, {} masters, {} modes)", name, body.mesh.num_nodes(),
                      m.size(), bd.modes));
      reduce_mesh_body(def, name, bd, m, body);
    }
    body.offset = model.num_dofs;
    for (int j = 0; j < body.reduced.size(); ++j) {
      const ReducedDof& d = body.reduced.dofs[j];
      if (d.kind == ReducedDof::Kind::kPhysical) {
        body.master_dof[{d.node_id, d.direction}] = body.offset + j;
      }
    }
    model.num_dofs += body.reduced.size();
    if (!body.from_mesh) {
      for (int id : m) {
        for (int dir = 0; dir < 3; ++dir) {
          if (body.global_dof(id, dir) < 0) {
            throw InvalidInput(def.where("bodies." + name),
                               fmt::format("node {} direction {} is not a DOF of the reduced "
                                           "matrices of body {}",
                                           id, "xyz"[dir], name));
          }
        }
      }
    }
  }
  model.K = Eigen::MatrixXd::Zero(model.num_dofs, model.num_dofs);
  model.M = Eigen::MatrixXd::Zero(model.num_dofs, model.num_dofs);
  for (const PreparedBody& body : model.bodies) {
    const int n = body.reduced.size();
    model.K.block(body.offset, body.offset, n, n) = body.reduced.K;
    model.M.block(body.offset, body.offset, n, n) = body.reduced.M;
  }
  say(fmt::format("modes of the reduced model ({} DOFs)", model.num_dofs));
  model.linear = linear_model_from_matrices(model.K, model.M, def.damping.alpha, def.damping.beta);

  // Contact elements on the reduced DOFs.
  for (size_t c = 0; c < def.contacts.size(); ++c) {
    const ContactDefinition& cd = def.contacts[c];
    const ResolvedContact& rc = contacts[c];
    const int np = static_cast<int>(rc.node_pairs.size());
    const ContactParametersDefinition p = per_pair_parameters(def, cd, np);
    const std::map<int, double> preload_by_node(cd.preloads.begin(), cd.preloads.end());
    const PreparedBody& A = model.bodies[rc.body_a];
    Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
    Eigen::MatrixXd row_frame;  // m x 3
    if (cd.law == "linear") {
      throw InvalidInput(def.where("contacts." + cd.name + ".law"),
                         "law: linear is not supported by run yet (use friction with a large mu)");
    }
    const bool is3d = cd.law == "friction";
    try {
      if (is3d) {
        frame = vec3(cd.t1).squaredNorm() > 0 ? frame_from_normal(vec3(cd.normal), vec3(cd.t1))
                                              : frame_from_normal(vec3(cd.normal));
        row_frame = frame;
      } else {
        const Eigen::Vector3d d = vec3(cd.direction);
        if (!(d.norm() > 0)) throw InvalidInput("direction must be a non-zero vector");
        row_frame = d.normalized().transpose();
      }
    } catch (const InvalidInput& e) {
      throw InvalidInput(def.where("contacts." + cd.name), e.message());
    }
    for (int i = 0; i < np; ++i) {
      const auto [a, b] = rc.node_pairs[i];
      ContactPair pair;
      PreparedPair info;
      info.contact = static_cast<int>(c);
      info.node_a_id = node_id_of(A, a);
      info.node_b_id = rc.body_b >= 0 ? node_id_of(model.bodies[rc.body_b], b) : 0;
      for (int dir = 0; dir < 3; ++dir) {
        pair.dofs_a.push_back(A.global_dof(info.node_a_id, dir));
        if (rc.body_b >= 0) {
          pair.dofs_b.push_back(model.bodies[rc.body_b].global_dof(info.node_b_id, dir));
        }
      }
      pair.frame = row_frame;
      double preload = p.preload;
      if (!preload_by_node.empty()) {
        const auto it = preload_by_node.find(info.node_a_id);
        if (it == preload_by_node.end()) {
          throw InvalidInput({cd.preload_file, 0, ""},
                             "no preload for node " + std::to_string(info.node_a_id) +
                                 " (the A node of a pair of contact " + cd.name + ")");
        }
        preload = it->second;
      }
      if (cd.law == "friction") {
        pair.element = std::make_shared<FrictionContact3D>(
            FrictionContactParameters{p.kt, p.kn, p.mu, preload, cd.gap});
      } else if (cd.law == "jenkins") {
        pair.element = std::make_shared<Jenkins1D>(JenkinsParameters{p.kt, p.mu, preload});
      } else if (cd.law == "gap") {
        pair.element =
            std::make_shared<UnilateralSpring>(UnilateralSpringParameters{p.kn, cd.gap, preload});
      } else if (cd.law == "cubic") {
        pair.element = std::make_shared<CubicSpring>(CubicSpringParameters{p.k1, p.k3});
      } else {
        throw InvalidInput(def.where("contacts." + cd.name + ".law"), "unknown law " + cd.law);
      }
      model.pairs.push_back(std::move(pair));
      model.pair_info.push_back(info);
      model.pair_frames.push_back(frame);
    }
  }

  // Excitation on the reduced DOFs: f(t) = Re(F e^{ikΩt}) on each selected node.
  for (size_t e = 0; e < def.excitation.size(); ++e) {
    const ExcitationDefinition& ed = def.excitation[e];
    const int b = body_index.at(ed.body);
    const PreparedBody& body = model.bodies[b];
    const auto nodes = resolve_nodes(def, fmt::format("excitation[{}]", e), body, ed.nodes);
    std::array<std::complex<double>, 3> f = ed.force;
    if (ed.by_direction) {
      const Eigen::Vector3d d = vec3(ed.direction).normalized();
      const std::complex<double> amp = std::polar(ed.amplitude, ed.phase_deg * kPi / 180.0);
      for (int i = 0; i < 3; ++i) f[i] = amp * d(i);
    }
    auto [it, inserted] =
        model.excitation.harmonics.try_emplace(ed.harmonic, Eigen::VectorXcd::Zero(model.num_dofs));
    for (int n : nodes) {
      for (int dir = 0; dir < 3; ++dir)
        it->second(body.global_dof(node_id_of(body, n), dir)) += f[dir];
    }
  }

  // The normal preload N0 is carried by the contact at rest: it is the force of an external
  // static load pressing the two nodes of each pair together (a bolt, a centrifugal load, a
  // spring pack). Without that load the bodies would push each other apart and the static
  // solution would relax N0 almost to zero. So every pair whose element force at zero relative
  // displacement f(0) is not zero adds the static load that balances it: −Rᵀf(0) on B, +Rᵀf(0)
  // on A (harmonic 0). Then u = 0 is the static equilibrium and N = N0 there.
  {
    Eigen::VectorXcd preload = Eigen::VectorXcd::Zero(model.num_dofs);
    bool any = false;
    const int samples = 4;
    for (const ContactPair& pair : model.pairs) {
      const int m = pair.element->dimension();
      Eigen::MatrixXd u0 = Eigen::MatrixXd::Zero(m, samples), f0;
      pair.element->march(u0, nullptr, f0, nullptr);
      const Eigen::VectorXd f_rest = f0.col(0);
      if (f_rest.norm() == 0.0) continue;
      any = true;
      const Eigen::Vector3d g = pair.frame.transpose() * f_rest;  // force on B, global axes
      for (int d = 0; d < 3; ++d) {
        if (!pair.dofs_b.empty()) preload(pair.dofs_b[d]) -= g(d);
        if (!pair.dofs_a.empty()) preload(pair.dofs_a[d]) += g(d);
      }
    }
    if (any) {
      auto [it, inserted] =
          model.excitation.harmonics.try_emplace(0, Eigen::VectorXcd::Zero(model.num_dofs));
      it->second += preload;
    }
  }

  // Harmonic balance options.
  const AnalysisDefinition& an = def.analysis;
  model.hbm.harmonic_list = an.harmonics;
  model.hbm.harmonics = an.max_harmonic();
  model.hbm.time_samples = an.time_samples;
  model.hbm.static_coupling =
      an.static_coupling == "coupled" ? StaticCoupling::kCoupled : StaticCoupling::kUncoupled;
  model.seconds_prepare = seconds_since(t0);
  return model;
}

Eigen::VectorXd stuck_frequencies_hz(const PreparedModel& model, const CaseDefinition& def) {
  Eigen::MatrixXd K = model.K;
  std::vector<int> pairs_of_contact(def.contacts.size(), 0);
  for (const PreparedPair& q : model.pair_info) ++pairs_of_contact[q.contact];
  for (size_t i = 0; i < model.pairs.size(); ++i) {
    const ContactPair& pair = model.pairs[i];
    const int c = model.pair_info[i].contact;
    const ContactDefinition& cd = def.contacts[c];
    const ContactParametersDefinition p = per_pair_parameters(def, cd, pairs_of_contact[c]);
    Eigen::VectorXd k_local;
    if (cd.law == "friction") {
      k_local = Eigen::Vector3d(p.kt, p.kt, p.kn);
    } else if (cd.law == "jenkins") {
      k_local = Eigen::VectorXd::Constant(1, p.kt);
    } else if (cd.law == "gap") {
      k_local = Eigen::VectorXd::Constant(1, p.kn);
    } else {
      k_local = Eigen::VectorXd::Constant(1, p.k1);
    }
    const int m = static_cast<int>(pair.frame.rows());
    Eigen::MatrixXd Bp = Eigen::MatrixXd::Zero(m, model.num_dofs);
    for (int d = 0; d < 3; ++d) {
      if (!pair.dofs_a.empty()) Bp.col(pair.dofs_a[d]) += pair.frame.col(d);
      if (!pair.dofs_b.empty()) Bp.col(pair.dofs_b[d]) -= pair.frame.col(d);
    }
    K += Bp.transpose() * k_local.asDiagonal() * Bp;
  }
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, model.M, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) {
    throw InvalidInput(def.where("bodies"), "the reduced mass matrix is not positive definite");
  }
  return eig.eigenvalues().cwiseMax(0.0).cwiseSqrt() / (2 * kPi);
}

std::vector<double> analysis_frequencies_hz(const PreparedModel& model, const CaseDefinition& def) {
  const FrequencyDefinition& f = def.analysis.frequency;
  double start = f.start_hz, stop = f.stop_hz;
  if (f.kind == FrequencyDefinition::Kind::kAroundMode) {
    const Eigen::VectorXd stuck = stuck_frequencies_hz(model, def);
    if (f.around_mode > stuck.size()) {
      throw InvalidInput(def.where("analysis.frequency.around_mode"),
                         fmt::format("the model has only {} modes", stuck.size()));
    }
    const double centre = stuck(f.around_mode - 1);
    start = centre - f.half_width_hz;
    stop = centre + f.half_width_hz;
    if (!(start > 0)) {
      throw InvalidInput(
          def.where("analysis.frequency.half_width_hz"),
          fmt::format("window reaches below 0 Hz (mode {} at {:.6g} Hz)", f.around_mode, centre));
    }
  }
  if (def.analysis.method == "continuation") return {start, stop};
  std::vector<double> grid;
  const int n = static_cast<int>(std::floor((stop - start) / f.step_hz + 1e-9));
  for (int i = 0; i <= n; ++i) grid.push_back(start + i * f.step_hz);
  if (stop - grid.back() > 1e-9 * stop) grid.push_back(stop);
  return grid;
}

SolvedCase solve_case(const PreparedModel& model, const CaseDefinition& def,
                      const std::function<void(const std::string&)>& progress) {
  const auto t0 = Clock::now();
  SolvedCase solved;
  solved.system = std::make_unique<HarmonicBalanceSystem>(model.linear, model.pairs,
                                                          model.excitation, model.hbm);
  if (!solved.system->static_summary().converged() &&
      model.hbm.static_coupling == StaticCoupling::kUncoupled && !model.pairs.empty()) {
    throw InvalidInput(
        def.where("analysis.static"),
        "the static contact problem did not converge: " + solved.system->static_summary().message);
  }
  solved.frequencies_hz = analysis_frequencies_hz(model, def);
  const AnalysisDefinition& an = def.analysis;
  FrequencyResponseOptions o;
  o.initial_guess =
      an.initial_guess == "free" ? InitialGuess::kLinearFree : InitialGuess::kLinearStuck;
  NewtonOptions newton;
  newton.tolerance = an.tolerance;
  newton.max_iterations = an.max_iterations;
  for (const auto& [contact, indices] : def.output.histories) {
    int first = -1, count = 0;
    for (size_t i = 0; i < model.pair_info.size(); ++i) {
      if (def.contacts[model.pair_info[i].contact].name == contact) {
        if (first < 0) first = static_cast<int>(i);
        ++count;
      }
    }
    for (int j : indices) {
      if (j < 0 || j >= count) {
        throw InvalidInput(
            def.where("output.histories." + contact),
            fmt::format("pair {} out of range: contact {} has {} pairs", j, contact, count));
      }
      o.history_pairs.push_back(first + j);
    }
  }
  if (an.method == "continuation") {
    o.method = ContinuationMethod::kArcLength;
    const FrequencyDefinition& f = an.frequency;
    o.arclength.lambda_start = hz_to_rad_s(solved.frequencies_hz.front());
    o.arclength.lambda_end = hz_to_rad_s(solved.frequencies_hz.back());
    const double range = o.arclength.lambda_end - o.arclength.lambda_start;
    o.arclength.initial_step = hz_to_rad_s(f.step_hz);
    o.arclength.min_step = f.min_step_hz > 0 ? hz_to_rad_s(f.min_step_hz) : range * 1e-7;
    o.arclength.max_step = f.max_step_hz > 0 ? hz_to_rad_s(f.max_step_hz)
                                             : std::max(range / 20, o.arclength.initial_step);
    o.arclength.max_points = an.max_points;
    o.arclength.newton = newton;
  } else {
    o.method = ContinuationMethod::kSteppedSweep;
    for (double hz : solved.frequencies_hz) o.omegas.push_back(hz_to_rad_s(hz));
    o.sweep.newton = newton;
  }
  if (progress) {
    progress(fmt::format(
        "harmonic balance: {} pairs, {} unknowns, {} {}", model.pairs.size(), solved.system->size(),
        an.method == "continuation" ? "continuation over" : std::to_string(o.omegas.size()),
        an.method == "continuation" ? "the range" : "points"));
  }
  solved.response = frequency_response(*solved.system, o);
  solved.seconds_solve = seconds_since(t0);
  return solved;
}

}  // namespace stickslip
