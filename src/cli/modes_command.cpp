#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <Eigen/Eigenvalues>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "cli/commands.h"
#include "cli/pipeline.h"
#include "cli/plots.h"
#include "cli/progress.h"
#include "model/campbell.h"
#include "model/cyclic_modes.h"
#include "model/stuck_assembly.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/atomic_file.h"
#include "io/case_file.h"
#include "io/two_beam_model.h"
#include "io/vtu_writer.h"
#include "linalg/modal.h"

namespace stickslip {
namespace {

// The reference case (docs/conventions.md, "The reference case"): steel.
constexpr double kYoungsModulus = 2e11;  // Pa
constexpr double kPoissonRatio = 0.3;
constexpr double kDensity = 7800.0;  // kg/m^3

// Mode j (0-based) of a mesh: point data "mode_<j+1>" (full, 3 per node) and field data
// "mode_<j+1>_frequency_hz".
void add_mode_shape(VtuData& data, int j, const Eigen::VectorXd& full, double f_hz) {
  data.point_data.push_back({fmt::format("mode_{}", j + 1),
                             Eigen::Map<const Eigen::MatrixXd>(full.data(), 3, full.size() / 3)});
  data.field_data.emplace_back(fmt::format("mode_{}_frequency_hz", j + 1), f_hz);
}

// A mode of the stuck reduced assembly is a rigid-body mode when ω² <= kRigidBodyFraction·s,
// s = max_i K(i,i)/M(i,i) (the scale of its Jacobi-scaled stiffness). Its rigid modes are exact
// null vectors of the reduced K (a floating body keeps them as generalised coordinates,
// craig_bampton.h), so their computed ω² is the round-off of the dense eigen-solve, a few eps·s;
// the threshold is far above that and far below any elastic mode (f < 1e-6 √s / 2π).
constexpr double kRigidBodyFraction = 1e-12;

// The frequency table on stdout; `rigid` modes are labelled.
void print_frequencies(const Eigen::VectorXd& f_hz, int rigid = 0) {
  fmt::print("{:>5} {:>14}\n", "mode", "frequency_Hz");
  for (int j = 0; j < f_hz.size(); ++j)
    fmt::print("{:>5} {:>14.3f}{}\n", j + 1, f_hz(j), j < rigid ? "  rigid-body mode" : "");
  if (rigid > 0)
    fmt::print("{} rigid-body mode{} (0 Hz within round-off)\n", rigid, rigid == 1 ? "" : "s");
}

// The modes per nodal diameter of a case's cyclic sector (model/cyclic_modes.h) into
// run.dir/modes/: cyclic_modes.csv (nodal_diameter, mode, frequency_hz) and the nodal-diameter
// diagram nodal_diameters.{png,svg} (with its .dat and .gp). Returns 1 when an eigen-solve failed
// (nothing written for that analysis), kExitPlotsMissing when the diagram could not be drawn.
int write_cyclic_modes(const StageRun& run, const ModesCommand& command, bool quiet,
                       const ProgressFn& progress, ModelCache* cache) {
  namespace fs = std::filesystem;
  const CaseDefinition& def = run.definition;
  const CyclicModes modes = cyclic_modes(def, command.num_modes, progress, cache);
  const std::string prefix = run.folder.empty() ? "" : run.folder + ": ";
  for (const NodalDiameterModes& d : modes.diameters) {
    if (d.summary.ok()) continue;
    std::fprintf(stderr, "stickslip: %smodes of nodal diameter %d failed: %s\n", prefix.c_str(),
                 d.nodal_diameter, d.summary.message.c_str());
    return 1;
  }
  const fs::path dir = run.dir / "modes";
  create_output_folder(dir);
  write_file_atomically((dir / "cyclic_modes.csv").string(), [&](std::ostream& out) {
    out << "nodal_diameter,mode,frequency_hz\n";
    for (const NodalDiameterModes& d : modes.diameters) {
      for (Eigen::Index j = 0; j < d.frequencies_hz.size(); ++j)
        fmt::print(out, "{},{},{}\n", d.nodal_diameter, j + 1, d.frequencies_hz(j));
    }
  });
  int code = 0;
  if (def.output.plots) {
    // One curve per mode number: its frequency at every nodal diameter.
    std::vector<PlotSeries> series;
    for (const NodalDiameterModes& d : modes.diameters) {
      for (Eigen::Index j = 0; j < d.frequencies_hz.size(); ++j) {
        if (static_cast<size_t>(j) >= series.size())
          series.push_back({fmt::format("mode {}", j + 1), {}, {}, "linespoints lw 1.5 pt 7 ps 1"});
        series[static_cast<size_t>(j)].x.push_back(d.nodal_diameter);
        series[static_cast<size_t>(j)].y.push_back(d.frequencies_hz(j));
      }
    }
    PlotLog plots;
    const std::string title = (def.title.empty() ? "" : def.title + ": ") + "body " + modes.body +
                              ", " + std::to_string(modes.sectors) + " sectors";
    if (!plot_curves(dir, "nodal_diameters", title, "nodal diameter", "frequency (Hz)", series,
                     &plots)) {
      std::fprintf(stderr,
                   "stickslip: the nodal-diameter diagram was not drawn; cyclic_modes.csv and "
                   "nodal_diameters.dat are complete (run `stickslip modes` again to draw it)\n");
      code = kExitPlotsMissing;
    }
  }
  if (!quiet) {
    fmt::print("{}cyclic sector {}: {} sectors, {} independent DOFs per sector\n", prefix,
               modes.body, modes.sectors, modes.sector_dofs);
    fmt::print("{:>14} {:>5} {:>14}\n", "nodal_diameter", "mode", "frequency_Hz");
    for (const NodalDiameterModes& d : modes.diameters) {
      for (Eigen::Index j = 0; j < d.frequencies_hz.size(); ++j)
        fmt::print("{:>14} {:>5} {:>14.3f}{}\n", d.nodal_diameter, j + 1, d.frequencies_hz(j),
                   d.doubled ? "  (double)" : "");
    }
    fmt::print("wrote {}\n", (dir / "cyclic_modes.csv").string());
  }
  return code;
}

// The Campbell diagram of a rotating case (model/campbell.h) into run.dir/modes/: campbell.csv
// (speed_rpm, system, nodal_diameter, mode, frequency_hz) and the plot campbell.{png,svg} with the
// engine-order lines f = EO · speed / 60. Returns kExitPlotsMissing when the plot could not be
// drawn, else 0.
int write_campbell(const StageRun& run, const ModesCommand& command, bool quiet,
                   const ProgressFn& progress, ModelCache* cache) {
  namespace fs = std::filesystem;
  const CaseDefinition& def = run.definition;
  const CampbellDiagram d = campbell_diagram(def, command.num_modes, progress, cache);
  const fs::path dir = run.dir / "modes";
  create_output_folder(dir);
  const auto label = [](const CampbellLine& l) {
    return l.nodal_diameter >= 0
               ? fmt::format("{} ND {} mode {}", l.system, l.nodal_diameter, l.mode)
               : fmt::format("{} mode {}", l.system, l.mode);
  };
  write_file_atomically((dir / "campbell.csv").string(), [&](std::ostream& out) {
    out << "speed_rpm,system,nodal_diameter,mode,frequency_hz\n";
    for (const CampbellLine& l : d.lines) {
      for (size_t s = 0; s < d.speeds_rpm.size(); ++s) {
        if (!std::isfinite(l.frequencies_hz[s])) continue;
        fmt::print(out, "{},{},{},{},{}\n", d.speeds_rpm[s], l.system,
                   l.nodal_diameter >= 0 ? std::to_string(l.nodal_diameter) : "", l.mode,
                   l.frequencies_hz[s]);
      }
    }
  });
  int code = 0;
  if (def.output.plots) {
    std::vector<PlotSeries> series;
    for (const CampbellLine& l : d.lines) {
      PlotSeries p{label(l), {}, {},
                   l.system == "stuck" ? "linespoints lw 1.5 pt 7 ps 0.8"
                                       : "linespoints lw 1 dt 2 pt 6 ps 0.8"};
      for (size_t s = 0; s < d.speeds_rpm.size(); ++s) {
        if (!std::isfinite(l.frequencies_hz[s])) continue;
        p.x.push_back(d.speeds_rpm[s]);
        p.y.push_back(l.frequencies_hz[s]);
      }
      series.push_back(std::move(p));
    }
    for (int eo : d.engine_orders) {
      const double a = d.speeds_rpm.front(), b = d.speeds_rpm.back();
      series.push_back({fmt::format("EO {}", eo), {a, b}, {eo * a / 60.0, eo * b / 60.0},
                        "lines lw 1 lc rgb 'gray40' dt 3"});
    }
    PlotLog plots;
    const std::string title = (def.title.empty() ? "" : def.title + ": ") + "Campbell diagram";
    if (!plot_curves(dir, "campbell", title, "speed (rpm)", "frequency (Hz)", series, &plots)) {
      std::fprintf(stderr,
                   "stickslip: the Campbell diagram was not drawn; campbell.csv and campbell.dat "
                   "are complete (run `stickslip modes` again to draw it)\n");
      code = kExitPlotsMissing;
    }
  }
  if (!quiet) {
    fmt::print("{}Campbell diagram, {} speeds from {} to {} rpm, {} lines\n",
               run.folder.empty() ? "" : run.folder + ": ", d.speeds_rpm.size(),
               d.speeds_rpm.front(), d.speeds_rpm.back(), d.lines.size());
    fmt::print("wrote {}\n", (dir / "campbell.csv").string());
  }
  return code;
}

// `stickslip modes CASE`: modes of the case's assembled reduced model with every contact stuck
// (the frequencies `analysis.frequency.around_mode` centres on), and their shapes on the full
// meshes (x = T q) when the Craig–Bampton basis is at hand.
int run_case_modes(const ModesCommand& command) {
  namespace fs = std::filesystem;
  const CaseDefinition base = read_case_file(command.case_file);
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  const fs::path out_dir = stage_output_dir(base, command.output_dir);
  ModelCache cache;  // meshes and reductions shared by the study's analyses
  const bool cyclic = std::any_of(base.bodies.begin(), base.bodies.end(),
                                  [](const auto& b) { return b.second.cyclic.has_value(); });
  int code = 0;
  for (const StageRun& run : stage_runs(base, out_dir)) {
    const CaseDefinition& def = run.definition;
    if (def.rotation && !def.rotation->campbell_speeds_rpm.empty())
      code = std::max(code, write_campbell(run, command, quiet, progress, &cache));
    if (cyclic) {  // the modes per nodal diameter instead of the stuck assembly's
      const int run_code = write_cyclic_modes(run, command, quiet, progress, &cache);
      if (run_code == 1) return 1;
      code = std::max(code, run_code);
      continue;
    }
    const PreparedModel model =
        prepare_stage_model(run, out_dir, command.case_file, /*full_matrices=*/false, progress,
                            /*load_basis_if_present=*/true, &cache);
    Eigen::MatrixXd K_stuck;  // the scale of rigid modes
    const ModalResult eig = stuck_modes(model, def, &K_stuck);
    const int n = std::min<int>(command.num_modes, static_cast<int>(eig.eigenvalues.size()));
    const Eigen::VectorXd f = eig.eigenvalues.head(n).cwiseMax(0.0).cwiseSqrt() / (2 * kPi);
    int rigid = 0;  // rigid-body modes of the whole assembly (ascending: the first ones)
    if (eig.eigenvalues.size() > 0) {
      const double limit =
          kRigidBodyFraction * K_stuck.diagonal().cwiseQuotient(model.M.diagonal()).maxCoeff();
      while (rigid < eig.eigenvalues.size() && eig.eigenvalues(rigid) <= limit) ++rigid;
    }
    const fs::path dir = run.dir / "modes";
    create_output_folder(dir);
    write_file_atomically((dir / "frequencies.csv").string(), [&](std::ostream& out) {
      out << "mode,frequency_hz,kind\n";
      for (int j = 0; j < n; ++j)
        fmt::print(out, "{},{},{}\n", j + 1, f(j), j < rigid ? "rigid" : "elastic");
    });
    std::vector<VtmBlock> shapes;  // modes.vtm: the bodies' mode shapes as one multiblock
    for (const PreparedBody& body : model.bodies) {
      if (!body.from_mesh) continue;
      if (!body.T) {
        progress("mode shapes of " + body.name +
                 " not written: the reused reduced matrices carry no Craig–Bampton basis "
                 "(`stickslip reduce --basis` writes it)");
        continue;
      }
      VtuData data;
      for (int j = 0; j < n; ++j) {
        add_mode_shape(data, j,
                       *body.T * eig.modes.col(j).segment(body.offset, body.reduced.size()),
                       f(j));
      }
      // One folder per body: ParaView would group modes_beam1.vtu and modes_beam2.vtu into one
      // false series (docs/output-files.md, ParaView).
      create_output_folder(dir / body.name);
      write_vtu((dir / body.name / "shapes.vtu").string(), body.mesh, data);
      shapes.push_back({body.name, body.name + "/shapes.vtu"});
    }
    if (!shapes.empty()) write_vtm((dir / "modes.vtm").string(), shapes);
    if (!quiet) {
      fmt::print("{}stuck assembly, {} reduced DOFs, {} contact pairs\n",
                 run.folder.empty() ? "" : run.folder + ": ", model.num_dofs, model.pairs.size());
      print_frequencies(f, std::min(rigid, n));
      fmt::print("wrote {}\n", (dir / "frequencies.csv").string());
    }
  }
  return code;
}

}  // namespace

int run_modes(const ModesCommand& command) {
  if (!command.case_file.empty()) return run_case_modes(command);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  TwoBeamOptions options;
  options.arrangement = command.arrangement == "lap" ? TwoBeamOptions::Arrangement::kLap
                                                     : TwoBeamOptions::Arrangement::kButt;
  options.thesis_coarse = command.thesis_coarse;
  if (!parse_element_type(command.element, &options.element_type)) {
    throw InvalidInput({"", 0, "--element"}, "unknown element type " + command.element);
  }
  const TwoBeamModel model = make_two_beam_model(options);
  const IsotropicMaterial steel{kYoungsModulus, kPoissonRatio, kDensity};
  StuckContact contact{model.contact_pairs, model.contact_normal, command.k_t, command.k_n};
  const StuckAssembly stuck =
      assemble_stuck(model.mesh, steel, AssemblyOptions{}, {contact}, {"CLAMP1", "CLAMP2"});

  ModalOptions modal_options;
  modal_options.num_modes = command.num_modes;
  const ModalResult modes = solve_modes(stuck.K, stuck.M, modal_options);
  if (!modes.summary.ok()) {
    std::fprintf(stderr, "stickslip: modal analysis failed: %s\n", modes.summary.message.c_str());
    return 1;
  }
  const Eigen::VectorXd f = modes.frequencies_hz();

  const std::filesystem::path dir(command.output_dir.empty() ? "." : command.output_dir);
  create_output_folder(dir);
  write_file_atomically((dir / "frequencies.csv").string(), [&](std::ostream& out) {
    out << "mode,frequency_hz\n";
    for (int j = 0; j < f.size(); ++j) fmt::print(out, "{},{}\n", j + 1, f(j));
  });
  VtuData data;
  for (int j = 0; j < f.size(); ++j) {
    add_mode_shape(data, j, stuck.dofs.expand(Eigen::VectorXd(modes.modes.col(j))), f(j));
  }
  write_vtu((dir / "modes.vtu").string(), model.mesh, data);

  if (!command.quiet) {
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    fmt::print(
        "two-beam joint, {} arrangement, stuck contact ({} pairs), {} nodes, {} elements, "
        "{} free DOFs\n",
        command.arrangement, model.contact_pairs.size(), model.mesh.num_nodes(),
        model.mesh.num_elements(), stuck.dofs.num_free());
    print_frequencies(f);
    fmt::print("wrote {} and {} ({:.1f} s)\n", (dir / "frequencies.csv").string(),
               (dir / "modes.vtu").string(), seconds);
  }
  return 0;
}

}  // namespace stickslip
