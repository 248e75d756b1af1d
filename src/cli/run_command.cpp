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
// Under mpirun with several processes the study's values, or one stepped sweep's frequencies,
// are spread over them (cli/distributed_run.h); rank 0 writes the files a run alone writes.
#include <sched.h>
#include <sys/sysinfo.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/distributed_run.h"
#include "cli/interruption.h"
#include "cli/nonlinear_mode_stage.h"
#include "cli/pipeline.h"
#include "cli/plots.h"
#include "cli/processes.h"
#include "cli/progress.h"
#include "cli/recovery_stage.h"
#include "cli/results_files.h"
#include "cli/summary_file.h"
#include "io/case_file.h"
#include "model/petsc_reduction.h"

namespace stickslip {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// One analysis of `run` (the case, or one value of its study): reduction and harmonic balance,
// the solve files, the recovery, the plots and summary.json's timings, added to `tally`.
// `runner` (may be null): solve_case's.
void analyse(const StageRun& run, ModelCache* cache, const ProgressFn& progress,
             ProgressReporter* reporter, const SweepRunner* runner, RunTally& tally) {
  const CaseDefinition& def = run.definition;
  if (!run.folder.empty()) progress("study: " + run.folder);
  const auto t_run = Clock::now();
  const std::string where = run.dir.string();
  interruption_doing("reducing and solving for " + where);
  const PreparedModel model = prepare_model(def, progress, cache);
  if (def.analysis.method == SweepMethod::kNonlinearMode) {  // its own files, no recovery
    tally.outcome += run_nonlinear_mode_stage(run, model, progress, reporter, &tally.plots, t_run,
                                              &tally.mode_overlay);
    return;
  }
  const SolvedCase solved = solve_case(model, def, progress, reporter, runner);
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
    plot_solve_results(run.dir, results, frf, &tally.plots, options);
    plot_full_vs_reduced(run.dir, def.title, frf, full_frf, &tally.plots, options);
    tally.overlay.emplace_back(run.value, frf);
    interruption_done("plots in " + where);
  }
  timings.plots_s = std::chrono::duration<double>(Clock::now() - t_plots).count();
  timings.total_s = std::chrono::duration<double>(Clock::now() - t_run).count();
  interruption_doing("completing summary.json in " + where);
  complete_summary(run.dir, timings);
  interruption_done("summary.json in " + where);
  tally.outcome += report_solved(solved, run.dir, progress);
}

}  // namespace

int run_case(const StageCommand& command) {
  const auto t0 = Clock::now();
  Processes* processes = stickslip::processes();  // null: this process runs alone
  const bool root = processes == nullptr || processes->root();
  if (!root) silence_stderr();  // rank 0 prints (and the errors of every process)
  CaseDefinition base;
  fs::path out_dir;
  std::vector<StageRun> runs;
  std::exception_ptr error;
  try {
    base = read_case_file(command.case_file);
    // Rank 0 makes the output folder; the others only need its name.
    out_dir = root ? stage_output_dir(base, command.output_dir)
                   : fs::path(command.output_dir.empty() ? base.output.directory
                                                         : command.output_dir);
    runs = stage_runs(base, out_dir);
  } catch (...) {
    error = std::current_exception();
  }
  if (processes != nullptr) {
    processes->checkpoint(error);
  } else if (error) {
    std::rethrow_exception(error);
  }
  // A study's other processes print their values' logs for rank 0 to print (quiet as here).
  const bool quiet = command.quiet || base.output.quiet;
  const auto progress = stderr_progress(quiet || !root);
  if (processes != nullptr && root) {
    // A process bound to fewer cores than the machine has runs fewer BLAS and loop threads than
    // a run alone, whose sums then round differently: the same results to round-off, other bits.
    cpu_set_t cpus;
    const int online = get_nprocs();
    if (sched_getaffinity(0, sizeof cpus, &cpus) == 0 && CPU_COUNT(&cpus) < online) {
      progress(fmt::format("{} processes, each bound to {} of the {} cores (mpirun's binding): "
                           "their numbers equal a run alone's to round-off, not to the bit "
                           "(`mpirun --bind-to none` gives the run alone's bits)",
                           processes->size(), CPU_COUNT(&cpus), online));
    }
  }
  RunTally tally;
  ModelCache cache;  // meshes and reductions shared by the study's analyses
  if (processes != nullptr && base.study.active()) {  // the values over the processes
    analyse_study_on_processes(
        *processes, runs, quiet,
        [&](const StageRun& run, const ProgressFn& run_progress, ProgressReporter* reporter,
            RunTally& run_tally) {
          analyse(run, &cache, run_progress, reporter, nullptr, run_tally);
        },
        &tally);
    if (!root) return 0;
  } else if (processes != nullptr && base.analysis.method == SweepMethod::kStepped) {
    // One stepped sweep: its frequencies in segments over the processes.
    bool reached = false;
    const SweepRunner runner = segment_runner(*processes, &reached);
    // Every process prepares the same model at once: a body with reduction_solver: petsc is
    // reduced by all of them together (model/petsc_reduction.h).
    set_petsc_reduction_collective(true);
    ProgressReporter reporter(std::cerr, stderr_progress_options(quiet || !root));
    try {
      analyse(runs.front(), &cache, progress, &reporter, &runner, tally);
    } catch (const SegmentSent&) {
      return 0;  // a rank other than 0: its points are with rank 0
    } catch (...) {
      if (!reached) processes->checkpoint(std::current_exception());
      throw;
    }
  } else {
    if (!root) return 0;  // one curve: rank 0 alone
    if (processes != nullptr) {
      progress(fmt::format("a {} is one curve, computed by process 0 alone: the other {} have "
                           "nothing to do",
                           base.analysis.method == SweepMethod::kContinuation ? "continuation"
                                                                              : "nonlinear mode",
                           processes->size() - 1));
    }
    ProgressReporter reporter(std::cerr, stderr_progress_options(quiet));
    for (const StageRun& run : runs) analyse(run, &cache, progress, &reporter, nullptr, tally);
  }
  if (runs.size() > 1 && base.output.plots && !tally.overlay.empty()) {
    interruption_doing("plotting the study overlay in " + out_dir.string());
    // The study overlay in the order of the studied value, as `stickslip plot` draws it again.
    std::stable_sort(tally.overlay.begin(), tally.overlay.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::vector<PlotSeries>> per_value;
    for (auto& entry : tally.overlay) per_value.push_back(std::move(entry.second));
    plot_study(out_dir, base.title, base.study.parameter, per_value, &tally.plots,
               PlotOptions{base.output.log_amplitude});
  }
  if (runs.size() > 1 && base.output.plots && !tally.mode_overlay.backbone.empty()) {
    interruption_doing("plotting the study overlay in " + out_dir.string());
    plot_nonlinear_mode_study(out_dir, base.title, base.study.parameter,
                              std::move(tally.mode_overlay), &tally.plots);
  }
  const int solved_code = solve_exit_code(
      std::chrono::duration<double>(Clock::now() - t0).count(), tally.outcome, progress);
  const int plots_code = plots_exit_code(tally.plots, out_dir);
  return solved_code != 0 ? solved_code : plots_code;
}

}  // namespace stickslip
