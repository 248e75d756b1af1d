// `stickslip export CASE -o DIR --point N|N,M,...|peak|all --format apdl|calculix`: the loads of
// solved points
// (excitation, static preload loads and contact forces, from the solve files) on each full body,
// as an ANSYS APDL macro (loads_p<N>_<body>.mac) or a CalculiX deck (recovery_p<N>_<body>.inp),
// the files run writes with output.apdl_macro / output.calculix_deck. A body given by matrices
// gets the APDL macro of its master loads on its mapping's node numbers (the thesis's route).
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/progress.h"
#include "cli/recovery_stage.h"
#include "cli/results_files.h"
#include "core/errors.h"
#include "core/types.h"
#include "io/case_file.h"

namespace stickslip {

int run_export(const ExportCommand& command) {
  namespace fs = std::filesystem;
  if (command.format != "apdl" && command.format != "calculix") {
    throw InvalidInput({"", 0, "--format"}, "'" + command.format + "' is not apdl or calculix");
  }
  const CaseDefinition base = read_case_file(command.stage.case_file);
  const bool quiet = command.stage.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  const fs::path out_dir = stage_output_dir(base, command.stage.output_dir);
  ModelCache cache;  // meshes and reductions shared by the study's analyses
  for (const StageRun& run : stage_runs(base, out_dir)) {
    const CaseDefinition& def = run.definition;
    SolveResults results = read_stage_solve(run, base, out_dir);
    const std::string points_csv = (run.dir / "points.csv").string();
    const bool numbered = command.points != "peak" && command.points != "all";
    std::vector<int> points;  // point numbers are checked before the model preparation
    if (numbered) points = numbered_points(command.points, results.response, points_csv);
    const PreparedModel model =
        prepare_stage_model(run, out_dir, command.stage.case_file, /*full_matrices=*/false,
                            progress, /*load_basis_if_present=*/false, &cache);
    for (const PreparedBody& body : model.bodies) {
      if (!model.wave || !body.cyclic) continue;
      throw InvalidInput(def.where("bodies." + body.name + ".cyclic"),
                         "body " + body.name +
                             " is a cyclic sector: its loads alone, without the cyclic "
                             "constraint of each harmonic's nodal diameter, would not reproduce "
                             "its response in another program (`stickslip recover` recovers it)");
    }
    const std::string hint = stage_hint("solve", base, out_dir);
    check_solve_matches_model(results, model, def, run, hint);
    if (!numbered) {
      // The peak is measured on the master response, rebuilt from the contact forces.
      if (command.points == "peak") rebuild_master_response(results, model, run, hint);
      points = points_from_option(command.points, def, model, results.response, points_csv);
    }
    const std::vector<int>& harmonics = results.response.harmonics;
    int written = 0;
    for (const int point : points) {
      const FrequencyPoint& p = results.response.points[point];
      const double f_hz = rad_s_to_hz(p.omega);
      // Each study folder has its own sweep: say which point of it (its own peak) is exported.
      progress(fmt::format("{}{} {} at {:.6g} Hz", run.folder.empty() ? "" : run.folder + ": ",
                           command.points == "peak" ? "peak: point" : "point", point, f_hz));
      for (const PreparedBody& body : model.bodies) {
        std::string path;
        if (body.from_mesh) {
          const Eigen::MatrixXcd F = recovery_loads(model, body, harmonics, p);
          path = command.format == "apdl"
                     ? write_apdl_loads(run.dir, def, body.name, body.mesh, point, f_hz,
                                        harmonics, F)
                     : write_calculix_loads(run.dir, def, body, point, f_hz, harmonics, F);
        } else if (command.format == "apdl") {
          // A body given by matrices: its master loads on the mapping's node numbers.
          const auto [mesh, F] = mapped_master_loads(model, body, harmonics, p);
          path = write_apdl_loads(run.dir, def, body.name, mesh, point, f_hz, harmonics, F);
        } else {
          continue;  // a CalculiX deck needs the body's mesh
        }
        progress("wrote " + path);
        ++written;
      }
    }
    if (written == 0) {
      throw InvalidInput(def.where("bodies"),
                         "no body is given by a mesh: a CalculiX deck needs the full model "
                         "(`--format apdl` writes the loads of bodies given by matrices on their "
                         "mapping's node numbers)");
    }
  }
  return 0;
}

}  // namespace stickslip
