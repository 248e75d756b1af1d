#include "cli/recovery_stage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "cli/progress.h"
#include "cli/results_files.h"
#include "core/errors.h"
#include "core/types.h"
#include "fe/stress.h"
#include "io/apdl_macro.h"
#include "io/atomic_file.h"
#include "io/calculix_deck.h"
#include "io/vtu_writer.h"
#include "mesh/mesh.h"
#include "model/body_recovery.h"
#include "recovery/cyclic_recovery.h"
#include "recovery/harmonic_response.h"
#include "recovery/stress_envelope.h"

namespace stickslip {
namespace {

const char* kAxes[3] = {"x", "y", "z"};

struct RecoveredVtu {
  int point;
  std::string body, file;  // file relative to the output folder
};

// The ParaView entry points of the recovered fields (docs/output-files.md): per point a .vtm of
// its bodies, one .pvd of the sweep (time = frequency in Hz when the recovered points' frequencies
// are distinct, as on a stepped sweep; the point number otherwise, e.g. two points of a fold at
// one frequency), and a .vtm of the bodies' envelopes. The per-body files live in
// recovery/<body>/ so that ParaView's grouping of numbered names makes series over points only.
void write_vtk_collections(const std::filesystem::path& dir, const FrequencyResponse& response,
                           const std::vector<int>& points, const std::vector<RecoveredVtu>& files,
                           const std::vector<VtmBlock>& envelope_blocks) {
  if (files.empty()) return;
  std::vector<std::string> bodies;  // in order of first appearance: the part numbers
  for (const RecoveredVtu& f : files) {
    if (std::find(bodies.begin(), bodies.end(), f.body) == bodies.end()) bodies.push_back(f.body);
  }
  std::vector<double> frequencies;
  for (int p : points) frequencies.push_back(rad_s_to_hz(response.points[p].omega));
  std::sort(frequencies.begin(), frequencies.end());
  const bool by_frequency =
      std::adjacent_find(frequencies.begin(), frequencies.end()) == frequencies.end();
  std::vector<PvdEntry> entries;
  for (int p : points) {
    std::vector<VtmBlock> blocks;
    for (const RecoveredVtu& f : files) {
      if (f.point != p) continue;
      blocks.push_back({f.body, f.file});
      const int part =
          static_cast<int>(std::find(bodies.begin(), bodies.end(), f.body) - bodies.begin());
      entries.push_back(
          {by_frequency ? rad_s_to_hz(response.points[p].omega) : p, part, f.body, f.file});
    }
    if (!blocks.empty()) write_vtm((dir / fmt::format("recovery_p{}.vtm", p)).string(), blocks);
  }
  write_pvd((dir / "recovery.pvd").string(), entries);
  if (!envelope_blocks.empty()) {
    write_vtm((dir / "recovery_envelope.vtm").string(), envelope_blocks);
  }
}

// The recovered fields of one point as VTU point data (docs/output-files.md): displacement and,
// when S is not empty, stress per harmonic and the envelope.
VtuData recovered_fields(const std::vector<int>& harmonics, const Eigen::MatrixXcd& x,
                         const std::vector<ComplexStressMatrix>& S, const StressEnvelope& env) {
  VtuData data;
  const Eigen::Index nodes = x.rows() / 3;
  for (size_t h = 0; h < harmonics.size(); ++h) {
    const Eigen::VectorXcd xh = x.col(static_cast<Eigen::Index>(h));
    const Eigen::MatrixXd re =
        Eigen::Map<const Eigen::MatrixXd>(Eigen::VectorXd(xh.real()).data(), 3, nodes);
    const Eigen::MatrixXd im =
        Eigen::Map<const Eigen::MatrixXd>(Eigen::VectorXd(xh.imag()).data(), 3, nodes);
    data.point_data.push_back({fmt::format("displacement_h{}_real", harmonics[h]), re});
    data.point_data.push_back({fmt::format("displacement_h{}_imag", harmonics[h]), im});
  }
  if (S.empty()) return data;
  for (size_t h = 0; h < harmonics.size(); ++h) {
    // VTU tensors are in ParaView order xx, yy, zz, xy, yz, xz; ours xx, yy, zz, xy, xz, yz.
    Eigen::MatrixXd re = S[h].real(), im = S[h].imag();
    re.row(4).swap(re.row(5));
    im.row(4).swap(im.row(5));
    data.point_data.push_back({fmt::format("stress_h{}_real", harmonics[h]), re});
    data.point_data.push_back({fmt::format("stress_h{}_imag", harmonics[h]), im});
  }
  data.point_data.push_back({"von_mises_max", env.von_mises_max.transpose()});
  data.point_data.push_back({"von_mises_alternating", env.von_mises_alternating.transpose()});
  data.point_data.push_back({"von_mises_mean", env.von_mises_mean.transpose()});
  data.point_data.push_back({"max_principal_max", env.max_principal_max.transpose()});
  return data;
}

}  // namespace

std::vector<int> numbered_points(const std::string& spec, const FrequencyResponse& response,
                                 const std::string& points_csv) {
  const auto& points = response.points;
  std::vector<int> out;
  std::stringstream list(spec);
  std::string item;
  while (std::getline(list, item, ',')) {
    char* end = nullptr;
    const long n = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || n < 0 || n >= static_cast<long>(points.size())) {
      throw InvalidInput({"", 0, "--point"},
                         fmt::format("'{}' is not peak, all, or a point (0..{}) or comma-separated "
                                     "points of {}",
                                     spec, points.size() - 1, points_csv));
    }
    if (!points[n].converged) {
      throw InvalidInput({points_csv, 0, "--point"}, fmt::format("point {} did not converge", n));
    }
    if (std::find(out.begin(), out.end(), static_cast<int>(n)) == out.end()) {
      out.push_back(static_cast<int>(n));
    }
  }
  if (out.empty()) throw InvalidInput({"", 0, "--point"}, "no point given");
  return out;
}

