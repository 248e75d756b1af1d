// `stickslip run CASE.yaml`: the whole pipeline, the stages in sequence without reusing files of
// earlier runs: reduction and harmonic balance (cli/pipeline.h), the solve files
// (write_solve_results), the full-model recovery (cli/recovery_stage.h) and the plots, drawn from
// the files just written (as `stickslip plot` draws them). Every file is written atomically.
// Exit status: 1 when frequency points failed, else kExitPlotsMissing when pictures could not be
// drawn (cli/plots.h), else 0.
// With a study, the analyses share their meshes and reductions (ModelCache, cli/pipeline.h): a
// body is reduced again only when the studied parameter changes its reduction fingerprint (a
// material), as `stickslip reduce` decides; the assembled model, contacts, preload loads,
// excitation, frequency window and harmonic balance are built again for every value.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/interruption.h"
#include "cli/nonlinear_mode_stage.h"
#include "cli/pipeline.h"
#include "cli/plots.h"
#include "cli/progress.h"
#include "cli/recovery_stage.h"
#include "cli/results_files.h"
#include "cli/summary_file.h"
#include "io/case_file.h"

namespace stickslip {

int run_case(const StageCommand& command) {
  namespace fs = std::filesystem;
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  const CaseDefinition base = read_case_file(command.case_file);
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet);
  ProgressReporter reporter(std::cerr, stderr_progress_options(quiet));
  const fs::path out_dir = stage_output_dir(base, command.output_dir);
  const std::vector<StageRun> runs = stage_runs(base, out_dir);
  SolveOutcome outcome;
  // The study overlay in the order of the studied value, as `stickslip plot` draws it again.
  std::vector<std::pair<double, std::vector<PlotSeries>>> overlay;
  PlotLog plots;
  ModelCache cache;  // meshes and reductions shared by the study's analyses
  NonlinearModeOverlay mode_overlay;  // a study of nonlinear modes: backbones and damping ratios
  for (const StageRun& run : runs) {
    const CaseDefinition& def = run.definition;
    if (!run.folder.empty()) progress("study: " + run.folder);
    const auto t_run = Clock::now();
    const std::string where = run.dir.string();
    interruption_doing("reducing and solving for " + where);
    const PreparedModel model = prepare_model(def, progress, &cache);
    if (def.analysis.method == SweepMethod::kNonlinearMode) {  // its own files, no recovery
      outcome +=
          run_nonlinear_mode_stage(run, model, progress, &reporter, &plots, t_run, &mode_overlay);
      continue;
    }
    const SolvedCase solved = solve_case(model, def, progress, &reporter);
    interruption_doing("writing the solve files in " + where);
    const auto removed = write_solve_results(
        run, model, solved, std::chrono::duration<double>(Clock::now() - t_run).count());
    if (!removed.empty()) progress(describe_removed(removed));
    warn_peak_at_window_edge(run, model, solved);
    interruption_done("solve files in " + where);
    interruption_doing("recovering in " + where);
    const auto t_recovery = Clock::now();
    std::vector<PlotSeries> full_frf;
    run_recovery(run.dir, def, model, solved.response, recovery_points(def, model, solved.response),
                 progress, &full_frf, run.value);
    interruption_done("recovery files in " + where);
    SummaryTimings timings;
    const auto t_plots = Clock::now();
    timings.recovery_s = std::chrono::duration<double>(t_plots - t_recovery).count();
    if (def.output.plots) {
      interruption_doing("plotting in " + where);
      const SolveResults results = read_solve_results(run.dir, "stickslip run");
      const auto frf = frf_series(results, run.folder.empty() ? "" : run.folder + ": ");
      const PlotOptions options{def.output.log_amplitude};
      plot_solve_results(run.dir, results, frf, &plots, options);
      plot_full_vs_reduced(run.dir, def.title, frf, full_frf, &plots, options);
      overlay.emplace_back(run.value, frf);
      interruption_done("plots in " + where);
    }
    timings.plots_s = std::chrono::duration<double>(Clock::now() - t_plots).count();
    timings.total_s = std::chrono::duration<double>(Clock::now() - t_run).count();
    interruption_doing("completing summary.json in " + where);
    complete_summary(run.dir, timings);
    interruption_done("summary.json in " + where);
    outcome += report_solved(solved, run.dir, progress);
  }
  if (runs.size() > 1 && base.output.plots && !overlay.empty()) {
    interruption_doing("plotting the study overlay in " + out_dir.string());
    std::stable_sort(overlay.begin(), overlay.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::vector<PlotSeries>> per_value;
    for (auto& entry : overlay) per_value.push_back(std::move(entry.second));
    plot_study(out_dir, base.title, base.study.parameter, per_value, &plots,
               PlotOptions{base.output.log_amplitude});
  }
  if (runs.size() > 1 && base.output.plots && !mode_overlay.backbone.empty()) {
    interruption_doing("plotting the study overlay in " + out_dir.string());
    plot_nonlinear_mode_study(out_dir, base.title, base.study.parameter, std::move(mode_overlay),
                              &plots);
  }
  const int solved_code = solve_exit_code(
      std::chrono::duration<double>(Clock::now() - t0).count(), outcome, progress);
  const int plots_code = plots_exit_code(plots, out_dir);
  return solved_code != 0 ? solved_code : plots_code;
}

}  // namespace stickslip
