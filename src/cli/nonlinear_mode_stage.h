// The nonlinear-mode analysis of `run` and `solve` (`analysis.method: nonlinear_mode`,
// docs/case-file.md): solved through the model layer (model/nonlinear_mode_case.h), its files
// written atomically (docs/output-files.md, "Nonlinear modes"): nonlinear_modes.csv (amplitude,
// frequency, damping ratio, ξ per point), nonlinear_mode_shapes.csv (the master-DOF harmonics at
// every point), summary.json (its `nonlinear_mode` entry) and, with plots, the backbone
// (frequency against modal amplitude) and the damping ratio against modal amplitude. The
// frequency-response files of an earlier run in the folder are removed (cli/stale_results.h).
// There is no full-model recovery of a nonlinear mode.
#pragma once

#include <chrono>

#include "cli/commands.h"
#include "cli/plots.h"
#include "cli/progress.h"
#include "model/case_model.h"

namespace stickslip {

// `plots` null: no plots (`solve`); else the case's output.plots decides. t_run: when this
// folder's analysis started (summary.json total_s). Returns the points that failed.
SolveOutcome run_nonlinear_mode_stage(const StageRun& run, const PreparedModel& model,
                                      const ProgressFn& progress, ProgressReporter* reporter,
                                      PlotLog* plots, std::chrono::steady_clock::time_point t_run);

}  // namespace stickslip