std::vector<int> points_from_option(const std::string& spec, const CaseDefinition& def,
                                    const PreparedModel& model, const FrequencyResponse& response,
                                    const std::string& points_csv) {
  if (spec != "peak" && spec != "all") return numbered_points(spec, response, points_csv);
  CaseDefinition d = def;
  d.recovery.points = spec == "peak" ? RecoveryPoints::kPeak : RecoveryPoints::kAll;
  std::vector<int> out = recovery_points(d, model, response);
  if (out.empty()) {
    throw InvalidInput({points_csv, 0, "--point"}, "no point of the sweep converged");
  }
  return out;
}

std::string write_apdl_loads(const std::filesystem::path& dir, const CaseDefinition& def,
                             const std::string& body, const Mesh& mesh, int point, double f_hz,
                             const std::vector<int>& harmonics, const Eigen::MatrixXcd& F) {
  ApdlMacroOptions o;
  o.frequency_hz = f_hz;
  o.harmonics = harmonics;
  o.alpha = def.damping.alpha;
  o.beta = def.damping.beta;
  const std::string path = (dir / fmt::format("loads_p{}_{}.mac", point, body)).string();
  write_apdl_macro(path, mesh, F, o);
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
    const auto clamped = [&](int d) { return body.constraints.is_clamped(dof_of(node, d)); };
    if (clamped(0) && clamped(1) && clamped(2)) {
      o.clamped_nodes.push_back(node);
    } else {
      for (int d = 0; d < 3; ++d) {
        if (clamped(d)) o.clamped_dofs.push_back(dof_of(node, d));
      }
    }
  }
  o.alpha = def.damping.alpha;
  o.beta = def.damping.beta;
  o.frequency_hz = f_hz;
  o.harmonics = harmonics;
  o.num_modes = std::min(def.recovery.modes, body.constraints.num_free() - 1);
  const std::string path = (dir / fmt::format("recovery_p{}_{}.inp", point, body.name)).string();
  // CalculiX has no B-bar brick: the deck's C3D8 (full integration) is stiffer than our C3D8B,
  // most of all as ν → ½ where it locks. Said once per body and run, not only inside the deck.
  static std::set<std::string> warned;
  const auto bbar = std::count(body.mesh.element_types.begin(), body.mesh.element_types.end(),
                               ElementType::kC3D8B);
  if (bbar > 0 && warned.insert(body.name).second) {
    stderr_warning(fmt::format(
        "the CalculiX deck {} writes the {} C3D8B (B-bar, ANSYS SOLID185) elements of body {} as "
        "C3D8: CalculiX has no B-bar element and its full-integration C3D8 is stiffer (it locks "
        "as the Poisson ratio nears 0.5, here {}), so ccx's results will differ from stickslip's",
        path, bbar, body.name, body.material.poisson_ratio));
  }
  if (body.constraints.has_dependents()) {
    // *EQUATION and supports in local frames, as the resolved equations of the body's DofMap.
    Mesh mesh = body.mesh;
    mesh.equations = body.constraints.resolved_equations();
    write_calculix_deck(path, mesh, F, o);
  } else {
    write_calculix_deck(path, body.mesh, F, o);
  }
  return path;
}

