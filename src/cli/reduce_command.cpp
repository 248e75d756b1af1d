// `stickslip reduce CASE -o DIR` and the plumbing every stage command shares: the analyses of a
// case (study folders), the bodies of a case resolved as the pipeline resolves them (meshes,
// clamps, master nodes, contact pairs), the fingerprints that say whether files of an earlier
// stage still belong to the case, and the reduced model rebuilt from reduce's files.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/pipeline.h"
#include "cli/results_files.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "io/ansys_mapping.h"
#include "io/case_file.h"
#include "io/gmsh_mesh.h"
#include "io/inp_reader.h"
#include "io/two_beam_model.h"
#include "mesh/mesh_tools.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

std::string study_folder(const std::string& parameter, double value) {
  std::string name = parameter.substr(parameter.rfind('.') + 1);
  return fmt::format("{}_{:g}", name, value);
}

}  // namespace

std::vector<StageRun> stage_runs(const CaseDefinition& base, const fs::path& out_dir) {
  std::vector<StageRun> runs;
  if (base.study.active()) {
    for (double v : base.study.values) {
      const std::string folder = study_folder(base.study.parameter, v);
      runs.push_back({folder,
                      with_parameter(base, base.study.parameter, v, base.where("study.parameter")),
                      out_dir / folder});
    }
  } else {
    runs.push_back({"", base, out_dir});
  }
  return runs;
}

fs::path stage_output_dir(const CaseDefinition& base, const std::string& output_dir) {
  return output_dir.empty() ? fs::path(base.output.directory) : fs::path(output_dir);
}

std::string stage_hint(const std::string& stage, const CaseDefinition& base,
                       const fs::path& out_dir) {
  return fmt::format("stickslip {} {} -o {}", stage, base.file, out_dir.string());
}

// ---- the bodies of a case, resolved as cli/pipeline.cpp resolves them --------------------------

namespace {

Mesh load_case_mesh(const CaseDefinition& def, const std::string& name, const MeshDefinition& m) {
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
    if (!e.where().file.empty()) throw;
    throw InvalidInput(where, e.message());
  }
}

// Node indices (mesh bodies) or ids (bodies given by matrices) of a selection: sets first, then
// ids, duplicates removed keeping the order.
std::vector<int> select(const CaseDefinition& def, const std::string& key, const CaseBody& body,
                        const NodeSelection& selection) {
  const SourceLocation where = def.where(key);
  if (!body.from_mesh) {
    if (!selection.sets.empty()) {
      throw InvalidInput(where, "body " + body.name +
                                    " is given by reduced matrices: select its nodes by id, "
                                    "not by node set");
    }
    return selection.ids;
  }
  std::vector<int> nodes;
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

int id_of(const CaseBody& body, int node) {
  return body.from_mesh ? body.mesh.node_ids[node] : node;
}

std::string mesh_description(const MeshDefinition& m) {
  if (m.source == MeshDefinition::Source::kGenerate) {
    const TwoBeamDefinition& t = m.two_beam;
    return fmt::format(
        "generate {} arrangement {} element {} coarse {} box {} {} {} end_block {} {} {} "
        "size {:.17g} {:.17g} {:.17g} {:.17g}",
        m.generate, t.arrangement, t.element, t.coarse, t.box[0], t.box[1], t.box[2],
        t.end_block[0], t.end_block[1], t.end_block[2], t.beam_length, t.width, t.thickness,
        t.end_length);
  }
  return fmt::format("file {} format {} hex8 {} hex20 {} bytes {}", m.file, m.format, m.hexahedron8,
                     m.hexahedron20, file_fingerprint_hex(m.file));
}

}  // namespace

