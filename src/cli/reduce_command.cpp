// `stickslip reduce CASE -o DIR` and the plumbing every stage command shares: the analyses of a
// case (study folders), the fingerprints that say whether files of an earlier stage still belong
// to the case, and the reduced model rebuilt from reduce's files.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <set>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/pipeline.h"
#include "cli/progress.h"
#include "cli/results_files.h"
#include "core/errors.h"
#include "fe/assembly.h"
#include "io/ansys_mapping.h"
#include "io/atomic_file.h"
#include "io/case_file.h"
#include "io/fingerprint.h"
#include "model/body_reduction.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;

}  // namespace

std::vector<StageRun> stage_runs(const CaseDefinition& base, const fs::path& out_dir) {
  std::vector<StageRun> runs;
  if (base.study.active()) {
    for (double v : base.study.values) {
      const std::string folder = study_folder_name(base.study.parameter, v);
      runs.push_back({folder,
                      with_parameter(base, base.study.parameter, v, base.where("study.parameter")),
                      out_dir / folder, v});
    }
  } else {
    runs.push_back({"", base, out_dir});
  }
  return runs;
}

fs::path stage_output_dir(const CaseDefinition& base, const std::string& output_dir) {
  const fs::path dir = output_dir.empty() ? fs::path(base.output.directory) : fs::path(output_dir);
  // The case's own files are never replaced by a result (io/atomic_file.h).
  protect_input_file(base.file);
  for (const auto& [name, mesh] : base.meshes) {
    if (mesh.source == MeshDefinition::Source::kFile) protect_input_file(mesh.file);
  }
  for (const auto& [name, body] : base.bodies) {
    if (body.source != BodyDefinition::Source::kReduced) continue;
    for (const std::string& f : {body.reduced.stiffness, body.reduced.mass, body.reduced.mapping}) {
      protect_input_file(f);
    }
  }
  for (const ContactDefinition& c : base.contacts) {
    protect_input_file(c.pairs_file);
    protect_input_file(c.preload_file);
  }
  // An input named like a result in the output folder or one of its folders would be refused when
  // that result is written: refuse now, before any work.
  std::vector<std::string> inputs = {base.file};
  for (const auto& [name, mesh] : base.meshes) inputs.push_back(mesh.file);
  for (const auto& [name, body] : base.bodies) {
    inputs.insert(inputs.end(), {body.reduced.stiffness, body.reduced.mass, body.reduced.mapping});
  }
  for (const ContactDefinition& c : base.contacts) {
    inputs.insert(inputs.end(), {c.pairs_file, c.preload_file});
  }
  static const std::set<std::string> kResults = {
      "points.csv",    "master_response.csv", "contact_forces.csv", "contact_state.csv",
      "histories.csv", "summary.json",        "recovery_check.csv", "recovered_nodes.csv",
      "reactions.csv", "contact_coupling.csv"};
  static const std::set<std::string> kPlots = {"frf", "contact_state", "hysteresis",
                                               "frf_full_vs_reduced", "frf_study"};
  for (const std::string& input : inputs) {
    if (input.empty() || !fs::exists(input)) continue;
    const fs::path p(input);
    const std::string name = p.filename().string(), stem = p.stem().string();
    const std::string ext = p.extension().string();
    const bool result_name =
        kResults.count(name) ||
        (kPlots.count(stem) && (ext == ".png" || ext == ".svg" || ext == ".dat" || ext == ".gp")) ||
        name.rfind("recovery", 0) == 0 || name.rfind("loads_p", 0) == 0;
    std::error_code ec;
    const fs::path parent = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const bool in_output =
        fs::equivalent(parent, dir, ec) ||
        fs::equivalent(parent.parent_path().empty() ? fs::path(".") : parent.parent_path(), dir,
                       ec);
    if (result_name && in_output) {
      throw InvalidInput({input, 0, ""},
                         "this input file has the name of a result that would be written in the "
                         "output folder " +
                             dir.string() +
                             ": results never replace inputs; choose another output folder (-o) "
                             "or rename the file");
    }
  }
  // Before any work: the folder exists and takes files (a read-only or full folder stops the
  // command now, not after the solve), and temporaries that killed runs left there are removed.
  create_output_folder(dir);
  TemporaryFolder probe(dir);
  return dir;
}