void run_recovery(const std::filesystem::path& dir, const CaseDefinition& def,
                  const PreparedModel& model, const FrequencyResponse& response,
                  const std::vector<int>& points,
                  const std::function<void(const std::string&)>& progress,
                  std::vector<PlotSeries>* full_frf, double study_value) {
  if (points.empty()) return;
  const std::vector<int>& harmonics = response.harmonics;
  const int nh = static_cast<int>(harmonics.size());
  const RecoveryMethod method = def.recovery.method;
  const bool want_stress = std::find(def.recovery.fields.begin(), def.recovery.fields.end(),
                                     RecoveryField::kStress) != def.recovery.fields.end();

  struct Row {
    int point, body, harmonic;
    double max_rel, rms_rel, reference_max, max_abs;
  };
  std::vector<Row> check;
  // Every number the shortest decimal that reads back to the same double, units in the column
  // names, and with a study the parameter and value on every row (docs/output-files.md).
  const StudyColumns study = study_columns(def, study_value);
  std::string nodes_csv = "point,body,node,axis,harmonic,real_m,imag_m" + study.header + "\n";
  std::string reactions_csv = "point,body,node,axis,harmonic,real_n,imag_n" + study.header + "\n";
  bool any_reactions = false;

  const int h1 = nh > 1 ? 1 : 0;  // column of the first dynamic harmonic
  std::vector<RecoveredVtu> vtu_files;
  std::vector<VtmBlock> envelope_blocks;
  if (def.output.vtu) {
    // The size of the .vtu files before compression, said before writing more than kLargeOutput:
    // per node and point 8-byte values of the displacement (3 × 2 × harmonics), the stress
    // tensors (6 × 2 × harmonics) and the four envelope scalars.
    constexpr double kLargeOutput = 1e9;  // bytes
    double bytes = 0;
    for (const PreparedBody& body : model.bodies) {
      if (!body.from_mesh) continue;
      double per_node = 8.0 * (3 * 2 * nh + (want_stress ? 6 * 2 * nh + 4 : 0));
      if (def.recovery.annulus && body.cyclic) per_node *= 1 + body.cyclic->sectors;
      bytes += per_node * body.mesh.num_nodes() * static_cast<double>(points.size());
    }
    if (bytes > kLargeOutput) {
      stderr_warning(fmt::format(
          "the recovery of {} points will write about {:.1f} GB of .vtu files in {} (before "
          "zlib compression, which typically halves it); recovery.points: peak or a list of "
          "frequencies writes fewer",
          points.size(), bytes / 1e9, dir.string()));
    }
  }
  for (size_t b = 0; b < model.bodies.size(); ++b) {
    const PreparedBody& body = model.bodies[b];
    if (!body.from_mesh) {
      // No full model: the loads on the mapping's node numbers, for the program the matrices
      // came from (the thesis's route).
      if (!def.output.apdl_macro) continue;
      for (int pi : points) {
        const FrequencyPoint& p = response.points[pi];
        const auto [mesh, F] = mapped_master_loads(model, body, harmonics, p);
        write_apdl_loads(dir, def, body.name, mesh, pi, rad_s_to_hz(p.omega), harmonics, F);
      }
      continue;
    }
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
    progress(fmt::format("recovery of {} ({} DOFs, {})", body.name, body.mesh.num_dofs(),
                         case_name(method)));
    const BodyRecovery recovery(def, model, static_cast<int>(b),
                                {.stresses = want_stress && def.output.vtu});
    const std::vector<int>& held_nodes = recovery.held_nodes();
    // recovery.annulus: the whole annulus of a cyclic sector, one mesh of N sectors.
    std::optional<Mesh> annulus;
    Eigen::MatrixXd annulus_sector;  // 1 x nodes: the sector of each node
    if (def.recovery.annulus && def.output.vtu && model.wave && body.cyclic) {
      annulus = annulus_mesh(body.mesh, *body.cyclic);
      const int n = body.mesh.num_nodes(), N = body.cyclic->sectors;
      annulus_sector.resize(1, static_cast<Eigen::Index>(n) * N);
      for (int j = 0; j < N; ++j)
        annulus_sector.middleCols(static_cast<Eigen::Index>(j) * n, n).setConstant(j);
    }
    any_reactions = any_reactions || !held_nodes.empty();
    const auto t_body = std::chrono::steady_clock::now();
    int done = 0, last_decile = 0;
    for (int pi : points) {
      // A line at every tenth of the points (a long recovery is not silent).
      const int decile = static_cast<int>(10 * done / static_cast<int>(points.size()));
      if (points.size() >= 10 && decile > last_decile) {
        last_decile = decile;
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t_body).count();
        progress(fmt::format("recovery of {}: {}/{} points, {:.1f} s, about {:.0f} s left",
                             body.name, done, points.size(), elapsed,
                             elapsed * (points.size() - done) / done));
      }
      ++done;
      const FrequencyPoint& p = response.points[pi];
      const RecoveredPoint r = recovery.recover(p, harmonics);
      const Eigen::MatrixXcd& F = r.loads;
      const Eigen::MatrixXcd& x = r.displacement;
      const double f_hz = rad_s_to_hz(p.omega);
      if (def.output.apdl_macro) {
        write_apdl_loads(dir, def, body.name, body.mesh, pi, f_hz, harmonics, F);
      }
      if (def.output.calculix_deck) {
        write_calculix_loads(dir, def, body, pi, f_hz, harmonics, F);
      }
      if (!r.summary.ok()) {
        // A singular dynamic stiffness (undamped, exactly at a natural frequency): those
        // harmonics are NaN in every output of this point; the other harmonics are valid.
        stderr_warning(fmt::format("recovery of {} at point {} ({:.6g} Hz): {}", body.name, pi,
                                   f_hz, r.summary.message));
      }
      for (const auto& [dof, series] : frf_dofs) {
        (*full_frf)[series].x.push_back(rad_s_to_hz(p.omega));
        (*full_frf)[series].y.push_back(std::abs(x(dof, h1)));
      }
      for (int h = 0; h < nh; ++h) {
        check.push_back({pi, static_cast<int>(b), harmonics[h], r.check.max_relative[h],
                         r.check.rms_relative[h], r.reduced_max[h], r.check.max_absolute[h]});
      }
      for (int h = 0; h < nh; ++h) {
        for (size_t i = 0; i < held_nodes.size(); ++i) {
          for (int d = 0; d < 3; ++d) {
            const std::complex<double> v = r.reactions(3 * static_cast<Eigen::Index>(i) + d, h);
            reactions_csv += fmt::format("{},{},{},{},{},{},{}{}\n", pi, body.name,
                                         body.mesh.node_ids[held_nodes[i]], kAxes[d],
                                         harmonics[h], v.real(), v.imag(), study.cells);
          }
        }
      }
      // Listed nodes.
      for (int id : def.recovery.nodes) {
        const auto it = std::find(body.mesh.node_ids.begin(), body.mesh.node_ids.end(), id);
        if (it == body.mesh.node_ids.end()) continue;
        const int node = static_cast<int>(it - body.mesh.node_ids.begin());
        for (int d = 0; d < 3; ++d) {
          for (int h = 0; h < nh; ++h) {
            const std::complex<double> v = x(dof_of(node, d), h);
            nodes_csv += fmt::format("{},{},{},{},{},{},{}{}\n", pi, body.name, id, kAxes[d],
                                     harmonics[h], v.real(), v.imag(), study.cells);
          }
        }
      }
      if (!def.output.vtu) continue;
      std::vector<ComplexStressMatrix> S;
      StressEnvelope env;
      if (want_stress) {
        S = recovery.stresses(x, harmonics);
        env = stress_envelope(S, harmonics, StressEnvelopeOptions{});
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
      VtuData data = recovered_fields(harmonics, x, S, env);
      data.field_data.emplace_back("frequency_hz", rad_s_to_hz(p.omega));
      const std::string file = fmt::format("recovery/{}/p{}.vtu", body.name, pi);
      create_output_folder(dir / "recovery" / body.name);
      write_vtu((dir / file).string(), body.mesh, data);
      vtu_files.push_back({pi, body.name, file});
      if (annulus) {  // every sector's fields from sector 0's (recovery/cyclic_recovery.h)
        const CyclicSymmetry& sym = *body.cyclic;
        const int eo = model.wave->engine_order;
        StressEnvelope env_a;
        if (want_stress) {
          const int N = sym.sectors;
          env_a.von_mises_max = env.von_mises_max.replicate(N, 1);
          env_a.von_mises_alternating = env.von_mises_alternating.replicate(N, 1);
          env_a.von_mises_mean = env.von_mises_mean.replicate(N, 1);
          env_a.max_principal_max = env.max_principal_max.replicate(N, 1);
        }
        VtuData a = recovered_fields(harmonics, annulus_vectors(x, harmonics, sym, eo),
                                     want_stress ? annulus_tensors(S, harmonics, sym, eo)
                                                 : std::vector<ComplexStressMatrix>{},
                                     env_a);
        a.point_data.push_back({"sector", annulus_sector});
        a.field_data = data.field_data;
        a.field_data.emplace_back("sectors", static_cast<double>(sym.sectors));
        a.field_data.emplace_back("engine_order", static_cast<double>(eo));
        const std::string name = body.name + "_annulus";
        const std::string afile = fmt::format("recovery/{}/p{}.vtu", name, pi);
        create_output_folder(dir / "recovery" / name);
        write_vtu((dir / afile).string(), *annulus, a);
        vtu_files.push_back({pi, name, afile});
      }
    }
    if (points.size() > 1 && sweep_vm_max.size() > 0) {
      VtuData data;
      data.point_data.push_back({"von_mises_max", sweep_vm_max.transpose()});
      data.point_data.push_back({"von_mises_alternating", sweep_vm_alt.transpose()});
      data.point_data.push_back({"max_principal_max", sweep_p_max.transpose()});
      data.field_data.emplace_back("recovered_points", static_cast<double>(points.size()));
      const std::string file = fmt::format("recovery/{}/envelope.vtu", body.name);
      write_vtu((dir / file).string(), body.mesh, data);
      envelope_blocks.push_back({body.name, file});
      if (annulus) {
        const int N = body.cyclic->sectors;
        VtuData a;
        for (const VtuField& f : data.point_data)
          a.point_data.push_back({f.name, annulus_scalars(f.values, N)});
        a.point_data.push_back({"sector", annulus_sector});
        a.field_data = data.field_data;
        const std::string name = body.name + "_annulus";
        const std::string afile = fmt::format("recovery/{}/envelope.vtu", name);
        write_vtu((dir / afile).string(), *annulus, a);
        envelope_blocks.push_back({name, afile});
      }
    }
  }
  write_vtk_collections(dir, response, points, vtu_files, envelope_blocks);
  write_file_atomically((dir / "recovery_check.csv").string(), [&](std::ostream& out) {
    out << "point,frequency_hz,body,harmonic,reduced_max_m,max_relative,rms_relative,"
           "max_absolute_m"
        << study.header << "\n";
    for (const Row& r : check) {
      fmt::print(out, "{},{},{},{},{},{},{},{}{}\n", r.point,
                 rad_s_to_hz(response.points[r.point].omega), model.bodies[r.body].name, r.harmonic,
                 r.reference_max, r.max_rel, r.rms_rel, r.max_abs, study.cells);
    }
  });
  if (any_reactions) {
    write_file_atomically((dir / "reactions.csv").string(),
                          [&](std::ostream& out) { out << reactions_csv; });
  }
  if (!def.recovery.nodes.empty()) {
    write_file_atomically((dir / "recovered_nodes.csv").string(),
                          [&](std::ostream& out) { out << nodes_csv; });
  }
}

}  // namespace stickslip
