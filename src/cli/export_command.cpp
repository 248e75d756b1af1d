// `stickslip export CASE -o DIR --point N --format apdl|calculix`: the loads of one solved point
// (excitation, static preload loads and contact forces, from the solve files) on each full body,
// as an ANSYS APDL macro (loads_p<N>_<body>.mac) or a CalculiX deck (recovery_p<N>_<body>.inp),
// the files run writes with output.apdl_macro / output.calculix_deck.
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
    const SolveResults results = read_stage_solve(run, base, out_dir);
    const auto& points = results.response.points;
    if (command.point < 0 || command.point >= static_cast<int>(points.size())) {
      throw InvalidInput({"", 0, "--point"},
                         fmt::format("point {} is not in {} (0..{})", command.point,
                                     (run.dir / "points.csv").string(), points.size() - 1));
    }
    const FrequencyPoint& p = points[command.point];
    if (!p.converged) {
      throw InvalidInput({(run.dir / "points.csv").string(), 0, "--point"},
                         fmt::format("point {} did not converge", command.point));
    }
    const PreparedModel model =
        prepare_stage_model(run, out_dir, command.stage.case_file, /*full_matrices=*/false,
                            progress, /*load_basis_if_present=*/false, &cache);
    check_solve_matches_model(results, model, def, run, stage_hint("solve", base, out_dir));
    const std::vector<int>& harmonics = results.response.harmonics;
    int written = 0;
    for (const PreparedBody& body : model.bodies) {
      if (!body.from_mesh) continue;
      const Eigen::MatrixXcd F = recovery_loads(model, body, harmonics, p);
      const double f_hz = rad_s_to_hz(p.omega);
      const std::string path =
          command.format == "apdl"
              ? write_apdl_loads(run.dir, def, body, command.point, f_hz, harmonics, F)
              : write_calculix_loads(run.dir, def, body, command.point, f_hz, harmonics, F);
      progress("wrote " + path);
      ++written;
    }
    if (written == 0) {
      throw InvalidInput(def.where("bodies"),
                         "no body is given by a mesh: there is no full model to load");
    }
  }
  return 0;
}

}  // namespace stickslip