CaseBodies resolve_case_bodies(const CaseDefinition& def, const ProgressFn& progress) {
  CaseBodies out;
  std::map<std::string, Mesh> meshes;
  for (const auto& [name, md] : def.meshes) {
    if (progress) progress("mesh " + name);
    meshes.emplace(name, load_case_mesh(def, name, md));
  }
  std::map<std::string, int> index;
  for (const auto& [name, bd] : def.bodies) {
    CaseBody body;
    body.name = name;
    if (bd.source == BodyDefinition::Source::kMesh) {
      body.from_mesh = true;
      const Mesh& mesh = meshes.at(bd.mesh);
      try {
        body.mesh = bd.element_set.empty() ? mesh : extract_element_set(mesh, bd.element_set).mesh;
      } catch (const InvalidInput& e) {
        throw InvalidInput(def.where("bodies." + name + ".element_set"), e.message());
      }
      const MaterialDefinition& m = def.materials.at(bd.material);
      body.material = {m.youngs_modulus, m.poisson_ratio, m.density};
      body.clamp = select(def, "bodies." + name + ".clamp", body, bd.clamp);
    }
    index[name] = static_cast<int>(out.bodies.size());
    out.bodies.push_back(std::move(body));
  }
  const auto find_body = [&](const std::string& name, const std::string& key) {
    if (name == "ground") return -1;
    const auto it = index.find(name);
    if (it == index.end()) throw InvalidInput(def.where(key), "unknown body " + name);
    return it->second;
  };
  std::vector<std::vector<int>> masters(out.bodies.size());
  for (const ContactDefinition& cd : def.contacts) {
    const std::string key = "contacts." + cd.name;
    const int a = find_body(cd.body_a, key), b = find_body(cd.body_b, key);
    if (a < 0) throw InvalidInput(def.where(key), "the first body of a contact cannot be ground");
    const CaseBody& A = out.bodies[a];
    std::vector<std::array<int, 2>> ids;
    if (!cd.pairs.empty() || !cd.pairs_file.empty()) {
      for (const auto& p : cd.pairs) {
        const int na = select(def, key + ".pairs", A, NodeSelection{{}, {p[0]}})[0];
        int nb = -1;
        if (b >= 0) nb = select(def, key + ".pairs", out.bodies[b], NodeSelection{{}, {p[1]}})[0];
        masters[a].push_back(na);
        if (b >= 0) masters[b].push_back(nb);
        ids.push_back({id_of(A, na), b >= 0 ? id_of(out.bodies[b], nb) : 0});
      }
    } else {
      const std::vector<int> nodes_a = select(def, key + ".between", A, cd.nodes_a);
      std::vector<std::pair<int, int>> pairs;
      if (b < 0) {
        for (int n : nodes_a) pairs.emplace_back(n, -1);
      } else {
        const CaseBody& B = out.bodies[b];
        if (!A.from_mesh || !B.from_mesh) {
          throw InvalidInput(def.where(key + ".between"),
                             "pairs between bodies given by matrices must be listed (pairs or "
                             "pairs_file): there are no coordinates to match");
        }
        const std::vector<int> nodes_b = select(def, key + ".between", B, cd.nodes_b);
        try {
          pairs = match_coincident_nodes(A.mesh, nodes_a, B.mesh, nodes_b, cd.tolerance);
        } catch (const InvalidInput& e) {
          throw InvalidInput(def.where(key + ".between"),
                             "contact nodes are not coincident within tolerance " +
                                 fmt::format("{:g}", cd.tolerance) + " m: " + e.message());
        }
        if (pairs.empty()) {
          throw InvalidInput(def.where(key + ".between"), "the contact has no node pairs");
        }
      }
      for (const auto& [na, nb] : pairs) {
        masters[a].push_back(na);
        if (b >= 0) masters[b].push_back(nb);
        ids.push_back({id_of(A, na), b >= 0 ? id_of(out.bodies[b], nb) : 0});
      }
    }
    out.contact_pairs.push_back(std::move(ids));
  }
  for (size_t e = 0; e < def.excitation.size(); ++e) {
    const ExcitationDefinition& ed = def.excitation[e];
    const int b = find_body(ed.body, fmt::format("excitation[{}]", e));
    const auto nodes = select(def, fmt::format("excitation[{}]", e), out.bodies[b], ed.nodes);
    masters[b].insert(masters[b].end(), nodes.begin(), nodes.end());
    std::vector<int> ids;
    for (int n : nodes) ids.push_back(id_of(out.bodies[b], n));
    out.excitation_ids.push_back(std::move(ids));
  }
  for (const auto& [name, bd] : def.bodies) {
    const int b = index.at(name);
    const auto nodes = select(def, "bodies." + name + ".masters", out.bodies[b], bd.masters);
    masters[b].insert(masters[b].end(), nodes.begin(), nodes.end());
  }
  for (size_t i = 0; i < def.output.frf.size(); ++i) {
    const ResponseDofDefinition& r = def.output.frf[i];
    const int b = find_body(r.body, fmt::format("output.frf[{}]", i));
    if (b < 0) throw InvalidInput(def.where(fmt::format("output.frf[{}]", i)), "unknown body");
    const auto nodes =
        select(def, fmt::format("output.frf[{}]", i), out.bodies[b], NodeSelection{{}, {r.node}});
    masters[b].push_back(nodes[0]);
  }
  for (const auto& [name, bd] : def.bodies) {
    CaseBody& body = out.bodies[index.at(name)];
    std::vector<int>& m = masters[index.at(name)];
    std::sort(m.begin(), m.end());
    m.erase(std::unique(m.begin(), m.end()), m.end());
    body.masters = m;
    if (!body.from_mesh) continue;
    std::string text = "stickslip reduce 1\n";
    text += mesh_description(def.meshes.at(bd.mesh)) + "\n";
    text += "element_set " + bd.element_set + "\n";
    text += fmt::format("material {:.17g} {:.17g} {:.17g}\n", body.material.youngs_modulus,
                        body.material.poisson_ratio, body.material.density);
    text += "clamp";
    for (int n : body.clamp) text += fmt::format(" {}", body.mesh.node_ids[n]);
    text += "\nmasters";
    for (int n : m) text += fmt::format(" {}", body.mesh.node_ids[n]);
    text += fmt::format("\nmodes {}\n", bd.modes);
    body.fingerprint = fingerprint_hex(text);
  }
  return out;
}