std::string stage_hint(const std::string& stage, const CaseDefinition& base,
                       const fs::path& out_dir) {
  return fmt::format("stickslip {} {} -o {}", stage, base.file, out_dir.string());
}

// ---- fingerprints ------------------------------------------------------------------------------

std::string solve_fingerprint(const CaseDefinition& definition) {
  CaseDefinition d = definition;
  d.recovery = RecoveryDefinition{};
  const OutputDefinition defaults;
  d.output.directory = defaults.directory;
  d.output.vtu = defaults.vtu;
  d.output.plots = defaults.plots;
  d.output.log_amplitude = defaults.log_amplitude;
  d.output.apdl_macro = defaults.apdl_macro;
  d.output.calculix_deck = defaults.calculix_deck;
  d.output.quiet = defaults.quiet;
  d.title.clear();
  // One analysis of a study depends on its own value only (already set in `definition`): the
  // study's other values do not enter, so its folder matches the `inputs` of its summary.json.
  d.study = StudyDefinition{};
  // Input files count by their contents, never by their paths: the same case read as
  // `case.yaml`, as `$PWD/case.yaml`, from another working directory or after the project folder
  // was moved has the same fingerprint (the paths are blanked here and the contents hashed below;
  // pairs and preloads are listed by value).
  for (auto& [name, m] : d.meshes) m.file.clear();
  for (auto& [name, b] : d.bodies) {
    b.reduced.stiffness.clear();
    b.reduced.mass.clear();
    b.reduced.mapping.clear();
  }
  for (ContactDefinition& cd : d.contacts) {
    cd.pairs_file.clear();
    cd.preload_file.clear();
  }
  std::string text = describe_case(d);
  for (const ContactDefinition& cd : d.contacts) {
    text += "\npairs " + cd.name;
    for (const auto& p : cd.pairs) text += fmt::format(" {}:{}", p[0], p[1]);
    text += "\npreloads";
    for (const auto& [node, value] : cd.preloads) text += fmt::format(" {}:{:.17g}", node, value);
  }
  for (const auto& [name, m] : definition.meshes) {
    // The mesh file and the files it includes, by contents.
    if (m.source == MeshDefinition::Source::kFile)
      text += "\nmesh " + mesh_fingerprint(definition, name);
  }
  for (const auto& [name, b] : definition.bodies) {
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

// The reduced matrices `stickslip reduce` wrote in `dir` (the body-reduction seam,
// model/body_reduction.h): a mesh body's K_r, M_r and mapping read from <body>_K.hb, _M.hb,
// _K.mapping (their fingerprints were checked against the manifest before), its mesh, material
// and constraints from the case, its full K and M assembled when asked (full_matrices) and its
// basis T read from <body>_T.bin when needed; both shared through the cache with the other
// analyses of a study that use the same reduction. Bodies given by matrices are read as
// CraigBamptonReduction reads them.
class StoredReduction final : public BodyReduction {
 public:
  struct Options {
    bool full_matrices = false;          // assemble the full K and M (recovery)
    bool need_basis = false;             // T required (recovery.method: expansion)
    bool load_basis_if_present = false;  // T whenever reduce wrote it (mode shapes)
  };
  StoredReduction(fs::path dir, std::map<std::string, std::string> fingerprints,
                  std::string reduce_hint, Options options, ModelCache* cache)
      : dir_(std::move(dir)),
        fingerprints_(std::move(fingerprints)),
        reduce_hint_(std::move(reduce_hint)),
        options_(options),
        cache_(cache) {}

  void reduce(const CaseDefinition& def, const CaseBody& resolved, PreparedBody& body,
              const ProgressFn& progress) const override {
    if (!body.from_mesh) {
      CraigBamptonReduction().reduce(def, resolved, body, progress);
      return;
    }
    const std::string k_file = (dir_ / (body.name + "_K.hb")).string();
    const std::string m_file = (dir_ / (body.name + "_M.hb")).string();
    const std::string mapping = (dir_ / (body.name + "_K.mapping")).string();
    body.reduced = read_ansys_reduced_body(k_file, m_file, mapping);
    check_reduced_matrices(def, body.name, body.reduced, k_file, m_file);
    body.constraints = body_constraints(resolved, body.mesh);
    attach_reduced_dofs_to_mesh(body);
    // What an earlier analysis of the study made for the same reduction (same fingerprint: the
    // mesh part, material and reduced DOFs are the same, so are K, M and T).
    ModelCache::Body* shared =
        cache_ != nullptr ? &cache_->body(body.name, fingerprints_.at(body.name)) : nullptr;
    if (options_.full_matrices && shared != nullptr && shared->K) {
      if (progress) {
        progress("full K and M of " + body.name +
                 ": the ones already assembled (same reduction fingerprint)");
      }
      body.K = shared->K;
      body.M = shared->M;
    } else if (options_.full_matrices) {
      SparseMatrix K, M;
      const AssemblyOptions rule{.mass_integration = def.bodies.at(body.name).mass_rule};
      assemble_stiffness_mass(body.mesh, body.material, rule, &K, &M);
      body.K = std::make_shared<const SparseMatrix>(std::move(K));
      body.M = std::make_shared<const SparseMatrix>(std::move(M));
      if (shared != nullptr) {
        shared->K = body.K;
        shared->M = body.M;
      }
    }
    const fs::path t = dir_ / (body.name + "_T.bin");
    if (options_.need_basis || (options_.load_basis_if_present && fs::exists(t))) {
      if (!fs::exists(t)) {
        throw InvalidInput({t.string(), 0, ""},
                           "missing: recovery.method: expansion needs the Craig–Bampton basis; "
                           "run `" +
                               reduce_hint_ + "` again");
      }
      const bool reuse = shared != nullptr && shared->T != nullptr;
      if (reuse && progress) progress("basis T of " + body.name + ": the one already read");
      body.T = reuse ? shared->T : std::make_shared<const Eigen::MatrixXd>(read_dense_matrix(t));
      if (body.T->rows() != body.mesh.num_dofs() || body.T->cols() != body.reduced.size()) {
        throw InvalidInput({t.string(), 0, ""},
                           "the basis does not fit the body: run `" + reduce_hint_ + "` again");
      }
      if (shared != nullptr && !reuse) shared->T = body.T;
    }
  }

 private:
  fs::path dir_;
  std::map<std::string, std::string> fingerprints_;  // body name -> reduction fingerprint
  std::string reduce_hint_;
  Options options_;
  ModelCache* cache_;
};

}  // namespace

PreparedModel prepare_stage_model(const StageRun& run, const fs::path& out_dir,
                                  const std::string& case_file, bool full_matrices,
                                  const ProgressFn& progress, bool load_basis_if_present,
                                  ModelCache* cache) {
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
    return prepare_model(def, progress, cache);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const ReduceManifest manifest = read_reduce_manifest(manifest_path);
  CaseBodies bodies = resolve_case_bodies(def, progress, cache);
  const std::vector<std::string> fingerprints = reduction_fingerprints(def, bodies);

  // Every mesh body's reduced files must be there and made for this body as the case defines it.
  std::map<std::string, std::string> fingerprint_of;
  for (size_t b = 0; b < bodies.bodies.size(); ++b) {
    const CaseBody& body = bodies.bodies[b];
    if (!body.from_mesh) continue;
    const auto it = manifest.body_fingerprint.find(body.name);
    if (it == manifest.body_fingerprint.end()) {
      throw InvalidInput(
          {manifest_path.string(), 0, "body " + body.name},
          "no reduced matrices for body " + body.name + ": run `" + reduce_hint + "` again");
    }
    if (it->second != fingerprints[b]) {
      throw InvalidInput({manifest_path.string(), 0, "body " + body.name},
                         "the reduced matrices of body " + body.name +
                             " are stale (its mesh, element set, material, clamps, master nodes "
                             "or modes changed since they were made): run `" +
                             reduce_hint + "` again");
    }
    for (const char* suffix : {"_K.hb", "_M.hb", "_K.mapping"}) {
      require_stage_file(dir / (body.name + suffix), reduce_hint);
    }
    fingerprint_of[body.name] = fingerprints[b];
  }
  if (progress) progress("reduced matrices from " + dir.string());
  StoredReduction::Options options;
  options.full_matrices = full_matrices;
  options.need_basis = full_matrices && def.recovery.method == RecoveryMethod::kExpansion;
  options.load_basis_if_present = load_basis_if_present;
  const StoredReduction reduction(dir, std::move(fingerprint_of), reduce_hint, options, cache);
  PreparedModel model = prepare_model(def, std::move(bodies), reduction, progress);
  model.seconds_prepare = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return model;
}

int run_reduce(const ReduceCommand& reduce) {
  const StageCommand& command = reduce.stage;
  const CaseDefinition base = read_case_file(command.case_file);
  for (const auto& [name, bd] : base.bodies) {
    if (!bd.cyclic) continue;
    throw InvalidInput(base.where("bodies." + name + ".cyclic"),
                       "body " + name + " is a cyclic sector: `stickslip reduce` does not store "
                       "its reductions per nodal diameter yet; `stickslip run` reduces and solves it");
  }
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  const fs::path out_dir = stage_output_dir(base, command.output_dir);
  const std::vector<StageRun> runs = stage_runs(base, out_dir);
  // One reduction for all study values unless the studied parameter changes a body's reduction
  // (a material): then one per study folder, each body reduced again only when its own
  // fingerprint changed (ModelCache, as `run` does); the meshes are loaded once.
  ModelCache cache;
  std::vector<CaseBodies> resolved;
  std::vector<std::vector<std::string>> fingerprints;
  for (const StageRun& run : runs) {
    resolved.push_back(resolve_case_bodies(run.definition, progress, &cache));
    fingerprints.push_back(reduction_fingerprints(run.definition, resolved.back()));
  }
  const bool shared = std::all_of(fingerprints.begin(), fingerprints.end(),
                                  [&](const auto& f) { return f == fingerprints.front(); });
  for (size_t r = 0; r < runs.size(); ++r) {
    if (shared && r > 0) break;
    const fs::path dir = (shared ? out_dir : runs[r].dir) / "reduced";
    create_output_folder(dir);
    fs::remove(dir / "manifest.txt");  // files being replaced belong to no case until it is back
    const CraigBamptonReduction reduction(&cache, fingerprints[r]);
    const PreparedModel model =
        prepare_model(runs[r].definition, std::move(resolved[r]), reduction, progress);
    ReduceManifest manifest;
    manifest.case_file = base.file;
    for (size_t b = 0; b < model.bodies.size(); ++b) {  // the order of resolved[r].bodies
      const PreparedBody& body = model.bodies[b];
      if (!body.from_mesh) continue;
      const std::string k = (dir / (body.name + "_K.hb")).string();
      const std::string m = (dir / (body.name + "_M.hb")).string();
      write_ansys_reduced_body(k, m, body.reduced);
      // The same matrices as Matrix Market for SciPy's mmread (scipy.io.hb_read refuses the
      // symmetric HB files), with the HB files' mapping (<body>_K.mapping, the same DOFs).
      write_matrix_market_reduced_body((dir / (body.name + "_K.mtx")).string(),
                                       (dir / (body.name + "_M.mtx")).string(),
                                       ansys_mapping_path(k), body.reduced);
      if (reduce.basis || runs[r].definition.recovery.method == RecoveryMethod::kExpansion) {
        write_dense_matrix(dir / (body.name + "_T.bin"), *body.T);
      }
      manifest.body_fingerprint[body.name] = fingerprints[r][b];
      progress(fmt::format("{}: {} reduced DOFs ({} physical) -> {}, {}", body.name,
                           body.reduced.size(), body.reduced.num_physical(), k, m));
    }
    write_reduce_manifest(dir / "manifest.txt", manifest);
  }
  return 0;
}

}  // namespace stickslip