std::string solve_fingerprint(const CaseDefinition& definition) {
  CaseDefinition d = definition;
  d.recovery = RecoveryDefinition{};
  const OutputDefinition defaults;
  d.output.directory = defaults.directory;
  d.output.vtu = defaults.vtu;
  d.output.plots = defaults.plots;
  d.output.apdl_macro = defaults.apdl_macro;
  d.output.calculix_deck = defaults.calculix_deck;
  d.output.quiet = defaults.quiet;
  d.title.clear();
  std::string text = describe_case(d);
  for (const ContactDefinition& cd : d.contacts) {
    text += "\npairs " + cd.name;
    for (const auto& p : cd.pairs) text += fmt::format(" {}:{}", p[0], p[1]);
    text += "\npreloads";
    for (const auto& [node, value] : cd.preloads) text += fmt::format(" {}:{:.17g}", node, value);
  }
  for (const auto& [name, m] : d.meshes) {
    if (m.source == MeshDefinition::Source::kFile) text += "\nmesh " + file_fingerprint_hex(m.file);
  }
  for (const auto& [name, b] : d.bodies) {
    if (b.source != BodyDefinition::Source::kReduced) continue;
    text += "\nmatrices " + file_fingerprint_hex(b.reduced.stiffness) + " " +
            file_fingerprint_hex(b.reduced.mass);
    if (!b.reduced.mapping.empty() && fs::exists(b.reduced.mapping)) {
      text += " " + file_fingerprint_hex(b.reduced.mapping);
    }
  }
  return fingerprint_hex(text);
}

// ---- the reduced model from reduce's files ------------------------------------------------------

namespace {

fs::path reduced_dir_of(const StageRun& run, const fs::path& out_dir) {
  const fs::path own = run.dir / "reduced";
  if (fs::exists(own / "manifest.txt")) return own;
  return out_dir / "reduced";
}

}  // namespace

PreparedModel prepare_stage_model(const StageRun& run, const fs::path& out_dir,
                                  const std::string& case_file, bool full_matrices,
                                  const ProgressFn& progress, bool load_basis_if_present) {
  const CaseDefinition& def = run.definition;
  const fs::path dir = reduced_dir_of(run, out_dir);
  const fs::path manifest_path = dir / "manifest.txt";
  const std::string reduce_hint =
      fmt::format("stickslip reduce {} -o {}", case_file, out_dir.string());
  bool any_mesh_body = false;
  for (const auto& [name, bd] : def.bodies) {
    any_mesh_body |= bd.source == BodyDefinition::Source::kMesh;
  }
  if (!any_mesh_body || !fs::exists(manifest_path)) {
    if (any_mesh_body && progress) {
      progress("no reduced matrices in " + dir.string() + ": reducing (run `" + reduce_hint +
               "` once to reuse them)");
    }
    return prepare_model(def, progress);
  }
  const ReduceManifest manifest = read_reduce_manifest(manifest_path);
  const CaseBodies bodies = resolve_case_bodies(def, progress);

  // The case with every mesh body given by its reduced matrices, node sets replaced by ids and
  // contact pairs listed: prepare_model then reads the matrices instead of reducing.
  CaseDefinition rewritten = def;
  for (const CaseBody& body : bodies.bodies) {
    if (!body.from_mesh) continue;
    const auto it = manifest.body_fingerprint.find(body.name);
    if (it == manifest.body_fingerprint.end()) {
      throw InvalidInput(
          {manifest_path.string(), 0, "body " + body.name},
          "no reduced matrices for body " + body.name + ": run `" + reduce_hint + "` again");
    }
    if (it->second != body.fingerprint) {
      throw InvalidInput({manifest_path.string(), 0, "body " + body.name},
                         "the reduced matrices of body " + body.name +
                             " are stale (its mesh, element set, material, clamps, master nodes "
                             "or modes changed since they were made): run `" +
                             reduce_hint + "` again");
    }
    BodyDefinition& bd = rewritten.bodies.at(body.name);
    bd.source = BodyDefinition::Source::kReduced;
    bd.reduced.stiffness = (dir / (body.name + "_K.hb")).string();
    bd.reduced.mass = (dir / (body.name + "_M.hb")).string();
    bd.reduced.mapping = (dir / (body.name + "_K.mapping")).string();
    bd.reduced.format = "harwell_boeing";
    for (const std::string& f : {bd.reduced.stiffness, bd.reduced.mass, bd.reduced.mapping}) {
      require_stage_file(f, reduce_hint);
    }
    bd.masters = NodeSelection{{}, {}};
    for (int n : body.masters) bd.masters.ids.push_back(body.mesh.node_ids[n]);
    bd.clamp = NodeSelection{};
  }
  for (size_t c = 0; c < rewritten.contacts.size(); ++c) {
    ContactDefinition& cd = rewritten.contacts[c];
    cd.pairs = bodies.contact_pairs[c];
    cd.pairs_file.clear();
    cd.nodes_a = NodeSelection{};
    cd.nodes_b = NodeSelection{};
  }
  for (size_t e = 0; e < rewritten.excitation.size(); ++e) {
    rewritten.excitation[e].nodes = NodeSelection{{}, bodies.excitation_ids[e]};
  }
  if (progress) progress("reduced matrices from " + dir.string());
  std::map<std::string, const Mesh*> geometry;  // for split: area of the reused bodies
  for (const CaseBody& body : bodies.bodies) {
    if (body.from_mesh) geometry[body.name] = &body.mesh;
  }
  PreparedModel model = prepare_model(rewritten, progress, geometry);

  // Give the reused bodies their full-model side back (recovery, decks, mode shapes).
  for (PreparedBody& body : model.bodies) {
    const auto it = std::find_if(bodies.bodies.begin(), bodies.bodies.end(),
                                 [&](const CaseBody& b) { return b.name == body.name; });
    if (it == bodies.bodies.end() || !it->from_mesh) continue;
    body.from_mesh = true;
    body.mesh = it->mesh;
    body.material = it->material;
    body.constraints = DofMap::from_nodes(body.mesh.num_nodes(), it->clamp);
    const auto by_id = node_index_by_id(body.mesh);
    for (ReducedDof& d : body.reduced.dofs) {
      if (d.kind != ReducedDof::Kind::kPhysical) continue;
      d.node_index = by_id.at(d.node_id);
      d.full_dof = 3 * d.node_index + d.direction;
    }
    const fs::path t = dir / (body.name + "_T.bin");
    const bool need_basis = full_matrices && def.recovery.method == "expansion";
    if (full_matrices) {
      assemble_stiffness_mass(body.mesh, body.material, AssemblyOptions{}, &body.K, &body.M);
    }
    if (need_basis || (load_basis_if_present && fs::exists(t))) {
      if (!fs::exists(t)) {
        throw InvalidInput({t.string(), 0, ""},
                           "missing: recovery.method: expansion needs the Craig–Bampton basis; "
                           "run `" +
                               reduce_hint + "` again");
      }
      body.T = read_dense_matrix(t);
      if (body.T.rows() != body.mesh.num_dofs() || body.T.cols() != body.reduced.size()) {
        throw InvalidInput({t.string(), 0, ""},
                           "the basis does not fit the body: run `" + reduce_hint + "` again");
      }
    }
  }
  return model;
}

int run_reduce(const ReduceCommand& reduce) {
  const StageCommand& command = reduce.stage;
  const CaseDefinition base = read_case_file(command.case_file);
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = [&](const std::string& line) {
    if (!quiet) std::fprintf(stderr, "stickslip: %s\n", line.c_str());
  };
  const fs::path out_dir = stage_output_dir(base, command.output_dir);
  const std::vector<StageRun> runs = stage_runs(base, out_dir);
  // One reduction for all study values unless the studied parameter changes a body's reduction
  // (a material): then one per study folder.
  std::vector<CaseBodies> resolved;
  bool shared = true;
  for (const StageRun& run : runs) {
    resolved.push_back(resolve_case_bodies(run.definition, nullptr));
    for (size_t b = 0; b < resolved.back().bodies.size(); ++b) {
      shared &= resolved.back().bodies[b].fingerprint == resolved.front().bodies[b].fingerprint;
    }
  }
  for (size_t r = 0; r < runs.size(); ++r) {
    if (shared && r > 0) break;
    const fs::path dir = (shared ? out_dir : runs[r].dir) / "reduced";
    fs::create_directories(dir);
    fs::remove(dir / "manifest.txt");  // files being replaced belong to no case until it is back
    const PreparedModel model = prepare_model(runs[r].definition, progress);
    ReduceManifest manifest;
    manifest.case_file = base.file;
    for (const PreparedBody& body : model.bodies) {
      if (!body.from_mesh) continue;
      const std::string k = (dir / (body.name + "_K.hb")).string();
      const std::string m = (dir / (body.name + "_M.hb")).string();
      write_ansys_reduced_body(k, m, body.reduced);
      if (reduce.basis || runs[r].definition.recovery.method == "expansion") {
        write_dense_matrix(dir / (body.name + "_T.bin"), body.T);
      }
      for (const CaseBody& cb : resolved[r].bodies) {
        if (cb.name == body.name) manifest.body_fingerprint[body.name] = cb.fingerprint;
      }
      progress(fmt::format("{}: {} reduced DOFs ({} physical) -> {}, {}", body.name,
                           body.reduced.size(), body.reduced.num_physical(), k, m));
    }
    write_reduce_manifest(dir / "manifest.txt", manifest);
  }
  return 0;
}

}  // namespace stickslip
